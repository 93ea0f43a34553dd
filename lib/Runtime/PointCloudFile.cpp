//===- PointCloudFile.cpp - Point clouds as Houdini ASCII .geo files ------===//
//
// The header gives the point count and the point attributes (name, size,
// type and default; an "index" attribute lists its strings instead); each
// point is then a line "x y z w (values...)". Primitives and the rest of the
// file are not needed for a point cloud and are not read.
//
//===----------------------------------------------------------------------===//
#include "OslAbi/Words.h"
#include "OslRuntime/PointCloud.h"

#include <cctype>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>

namespace osl {

char PointAttribute::oslKind() const {
  if (type == 'f')
    return components == 1 ? 'f' : components == 3 ? 't' : 0;
  if (components != 1)
    return 0;
  return type; // 'i' or 's'
}

const PointAttribute *PointCloudData::find(const std::string &name) const {
  for (const PointAttribute &a : attributes)
    if (a.name == name)
      return &a;
  return nullptr;
}

namespace {

/// Whitespace-separated words, parentheses counting as whitespace (a
/// point's values are in parentheses, touching the first and last); a
/// word in double quotes runs to its closing quote.
class GeoWords {
public:
  explicit GeoWords(std::istream &in) : in(in) {}
  bool next(std::string &word) {
    word.clear();
    char c;
    while (in.get(c)) {
      if (std::isspace(static_cast<unsigned char>(c)) || c == '(' || c == ')') {
        if (!word.empty())
          return true;
        continue;
      }
      if (word.empty() && c == '"') { // a quoted string: spaces and all
        word += c;
        while (in.get(c)) {
          word += c;
          if (c == '\\' && in.get(c))
            word += c;
          else if (c == '"')
            return true;
        }
        return false;
      }
      word += c;
    }
    return !word.empty();
  }
  bool number(double &value) {
    std::string w;
    if (!next(w))
      return false;
    char *end = nullptr;
    value = std::strtod(w.c_str(), &end);
    return end && *end == '\0';
  }
  /// A count: a whole number in [0, 2^31) (the kd-tree's indices are
  /// int32), never trusted to size anything before the data is read.
  bool count(long &value) {
    double d;
    if (!number(d) || !(d >= 0 && d <= double(INT32_MAX)) || d != std::floor(d))
      return false;
    value = static_cast<long>(d);
    return true;
  }
  /// An int value of an attribute, in int32's range.
  bool integer(int32_t &value) {
    double d;
    if (!number(d) || !(d >= double(INT32_MIN) && d <= double(INT32_MAX)))
      return false;
    value = static_cast<int32_t>(d);
    return true;
  }
  /// A word, its quotes removed (Partio quotes an index attribute's
  /// strings, with \ escapes).
  bool text(std::string &word) {
    if (!next(word))
      return false;
    if (word.size() >= 2 && word.front() == '"' && word.back() == '"') {
      std::string unquoted;
      for (size_t i = 1; i + 1 < word.size(); ++i) {
        if (word[i] == '\\' && i + 2 < word.size())
          ++i;
        unquoted += word[i];
      }
      word = unquoted;
    }
    return true;
  }

private:
  std::istream &in;
};

} // namespace

bool readGeoFile(const std::string &path, PointCloudData &cloud, std::string &error) {
  std::ifstream in(path);
  if (!in) {
    error = "cannot read \"" + path + "\"";
    return false;
  }
  GeoWords words(in);
  auto fail = [&](const std::string &what) {
    error = "\"" + path + "\" is not a point cloud Houdini .geo file (" + what + ")";
    return false;
  };
  std::string w;
  if (!words.next(w) || w != "PGEOMETRY" || !words.next(w))
    return fail("it does not start with PGEOMETRY");
  long npoints = -1, nattribs = 0;
  for (const char *key : {"NPoints", "NPrims", "NPointGroups", "NPrimGroups", "NPointAttrib",
                          "NVertexAttrib", "NPrimAttrib", "NAttrib"}) {
    long value;
    if (!words.next(w) || w != key || !words.count(value))
      return fail(std::string("no ") + key + " in its header");
    if (w == "NPoints")
      npoints = value;
    if (w == "NPointAttrib")
      nattribs = value;
  }
  PointAttribute position;
  position.name = "position";
  position.components = 3;
  position.isVector = true;
  cloud.attributes = {position};
  if (nattribs > 0 && (!words.next(w) || w != "PointAttrib"))
    return fail("no PointAttrib before its point attributes");
  for (long a = 0; a < nattribs; ++a) {
    PointAttribute attr;
    long size;
    std::string type;
    if (!words.next(attr.name) || !words.count(size) || !words.next(type) || size < 1 || size > 64)
      return fail("a malformed point attribute");
    attr.components = static_cast<int32_t>(size);
    if (type == "index") {
      long nstrings;
      if (size != 1 || !words.count(nstrings))
        return fail("a malformed index attribute");
      attr.type = 's';
      for (long k = 0; k < nstrings; ++k) {
        std::string text;
        if (!words.text(text))
          return fail("a malformed index attribute");
        attr.strings.push_back(std::move(text));
      }
    } else {
      if (type != "float" && type != "vector" && type != "int")
        return fail("attribute type '" + type + "' is not supported");
      attr.type = type == "int" ? 'i' : 'f';
      attr.isVector = type == "vector";
      double skip;
      for (long k = 0; k < size; ++k)
        if (!words.number(skip))
          return fail("a malformed attribute default");
    }
    cloud.attributes.push_back(std::move(attr));
  }
  // (Nothing is sized from the header's counts: a file that claims more
  // points than it holds ends in an error, not a huge allocation.)
  for (long p = 0; p < npoints; ++p) {
    double v;
    for (int k = 0; k < 4; ++k) { // x y z w
      if (!words.number(v) || (k < 3 && !std::isfinite(float(v))))
        return fail("point " + std::to_string(p) + " is malformed");
      if (k < 3)
        cloud.attributes[0].words.push_back(wordOfFloat(static_cast<float>(v)));
    }
    for (size_t a = 1; a < cloud.attributes.size(); ++a) {
      PointAttribute &attr = cloud.attributes[a];
      for (int32_t k = 0; k < attr.components; ++k) {
        int32_t word;
        bool ok = attr.type == 'f' ? words.number(v) : words.integer(word);
        if (!ok)
          return fail("point " + std::to_string(p) + " is malformed");
        attr.words.push_back(attr.type == 'f' ? wordOfFloat(static_cast<float>(v)) : word);
      }
    }
  }
  return true;
}

bool writeGeoFile(const std::string &path, const PointCloudData &cloud, std::string &error) {
  std::ostringstream out;
  out.precision(9); // every float reads back the same
  size_t n = cloud.size();
  size_t nattribs = cloud.attributes.empty() ? 0 : cloud.attributes.size() - 1;
  out << "PGEOMETRY V5\n"
      << "NPoints " << n << " NPrims 1\n"
      << "NPointGroups 0 NPrimGroups 0\n"
      << "NPointAttrib " << nattribs << " NVertexAttrib 0 NPrimAttrib 0 NAttrib 0\n";
  if (nattribs)
    out << "PointAttrib\n";
  for (size_t a = 1; a < cloud.attributes.size(); ++a) {
    const PointAttribute &attr = cloud.attributes[a];
    out << attr.name << ' ' << attr.components << ' ';
    if (attr.type == 's') {
      out << "index " << attr.strings.size();
      for (const std::string &s : attr.strings) { // quoted, as Partio writes them
        out << " \"";
        for (char c : s)
          out << (c == '"' || c == '\\' ? "\\" : "") << c;
        out << '"';
      }
    } else {
      out << (attr.type == 'i' ? "int" : attr.isVector ? "vector" : "float");
      for (int32_t k = 0; k < attr.components; ++k)
        out << " 0";
    }
    out << '\n';
  }
  for (size_t p = 0; p < n; ++p) {
    const int32_t *xyz = &cloud.attributes[0].words[3 * p];
    out << floatOfWord(xyz[0]) << ' ' << floatOfWord(xyz[1]) << ' ' << floatOfWord(xyz[2]) << " 1";
    for (size_t a = 1; a < cloud.attributes.size(); ++a) {
      const PointAttribute &attr = cloud.attributes[a];
      out << (a == 1 ? " (" : "\t");
      for (int32_t k = 0; k < attr.components; ++k) {
        int32_t word = attr.words[p * attr.components + k];
        out << (k ? " " : "");
        if (attr.type == 'f')
          out << floatOfWord(word);
        else
          out << word;
      }
    }
    out << (nattribs ? ")\n" : "\n");
  }
  out << "Part " << n;
  for (size_t p = 0; p < n; ++p)
    out << ' ' << p;
  out << "\nbeginExtra\nendExtra\n";
  std::ofstream file(path, std::ios::binary);
  if (!(file << out.str()) || !file.flush()) {
    error = "cannot write \"" + path + "\"";
    return false;
  }
  return true;
}

} // namespace osl
