//===- PointCloud.h - pointcloud_search, _get and _write: the ABI -*- C++
//-*-===//
//
// The three point-cloud functions are one op, osl.pointcloud, and one entry
// point, osl_rt_pointcloud (EntryPoints.h). Its operands are rows as
// osl.string_call's (OslAbi/Strings.h): first the inputs, then the current
// elements of the output arrays, then two rows the runtime writes: the
// function's result (search: the count found; get and write: 1 or 0) and how
// many leading elements of each output array it wrote.
//
// Inputs, by function:
//   search  filename (s), center (t), radius (f), max points (i), sort (i)
//   get     filename (s), count (i), attribute name (s), the indices (i each)
//   write   filename (s), position (t), then each attribute's value
//
// The `layout` attribute names the arrays: "name:kind:length" joined by ';'
// (kind one of i f t s). For search and get they are the output arrays (get
// has one, its name empty: the name is an input row); for write, the
// attributes written, each of length 1.
//
//===----------------------------------------------------------------------===//
#ifndef OSLABI_POINTCLOUD_H
#define OSLABI_POINTCLOUD_H

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace osl {

enum class PointCloudFunction : int32_t { Search = 0, Get = 1, Write = 2 };

inline std::optional<PointCloudFunction> pointCloudFunction(std::string_view name) {
  if (name == "search")
    return PointCloudFunction::Search;
  if (name == "get")
    return PointCloudFunction::Get;
  if (name == "write")
    return PointCloudFunction::Write;
  return std::nullopt;
}

/// The input kinds of `function` before its per-array inputs (get's
/// indices, write's values).
inline const char *pointCloudInputKinds(PointCloudFunction function) {
  switch (function) {
  case PointCloudFunction::Search:
    return "stfii";
  case PointCloudFunction::Get:
    return "sis";
  case PointCloudFunction::Write:
    return "st";
  }
  return "";
}

/// One array of a layout.
struct PointCloudArray {
  std::string name;
  char kind = 'f';
  int32_t length = 0;
};

/// The arrays `layout` names, or nullopt if it is malformed.
inline std::optional<std::vector<PointCloudArray>> parsePointCloudLayout(std::string_view layout) {
  std::vector<PointCloudArray> arrays;
  while (!layout.empty()) {
    size_t end = layout.find(';');
    std::string_view item = layout.substr(0, end);
    layout = end == std::string_view::npos ? std::string_view() : layout.substr(end + 1);
    size_t colon = item.rfind(':');
    if (colon == std::string_view::npos || colon < 2 || item[colon - 2] != ':')
      return std::nullopt;
    PointCloudArray a;
    a.name = std::string(item.substr(0, colon - 2));
    a.kind = item[colon - 1];
    if (std::string_view("ifts").find(a.kind) == std::string_view::npos)
      return std::nullopt;
    std::string_view digits = item.substr(colon + 1);
    if (digits.empty() || digits.size() > 9)
      return std::nullopt;
    for (char c : digits) {
      if (c < '0' || c > '9')
        return std::nullopt;
      a.length = a.length * 10 + (c - '0');
    }
    if (a.length <= 0)
      return std::nullopt;
    arrays.push_back(std::move(a));
  }
  return arrays;
}

/// The layout text of `arrays` (parsePointCloudLayout's inverse).
inline std::string pointCloudLayout(const std::vector<PointCloudArray> &arrays) {
  std::string text;
  for (const PointCloudArray &a : arrays) {
    if (!text.empty())
      text += ';';
    text += a.name + ":" + a.kind + ":" + std::to_string(a.length);
  }
  return text;
}

} // namespace osl

#endif // OSLABI_POINTCLOUD_H
