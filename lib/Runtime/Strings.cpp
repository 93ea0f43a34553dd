//===- Strings.cpp - OSL's string functions at run time -------------------===//
//
// The intern table behind string handles and the lane loop of
// osl_rt_string_call (OslRuntime/StringCall.h). Each function follows OSL
// 1.13's semantics: format is C printf applied value by value, hash is
// OpenImageIO's ustring hash, the regex functions use std::regex
// (ECMAScript), substr counts a negative start from the end, getchar out
// of range is 0, stoi/stof parse a prefix as atoi/atof do.
//
// Compiled with exceptions in OslImageIO: std::regex reports a bad pattern
// by throwing.
//
//===----------------------------------------------------------------------===//
#include "Dictionaries.h"
#include "OslRuntime/StringCall.h"
#include "OslRuntime/PrintCall.h"
#include "OslRuntime/Closure.h"

#include <OpenImageIO/strutil.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <memory>
#include <mutex>
#include <regex>
#include <set>
#include <shared_mutex>
#include <unordered_map>
#include <vector>

namespace {

//===----------------------------------------------------------------------===//
// The intern table
//===----------------------------------------------------------------------===//

/// Strings by handle and handles by string. Append-only, as OSL's ustrings
/// are: a handle is never invalidated, so lanes and threads can keep them.
/// Reading a handle's text takes no lock (lanes read far more strings than
/// they make): strings live in fixed chunks that never move, and a handle
/// is published only after its string is written.
class InternTable {
public:
  InternTable() { intern(""); }

  int32_t intern(std::string_view s) {
    {
      std::shared_lock<std::shared_mutex> lock(mutex);
      if (auto it = handles.find(s); it != handles.end())
        return it->second;
    }
    std::unique_lock<std::shared_mutex> lock(mutex);
    if (auto it = handles.find(s); it != handles.end())
      return it->second;
    int32_t handle = count.load(std::memory_order_relaxed);
    if (handle == std::numeric_limits<int32_t>::max()) {
      std::fprintf(stderr, "error: too many distinct strings for 32-bit string handles\n");
      std::abort();
    }
    std::unique_ptr<std::string[]> &chunk = chunks[size_t(handle) / kChunkSize];
    if (!chunk)
      chunk = std::make_unique<std::string[]>(kChunkSize);
    std::string &slot = chunk[size_t(handle) % kChunkSize];
    slot.assign(s);
    handles.emplace(slot, handle);
    count.store(handle + 1, std::memory_order_release);
    return handle;
  }

