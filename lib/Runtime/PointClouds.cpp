//===- PointClouds.cpp - pointcloud_search, _get and _write --------------===//
//
// Clouds are read on first use and kept for the process (a file that cannot
// be read is remembered too, and reported at each lookup, as OSL's renderer
// reports it). Written points are kept per file with the point that wrote
// them, and saved in point order when the run ends (savePointClouds).
//
// Search answers are always nearest first, equal distances by index: OSL
// leaves the order of an unsorted search to the renderer, and one order for
// both keeps every width and thread count bit-identical.
//
//===----------------------------------------------------------------------===//
#include "OslAbi/EntryPoints.h"
#include "OslAbi/PointCloud.h"
#include "OslAbi/Words.h"
#include "OslRuntime/PointCloud.h"
#include "OslRuntime/PrintCall.h"
#include "OslRuntime/StringCall.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <map>
#include <memory>
#include <mutex>
#include <unordered_map>

namespace osl {
namespace {

struct LoadedCloud {
  std::string error; // why the file could not be read, or empty
  PointCloudData data;
  std::vector<float> positions;
  std::unique_ptr<PointKdTree> tree;
};

std::atomic<int> fileErrors{0};

const LoadedCloud &loadCloud(const std::string &path) {
  static std::mutex mutex;
  static std::map<std::string, std::unique_ptr<LoadedCloud>> clouds;
  std::lock_guard<std::mutex> lock(mutex);
  std::unique_ptr<LoadedCloud> &cloud = clouds[path];
  if (!cloud) {
    cloud = std::make_unique<LoadedCloud>();
    if (!readGeoFile(path, cloud->data, cloud->error)) {
      ++fileErrors;
    } else {
      const std::vector<int32_t> &bits = cloud->data.attributes[0].words;
      cloud->positions.resize(bits.size());
      std::memcpy(cloud->positions.data(), bits.data(), bits.size() * sizeof(float));
      cloud->tree = std::make_unique<PointKdTree>(cloud->positions);
    }
  }
  return *cloud;
}

/// loadCloud, remembered per thread: every lane of a lookup asks, and
/// clouds live as long as the process.
const LoadedCloud &cloudNamed(const std::string &path) {
  thread_local std::unordered_map<std::string, const LoadedCloud *> known;
  const LoadedCloud *&cloud = known[path];
  if (!cloud)
    cloud = &loadCloud(path);
  return *cloud;
}

/// One pointcloud_write: the point that made it, its call's place among
/// the batch's, and its values (position first).
struct WrittenPoint {
  long point;
  int32_t call;
  std::vector<std::pair<size_t, std::vector<int32_t>>> values; // attribute, words
  std::vector<std::pair<size_t, std::string>> strings;
};

struct WrittenCloud {
  std::vector<std::pair<std::string, char>> attributes; // name, kind
  std::vector<WrittenPoint> points;
};

std::mutex writtenMutex;
std::map<std::string, WrittenCloud> &writtenClouds() {
  static std::map<std::string, WrittenCloud> clouds;
  return clouds;
}

thread_local long batchFirstPoint = 0;
thread_local int32_t batchCalls = 0;

void report(int32_t lane, const std::string &text) {
  keepLaneText(printStreamCode("renderer_error"), lane, "", text);
}

int32_t rowsOf(char kind) { return kind == 't' ? 3 : 1; }

/// The rows of one call, operand by operand.
class CallRows {
public:
  CallRows(int32_t *rows, int32_t width, const char *kinds) : rows(rows), width(width) {
    int32_t row = 0;
    for (const char *k = kinds; *k; ++k) {
      first.push_back(row);
      row += rowsOf(*k);
    }
    extra = row;
  }
  int32_t &word(size_t operand, int32_t component, int32_t lane) {
    return rows[size_t(first[operand] + component) * width + lane];
  }
  float number(size_t operand, int32_t lane) { return floatOfWord(word(operand, 0, lane)); }
  int32_t &status(int32_t lane) { return rows[size_t(extra) * width + lane]; }
  int32_t &written(int32_t lane) { return rows[size_t(extra + 1) * width + lane]; }

private:
  int32_t *rows;
  int32_t width;
  std::vector<int32_t> first;
  int32_t extra = 0;
};

/// The cloud `file` names for `function`'s lookups, or null after
/// reporting why there is none.
const LoadedCloud *openCloud(const std::string &file, const char *function, int32_t lane) {
  const LoadedCloud *cloud = file.empty() ? nullptr : &cloudNamed(file);
  if (!cloud || !cloud->error.empty()) {
    std::string why = cloud && cloud->error.rfind("cannot read", 0) != 0 ? ": " + cloud->error : "";
    report(lane, std::string(function) + ": could not open \"" + file + "\"" + why);
    return nullptr;
  }
  return cloud;
}

/// Copies attribute `name` of the points `indices` (count of them) into the
/// array whose first element is operand `operand`. False after reporting.
bool fetch(const LoadedCloud &cloud, const std::string &file, const std::string &name,
           const PointCloudArray &array, const int32_t *indices, int32_t count, CallRows &rows,
           size_t operand, int32_t lane) {
  const PointAttribute *attr = cloud.data.find(name);
  if (!attr) {
    report(lane, "Accessing unexisting attribute " + name + " in pointcloud \"" + file + "\"");
    return false;
  }
  if (attr->oslKind() != array.kind) {
    const char *osl = array.kind == 'i'   ? "int"
                      : array.kind == 'f' ? "float"
                      : array.kind == 's' ? "string"
                                          : "triple";
    report(lane, "Type of attribute \"" + name + "\" : " +
                     (attr->type == 's'   ? std::string("string")
                      : attr->type == 'i' ? std::string("int")
                                          : "float[" + std::to_string(attr->components) + "]") +
                     " not compatible with OSL's " + osl + " in \"" + file + "\" pointcloud");
    return false;
  }
  size_t npoints = cloud.data.size();
  for (int32_t k = 0; k < count; ++k)
    if (indices[k] < 0 || size_t(indices[k]) >= npoints) {
      report(lane, "pointcloud_get: index " + std::to_string(indices[k]) + " is not a point of \"" +
                       file + "\" (" + std::to_string(npoints) + " points)");
      return false;
    }
  for (int32_t k = 0; k < count; ++k) {
    size_t p = size_t(indices[k]);
    for (int32_t c = 0; c < attr->components; ++c) {
      int32_t w = attr->words[p * attr->components + c];
      if (attr->type == 's')
        w = osl_rt_string_intern(
            w >= 0 && size_t(w) < attr->strings.size() ? attr->strings[size_t(w)].c_str() : "");
      rows.word(operand + k, c, lane) = w;
    }
  }
  return true;
}

void search(const std::vector<PointCloudArray> &arrays, CallRows &rows, int32_t lane) {
  rows.status(lane) = rows.written(lane) = 0;
  std::string file = stringText(rows.word(0, 0, lane));
  if (file.empty())
    return;
  const LoadedCloud *cloud = openCloud(file, "pointcloud_search", lane);
  if (!cloud)
    return;
  float center[3] = {floatOfWord(rows.word(1, 0, lane)), floatOfWord(rows.word(1, 1, lane)),
                     floatOfWord(rows.word(1, 2, lane))};
  int32_t maxPoints = rows.word(3, 0, lane);
  for (const PointCloudArray &a : arrays)
    maxPoints = std::min(maxPoints, a.length);
  std::vector<int32_t> indices;
  std::vector<float> distance2;
  int32_t count = cloud->tree->nearest(center, rows.number(2, lane), maxPoints, indices, distance2);
  size_t operand = 5;
  for (const PointCloudArray &a : arrays) {
    if (a.name == "index" && a.kind == 'i') {
      for (int32_t k = 0; k < count; ++k)
        rows.word(operand + k, 0, lane) = indices[k];
    } else if (a.name == "distance" && a.kind == 'f') {
      for (int32_t k = 0; k < count; ++k)
        rows.word(operand + k, 0, lane) = wordOfFloat(std::sqrt(distance2[k]));
    } else {
      fetch(*cloud, file, a.name, a, indices.data(), count, rows, operand, lane);
    }
    operand += a.length;
  }
  rows.status(lane) = rows.written(lane) = count;
}

void get(const PointCloudArray &array, size_t nindices, CallRows &rows, int32_t lane) {
  rows.written(lane) = 0;
  rows.status(lane) = 1; // asking for nothing always succeeds
  int32_t count =
      std::min<int32_t>(rows.word(1, 0, lane), std::min<int32_t>(array.length, int32_t(nindices)));
  if (count <= 0)
    return;
  rows.status(lane) = 0;
  std::string file = stringText(rows.word(0, 0, lane));
  const LoadedCloud *cloud = openCloud(file, "pointcloud_get", lane);
  if (!cloud)
    return;
  std::vector<int32_t> indices(static_cast<size_t>(count));
  for (int32_t k = 0; k < count; ++k)
    indices[k] = rows.word(3 + k, 0, lane);
  if (fetch(*cloud, file, stringText(rows.word(2, 0, lane)), array, indices.data(), count, rows,
            3 + nindices, lane)) {
    rows.status(lane) = 1;
    rows.written(lane) = count;
  }
}

void write(const std::vector<PointCloudArray> &arrays, const char *kinds, CallRows &rows,
           int32_t lane, int32_t call) {
  rows.written(lane) = 0;
  rows.status(lane) = 0;
  std::string file = stringText(rows.word(0, 0, lane));
  if (file.empty())
    return;
  std::lock_guard<std::mutex> lock(writtenMutex);
  WrittenCloud &cloud = writtenClouds()[file];
  WrittenPoint point{batchFirstPoint + lane, call, {}, {}};
  std::vector<int32_t> position = {rows.word(1, 0, lane), rows.word(1, 1, lane),
                                   rows.word(1, 2, lane)};
  point.values.emplace_back(0, std::move(position));
  for (size_t a = 0; a < arrays.size(); ++a) {
    char kind = kinds[2 + a];
    auto known = std::find_if(cloud.attributes.begin(), cloud.attributes.end(),
                              [&](const auto &n) { return n.first == arrays[a].name; });
    if (known == cloud.attributes.end()) {
      cloud.attributes.emplace_back(arrays[a].name, kind);
      known = cloud.attributes.end() - 1;
    }
    if (known->second != kind) // first written with another type: skipped, as OSL does
      continue;
    size_t index = size_t(known - cloud.attributes.begin()) + 1;
    if (kind == 's') {
      point.strings.emplace_back(index, stringText(rows.word(2 + a, 0, lane)));
      continue;
    }
    std::vector<int32_t> words;
    for (int32_t c = 0; c < rowsOf(kind); ++c)
      words.push_back(rows.word(2 + a, c, lane));
    point.values.emplace_back(index, std::move(words));
  }
  cloud.points.push_back(std::move(point));
  rows.status(lane) = 1;
}

/// The cloud `written` makes, its points in point order.
PointCloudData cloudOf(WrittenCloud &written) {
  std::stable_sort(written.points.begin(), written.points.end(),
                   [](const WrittenPoint &a, const WrittenPoint &b) {
                     return a.point < b.point || (a.point == b.point && a.call < b.call);
                   });
  PointCloudData data;
  PointAttribute position;
  position.name = "position";
  position.components = 3;
  position.isVector = true;
  data.attributes.push_back(position);
  for (const auto &[name, kind] : written.attributes) {
    PointAttribute attr;
    attr.name = name;
    attr.type = kind == 't' ? 'f' : kind;
    attr.components = rowsOf(kind);
    attr.isVector = kind == 't';
    data.attributes.push_back(attr);
  }
  for (const WrittenPoint &p : written.points) {
    for (PointAttribute &attr : data.attributes)
      attr.words.resize(attr.words.size() + attr.components, 0);
    for (const auto &[index, words] : p.values) {
      PointAttribute &attr = data.attributes[index];
      std::copy(words.begin(), words.end(), attr.words.end() - attr.components);
    }
    for (const auto &[index, text] : p.strings) {
      PointAttribute &attr = data.attributes[index];
      auto known = std::find(attr.strings.begin(), attr.strings.end(), text);
      if (known == attr.strings.end())
        known = attr.strings.insert(attr.strings.end(), text);
      attr.words.back() = int32_t(known - attr.strings.begin());
    }
  }
  return data;
}

} // namespace

void setPointCloudBatch(long firstPoint) {
  batchFirstPoint = firstPoint;
  batchCalls = 0;
}

int pointCloudFileErrors() { return fileErrors; }

bool savePointClouds(std::string &error) {
  std::lock_guard<std::mutex> lock(writtenMutex);
  for (auto &[file, written] : writtenClouds())
    if (!writeGeoFile(file, cloudOf(written), error))
      return false;
  writtenClouds().clear();
  return true;
}

} // namespace osl

extern "C" void osl_rt_pointcloud(int32_t function, const char *layout, const char *kinds,
                                  int32_t *rows, int32_t width, uint32_t laneMask) {
  auto arrays = osl::parsePointCloudLayout(layout);
  if (!arrays)
    return; // the verifier rejects such an op
  osl::CallRows callRows(rows, width, kinds);
  int32_t call = osl::batchCalls++;
  size_t nindices = function == int32_t(osl::PointCloudFunction::Get) && !arrays->empty()
                        ? std::strlen(kinds) - 3 - size_t(arrays->front().length)
                        : 0;
  for (int32_t lane = 0; lane < width; ++lane) {
    if (!(laneMask >> lane & 1u))
      continue;
    switch (osl::PointCloudFunction(function)) {
    case osl::PointCloudFunction::Search:
      osl::search(*arrays, callRows, lane);
      break;
    case osl::PointCloudFunction::Get:
      osl::get(arrays->front(), nindices, callRows, lane);
      break;
    case osl::PointCloudFunction::Write:
      osl::write(*arrays, kinds, callRows, lane, call);
      break;
    }
  }
}