  /// The text of a handle; "" for one that was never issued (lanes that
  /// were off when it was computed).
  std::string_view text(int32_t handle) const {
    if (handle < 0 || handle >= count.load(std::memory_order_acquire))
      return {};
    return chunks[size_t(handle) / kChunkSize][size_t(handle) % kChunkSize];
  }

private:
  static constexpr size_t kChunkSize = size_t(1) << 16;
  static constexpr size_t kMaxChunks = size_t(1) << 15; // 2^31 handles in all
  std::shared_mutex mutex; // guards `handles` and writes to `chunks`
  std::unique_ptr<std::unique_ptr<std::string[]>[]> chunks =
      std::make_unique<std::unique_ptr<std::string[]>[]>(kMaxChunks);
  std::atomic<int32_t> count{0};
  std::unordered_map<std::string_view, int32_t> handles;
};

InternTable &internTable() {
  static InternTable *table = new InternTable(); // lives as long as kernels may run
  return *table;
}

//===----------------------------------------------------------------------===//
// Errors, once per call site and message
//===----------------------------------------------------------------------===//

std::mutex errorMutex;
std::set<std::string> reportedErrors;

void reportOnce(const char *where, const std::string &message) {
  std::lock_guard<std::mutex> lock(errorMutex);
  if (!reportedErrors.insert(std::string(where) + "\n" + message).second)
    return;
  std::fprintf(stderr, "%s: error: %s\n", where, message.c_str());
}

//===----------------------------------------------------------------------===//
// One lane's operands
//===----------------------------------------------------------------------===//

struct Operand {
  char kind;
  int32_t i = 0;       // an int, or a string's handle
  float f[3] = {0, 0, 0};
  std::string_view s;  // a string's text
};

float floatBits(int32_t bits) {
  float f;
  std::memcpy(&f, &bits, sizeof f);
  return f;
}

int32_t bitsOf(float f) {
  int32_t bits;
  std::memcpy(&bits, &f, sizeof bits);
  return bits;
}

//===----------------------------------------------------------------------===//
// format
//===----------------------------------------------------------------------===//

/// One conversion of a format string: its text up to the conversion
/// letter, e.g. "%-05.2" and 'f'.
struct Conversion {
  std::string spec;
  char letter;
};

bool isIntLetter(char c) { return std::strchr("diouxXc", c) != nullptr; }
bool isFloatLetter(char c) { return std::strchr("eEfFgGaA", c) != nullptr; }

/// Parses the conversion starting at format[pos] == '%' (not "%%"); on
/// success `pos` is past it.
bool parseConversion(std::string_view format, size_t &pos, Conversion &out) {
  size_t start = pos++;
  while (pos < format.size() && std::strchr("-+ #0", format[pos]))
    ++pos;
  while (pos < format.size() && std::isdigit((unsigned char)format[pos]))
    ++pos;
  if (pos < format.size() && format[pos] == '.') {
    ++pos;
    while (pos < format.size() && std::isdigit((unsigned char)format[pos]))
      ++pos;
  }
  // Length modifiers mean nothing for OSL's types; C's are skipped.
  std::string spec(format.substr(start, pos - start));
  while (pos < format.size() && std::strchr("hlLqjzt", format[pos]))
    ++pos;
  if (pos >= format.size())
    return false;
  char letter = format[pos++];
  if (letter != 's' && !isIntLetter(letter) && !isFloatLetter(letter))
    return false;
  out = {spec, letter};
  return true;
}

template <typename T>
std::string printfText(const std::string &spec, char letter, T value) {
  std::string fmt = spec + letter;
  int n = std::snprintf(nullptr, 0, fmt.c_str(), value);
  std::string text(size_t(n > 0 ? n : 0), '\0');
  std::snprintf(text.data(), text.size() + 1, fmt.c_str(), value);
  return text;
}

std::string formatNumber(const Conversion &c, double value, bool isInt) {
  if (c.letter == 's') // a number printed as text: its usual form
    return isInt ? printfText(c.spec, 'd', int(value)) : printfText(c.spec, 'g', value);
  if (isIntLetter(c.letter))
    return printfText(c.spec, c.letter, int(value));
  return printfText(c.spec, c.letter, value);
}

std::string closureText(int32_t handle);

/// One value under one conversion; triples print their components
/// separated by spaces, as OSL does; closures as OSL prints them.
std::string formatValue(const Conversion &c, const Operand &v) {
  switch (v.kind) {
  case 'k':
    return printfText(c.spec, 's', closureText(v.i).c_str());
  case 's':
    return printfText(c.spec, 's', std::string(v.s).c_str());
  case 'i':
    return formatNumber(c, double(v.i), true);
  case 'f':
    return formatNumber(c, double(v.f[0]), false);
  default:
    return formatNumber(c, v.f[0], false) + " " + formatNumber(c, v.f[1], false) + " " +
           formatNumber(c, v.f[2], false);
  }
}

/// Walks `format`, calling `onConversion` for each conversion in order;
/// returns an error, or "".
template <typename Fn>
std::string walkFormat(std::string_view format, std::string &literal, Fn onConversion) {
  for (size_t pos = 0; pos < format.size();) {
    if (format[pos] != '%') {
      literal += format[pos++];
      continue;
    }
    if (pos + 1 < format.size() && format[pos + 1] == '%') {
      literal += '%';
      pos += 2;
      continue;
    }
    Conversion c;
    size_t at = pos;
    if (!parseConversion(format, pos, c))
      return "malformed conversion '" + std::string(format.substr(at, pos - at)) +
             "' in format string \"" + std::string(format) + "\"";
    std::string error = onConversion(c);
    if (!error.empty())
      return error;
  }
  return "";
}

/// A closure as OSL prints it: its primitives, weights multiplied through,
/// one per line after the first: `(r, g, b) * name (param, ..., "keyword",
/// value)`.
std::string closureText(int32_t handle) {
  std::vector<osl::ClosurePrimitive> prims;
  osl::threadClosureArena().flatten(handle, prims);
  std::string out;
  auto number = [](float f) { return printfText("%", 'g', double(f)); };
  auto triple = [&](std::array<float, 3> t) {
    return "(" + number(t[0]) + ", " + number(t[1]) + ", " + number(t[2]) + ")";
  };
  for (size_t k = 0; k < prims.size(); ++k) {
    const osl::ClosurePrimitive &p = prims[k];
    if (k)
      out += "\n\t+ ";
    out += triple(p.weight) + " * " + p.name() + " (";
    char kinds[osl::kMaxClosureParams];
    int32_t count = std::min(osl::closureParamKinds(p.id, kinds, osl::kMaxClosureParams),
                             osl::kMaxClosureParams);
    int32_t positional = int32_t(std::strlen(osl::kClosures[p.id].params));
    std::vector<std::string_view> keywords;
    osl::forEachClosureKeyword(p.id, [&](std::string_view name, char) {
      keywords.push_back(name);
    });
    for (int32_t i = 0; i < count; ++i) {
      if (i)
        out += ", ";
      if (i >= positional)
        out += "\"" + std::string(keywords[size_t(i - positional)]) + "\", ";
      switch (kinds[i]) {
      case 'n':
      case 'c':
        out += triple(p.tripleParam(i));
        break;
      case 'f':
        out += number(p.floatParam(i));
        break;
      case 'i':
        out += std::to_string(p.intParam(i));
        break;
      case 's':
        out += "\"" + osl::stringText(p.stringParam(i)) + "\"";
        break;
      default: // a closure parameter (layer's top and base)
        out += "(" + closureText(p.closureParam(i)) + ")";
      }
    }
    out += ")";
  }
  return out;
}

std::string formatLane(std::string_view format, const std::vector<Operand> &values,
                       std::string &error) {
  std::string out;
  size_t next = 0;
  error = walkFormat(format, out, [&](const Conversion &c) -> std::string {
    if (next >= values.size())
      return "format string \"" + std::string(format) + "\" needs more values than the " +
             std::to_string(values.size()) + " given";
    out += formatValue(c, values[next++]);
    return "";
  });
  return error.empty() ? out : std::string();
}

//===----------------------------------------------------------------------===//
// Regular expressions
//===----------------------------------------------------------------------===//

/// Compiled patterns by handle, per thread (std::regex is not meant to be
/// shared while matching); null for a bad pattern.
const std::regex *compiledRegex(int32_t handle, std::string_view pattern, std::string &error) {
  thread_local std::unordered_map<int32_t, std::unique_ptr<std::regex>> cache;
  auto it = cache.find(handle);
  if (it == cache.end()) {
    std::unique_ptr<std::regex> re;
    try {
      re = std::make_unique<std::regex>(std::string(pattern), std::regex::ECMAScript);
    } catch (const std::regex_error &) {
    }
    it = cache.emplace(handle, std::move(re)).first;
  }
  if (!it->second)
    error = osl::regexError(std::string(pattern));
  return it->second.get();
}

/// Lane `lane`'s operands from rows of `width` 32-bit values.
void readLane(const char *kinds, const int32_t *rows, int32_t width, int32_t lane,
              std::vector<Operand> &out) {
  out.clear();
  int32_t row = 0;
  for (const char *k = kinds; *k; ++k) {
    auto next = [&] { return rows[size_t(row++) * size_t(width) + size_t(lane)]; };
    Operand &o = out.emplace_back();
    o.kind = *k;
    for (int32_t c = 0; c < osl::stringOperandRows(o.kind); ++c) {
      int32_t bits = next();
      o.i = bits;
      o.f[c] = floatBits(bits);
    }
    o.s = o.kind == 's' ? internTable().text(o.i) : std::string_view();
  }
}

//===----------------------------------------------------------------------===//
// The functions, one lane at a time
//===----------------------------------------------------------------------===//

enum : int32_t {
  kConcat, kFormat, kStrlen, kHash, kStartswith, kEndswith, kGetchar, kSubstr,
  kStoi, kStof, kRegexSearch, kRegexMatch, kSplitCount, kSplitPiece, kRegexResult,
  kDictFind, kDictFindNode, kDictNext, kDictValueFound, kDictValueInt, kDictValueFloat,
  kDictValueString,
};

/// A dictionary attribute's text as `count` numbers (separated by spaces or
/// commas), each parsed whole; false if it is not.
bool parseNumbers(const std::string &text, size_t count, bool integer,
                  std::vector<double> &numbers) {
  numbers.clear();
  const char *p = text.c_str();
  while (*p) {
    while (*p == ' ' || *p == ',' || *p == '\t' || *p == '\n')
      ++p;
    if (!*p)
      break;
    char *end = nullptr;
    double x = integer ? double(std::strtol(p, &end, 10)) : std::strtod(p, &end);
    if (end == p)
      return false;
    numbers.push_back(x);
    p = end;
  }
  return numbers.size() == count;
}

/// dict_value's answer for a node's attribute: found (what = 0 int, 1
/// float, 2 string, N >= 3 floats), or the value (component k).
bool dictNumbers(int32_t node, std::string_view name, int32_t what,
                 std::vector<double> &numbers) {
  std::string text;
  if (!osl::dictAttribute(node, name, text))
    return false;
  if (what == 2)
    return true;
  return parseNumbers(text, what >= 3 ? size_t(what) : 1, what == 0, numbers);
}

int32_t intern(std::string_view s) { return internTable().intern(s); }

/// substr(s, start, length): a negative start counts from the end; both
/// are clamped to the string.
std::string_view substring(std::string_view s, int32_t start, int32_t length) {
  int32_t n = int32_t(s.size());
  int32_t b = start < 0 ? start + n : start;
  b = std::clamp(b, 0, n);
  return s.substr(size_t(b), size_t(std::clamp(length, 0, n)));
}

/// The pieces of `s` as Python's str.split(sep, maxsplit) makes them (what
/// OSL's split does): an empty `sep` splits at runs of whitespace and drops
/// leading and trailing whitespace; a negative `maxsplit` does not limit.
std::vector<std::string_view> splitPieces(std::string_view s, std::string_view sep,
                                          int32_t maxsplit) {
  std::vector<std::string_view> pieces;
  auto limited = [&] { return maxsplit >= 0 && int32_t(pieces.size()) >= maxsplit; };
  if (sep.empty()) {
    auto space = [](char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; };
    size_t i = 0;
    while (true) {
      while (i < s.size() && space(s[i]))
        ++i;
      if (i >= s.size())
        break;
      if (limited()) {
        size_t end = s.size();
        while (end > i && space(s[end - 1]))
          --end;
        pieces.push_back(s.substr(i, end - i));
        break;
      }
      size_t j = i;
      while (j < s.size() && !space(s[j]))
        ++j;
      pieces.push_back(s.substr(i, j - i));
      i = j;
    }
    return pieces;
  }
  size_t start = 0;
  while (!limited()) {
    size_t at = s.find(sep, start);
    if (at == std::string_view::npos)
      break;
    pieces.push_back(s.substr(start, at - start));
    start = at + sep.size();
  }
  pieces.push_back(s.substr(start));
  return pieces;
}

/// The result's 32 bits for one lane.
int32_t callLane(int32_t function, const std::vector<Operand> &a, std::string &error) {
  switch (function) {
  case kConcat: {
    std::string s;
    for (const Operand &o : a)
      s += o.s;
    return intern(s);
  }
  case kFormat:
    return intern(formatLane(a[0].s, std::vector<Operand>(a.begin() + 1, a.end()), error));
  case kStrlen:
    return int32_t(a[0].s.size());
  case kHash: // OSL's hash(string) is the ustring hash (inline, as an int)
    return int32_t(OIIO::Strutil::strhash(a[0].s));
  case kStartswith:
    return a[0].s.substr(0, a[1].s.size()) == a[1].s;
  case kEndswith:
    return a[0].s.size() >= a[1].s.size() &&
           a[0].s.substr(a[0].s.size() - a[1].s.size()) == a[1].s;
  case kGetchar:
    return a[1].i >= 0 && size_t(a[1].i) < a[0].s.size() ? int32_t(a[0].s[size_t(a[1].i)])
                                                          : 0;
  case kSubstr:
    return intern(substring(a[0].s, a[1].i,
                            a.size() > 2 ? a[2].i : int32_t(a[0].s.size())));
  case kStoi:
    return int32_t(std::atoi(std::string(a[0].s).c_str()));
  case kStof:
    return bitsOf(float(std::atof(std::string(a[0].s).c_str())));
  case kRegexSearch:
  case kRegexMatch: {
    const std::regex *re = compiledRegex(a[1].i, a[1].s, error);
    if (!re)
      return 0;
    const char *begin = a[0].s.data(), *end = begin + a[0].s.size();
    return function == kRegexSearch ? std::regex_search(begin, end, *re)
                                    : std::regex_match(begin, end, *re);
  }
  case kRegexResult: { // (subject, regex, full match?, k, old value)
    // Entries 2i and 2i+1 are where group i begins and ends (an unmatched
    // group at the subject's end, as std::regex leaves it, which OSL uses
    // too); entries past the groups, and every entry when nothing matches,
    // keep their values.
    // The entries of one lane are asked for one after another: the match
    // is kept per thread, so the regex runs once per lane, not per entry.
    struct LastMatch {
      int32_t subject = -1, regex = -1, full = -1;
      bool found = false;
      std::vector<int32_t> positions; // begin and end of each group
    };
    thread_local LastMatch last;
    if (last.subject != a[0].i || last.regex != a[1].i || last.full != a[2].i) {
      const std::regex *re = compiledRegex(a[1].i, a[1].s, error);
      if (!re)
        return a[4].i;
      const char *begin = a[0].s.data(), *end = begin + a[0].s.size();
      std::cmatch m;
      last = {a[0].i, a[1].i, a[2].i,
              a[2].i ? std::regex_match(begin, end, m, *re)
                     : std::regex_search(begin, end, m, *re),
              {}};
      for (size_t g = 0; last.found && g < m.size(); ++g)
        for (const char *at : {m[g].first, m[g].second})
          last.positions.push_back(int32_t((m[g].matched ? at : end) - begin));
    }
    if (!last.found || a[3].i < 0 || size_t(a[3].i) >= last.positions.size())
      return a[4].i;
    return last.positions[size_t(a[3].i)];
  }
  case kDictFind:
    return osl::dictFind(a[0].s, a[1].s, error);
  case kDictFindNode:
    return osl::dictFindBelow(a[0].i, a[1].s, error);
  case kDictNext:
    return osl::dictNext(a[0].i);
  case kDictValueFound: {
    std::vector<double> numbers;
    return dictNumbers(a[0].i, a[1].s, a[2].i, numbers);
  }
  case kDictValueInt: {
    std::vector<double> numbers;
    return dictNumbers(a[0].i, a[1].s, 0, numbers) ? int32_t(numbers[0]) : 0;
  }
  case kDictValueFloat: { // (node, name, k): float k of the attribute's numbers
    std::string text;
    std::vector<double> numbers;
    if (!osl::dictAttribute(a[0].i, a[1].s, text))
      return bitsOf(0);
    parseNumbers(text, 0, false, numbers);
    return bitsOf(a[2].i >= 0 && size_t(a[2].i) < numbers.size()
                      ? float(numbers[size_t(a[2].i)])
                      : 0.0f);
  }
  case kDictValueString: {
    std::string text;
    return intern(osl::dictAttribute(a[0].i, a[1].s, text) ? text : "");
  }
  case kSplitCount: // (str, sep, maxsplit, result length)
    return std::min(int32_t(splitPieces(a[0].s, a[1].s, a[2].i).size()), a[3].i);
  case kSplitPiece: { // (str, sep, maxsplit, k)
    std::vector<std::string_view> pieces = splitPieces(a[0].s, a[1].s, a[2].i);
    return a[3].i >= 0 && size_t(a[3].i) < pieces.size() ? intern(pieces[size_t(a[3].i)]) : 0;
  }
  }
  return 0;
}

} // namespace

//===----------------------------------------------------------------------===//
// Entry points
//===----------------------------------------------------------------------===//

std::string osl::regexError(const std::string &pattern) {
  try {
    std::regex re(pattern, std::regex::ECMAScript);
  } catch (const std::regex_error &e) {
    return "invalid regular expression \"" + pattern + "\": " + e.what();
  }
  return "";
}

std::string osl::repeatConversions(std::string_view format, const std::vector<int> &counts) {
  std::string out;
  size_t next = 0;
  for (size_t pos = 0; pos < format.size();) {
    if (format[pos] != '%' || (pos + 1 < format.size() && format[pos + 1] == '%')) {
      size_t n = format[pos] == '%' ? 2 : 1;
      out += format.substr(pos, n);
      pos += n;
      continue;
    }
    size_t at = pos;
    Conversion c;
    if (!parseConversion(format, pos, c)) // formatError reports it
      return std::string(format);
    std::string_view one = format.substr(at, pos - at);
    int n = next < counts.size() ? counts[next] : 1;
    ++next;
    for (int k = 0; k < n; ++k)
      (out += k ? " " : "") += one;
  }
  return out;
}

std::string osl::formatError(std::string_view format, std::string_view valueKinds) {
  std::string literal;
  size_t next = 0;
  return walkFormat(format, literal, [&](const Conversion &c) -> std::string {
    if (next >= valueKinds.size())
      return "format string \"" + std::string(format) + "\" needs more values than the " +
             std::to_string(valueKinds.size()) + " given";
    if (valueKinds[next++] == 's' && c.letter != 's')
      return "format string \"" + std::string(format) + "\" prints a string with '%" +
             c.letter + "'";
    return "";
  });
}

std::string osl::stringText(int32_t handle) { return std::string(internTable().text(handle)); }

int osl::stringErrors() {
  std::lock_guard<std::mutex> lock(errorMutex);
  return int(reportedErrors.size());
}

extern "C" int32_t osl_rt_string_intern(const char *text) { return intern(text); }

extern "C" void osl_rt_string_call(const char *where, int32_t function, const char *kinds,
                                   int32_t *rows, int32_t width, uint32_t laneMask) {
  size_t nkinds = std::strlen(kinds);
  int32_t resultRow = 0;
  for (size_t k = 0; k < nkinds; ++k)
    resultRow += osl::stringOperandRows(kinds[k]);
  int32_t *result = rows + size_t(resultRow) * size_t(width);
  std::vector<Operand> operands;
  for (int32_t lane = 0; lane < width; ++lane) {
    result[lane] = 0;
    if (!(laneMask >> lane & 1))
      continue;
    readLane(kinds, rows, width, lane, operands);
    std::string error;
    int32_t value = callLane(function, operands, error);
    if (!error.empty() && osl::isDictionaryFunction(osl::kStringFunctions[function].name)) {
      // A dictionary that cannot be read: reported in the shader's output
      // as OSL's renderer reports it (dict_find answers -1), and it counts
      // for the exit status.
      osl::keepLaneText(osl::printStreamCode("renderer_error"), lane, "", error);
      std::lock_guard<std::mutex> lock(errorMutex);
      reportedErrors.insert(error);
    } else if (!error.empty()) {
      reportOnce(where, error);
      value = osl::kStringFunctions[function].result == 's' ? intern("") : 0;
    }
    result[lane] = value;
  }
}

extern "C" void osl_rt_print(const char *where, int32_t stream, const char *kinds,
                             int32_t *rows, int32_t width, uint32_t laneMask) {
  size_t leading = std::strlen(osl::kPrintStreams[stream].operands);
  std::vector<Operand> operands;
  for (int32_t lane = 0; lane < width; ++lane) {
    if (!(laneMask >> lane & 1))
      continue;
    readLane(kinds, rows, width, lane, operands);
    std::string error;
    std::string text =
        formatLane(operands[leading - 1].s,
                   std::vector<Operand>(operands.begin() + leading, operands.end()), error);
    if (!error.empty()) {
      reportOnce(where, error);
      continue;
    }
    osl::keepLaneText(stream, lane, leading > 1 ? std::string(operands[0].s) : std::string(),
                      std::move(text));
  }
}
