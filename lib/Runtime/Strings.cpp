//===- Strings.cpp - OSL's string functions at run time -------------------===//
//
// The intern table behind string handles and the lane loops of
// osl_rt_string_call and osl_rt_print (OslAbi/EntryPoints.h): each lane's
// operands are read from rows, handles become their text, and the pure
// string functions (OslStrings) run on them. Dictionaries and closures'
// text, which belong to this process, are here.
//
//===----------------------------------------------------------------------===//
#include "Dictionaries.h"
#include "OslAbi/EntryPoints.h"
#include "OslAbi/Words.h"
#include "OslRuntime/StringCall.h"
#include "OslRuntime/PrintCall.h"
#include "OslRuntime/Closure.h"
#include "OslStrings/StringFunctions.h"

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <memory>
#include <mutex>
#include <set>
#include <shared_mutex>
#include <unordered_map>
#include <utility>
#include <vector>

using osl::StringValue;
using osl::floatOfWord;
using osl::wordOfFloat;

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
    auto [c, offset] = slotOf(handle);
    std::unique_ptr<std::string[]> &chunk = chunks[c];
    if (!chunk)
      chunk = std::make_unique<std::string[]>(kFirstChunk << c);
    std::string &slot = chunk[offset];
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
    auto [c, offset] = slotOf(handle);
    return chunks[c][offset];
  }

private:
  /// Chunk c holds kFirstChunk << c strings: a process that makes a few
  /// strings (most) builds a few small chunks, not megabytes of empty
  /// strings to fault in, and 2^31 handles still fit in kChunks.
  static constexpr int kFirstChunkBits = 8;
  static constexpr size_t kFirstChunk = size_t(1) << kFirstChunkBits;
  static constexpr int kChunks = 32 - kFirstChunkBits;
  /// The chunk and index in it of `handle`: handle + kFirstChunk's top bit
  /// says which chunk.
  static std::pair<int, size_t> slotOf(int32_t handle) {
    uint64_t at = uint64_t(handle) + kFirstChunk;
    int top = 63 - __builtin_clzll(at);
    return {top - kFirstChunkBits, size_t(at - (uint64_t(1) << top))};
  }
  std::shared_mutex mutex; // guards `handles` and writes to `chunks`
  std::unique_ptr<std::string[]> chunks[kChunks];
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

/// A closure as OSL prints it: its primitives, weights multiplied through,
/// one per line after the first: `(r, g, b) * name (param, ..., "keyword",
/// value)`.
std::string closureText(int32_t handle) {
  std::vector<osl::ClosurePrimitive> prims;
  osl::threadClosureArena().flatten(handle, prims);
  std::string out;
  auto number = [](float f) { return osl::printNumber(double(f)); };
  auto triple = [&](std::array<float, 3> t) {
    return "(" + number(t[0]) + ", " + number(t[1]) + ", " + number(t[2]) + ")";
  };
  for (size_t k = 0; k < prims.size(); ++k) {
    const osl::ClosurePrimitive &p = prims[k];
    if (k)
      out += "\n\t+ ";
    out += triple(p.weight) + " * " + p.name() + " (";
    // Parameter i's value (an array's element), then each positional one
    // (an array in brackets), then each keyword after its name.
    int32_t i = 0;
    auto value = [&](char kind) {
      switch (kind) {
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
      ++i;
    };
    osl::forEachClosureParam(p.id, [&](char kind, int32_t length) {
      out += i ? ", " : "";
      if (!length)
        return value(kind);
      out += "[";
      for (int32_t e = 0; e < length; ++e) {
        out += e ? ", " : "";
        value(kind);
      }
      out += "]";
    });
    osl::forEachClosureKeyword(p.id, [&](std::string_view name, char kind) {
      out += (i ? ", \"" : "\"") + std::string(name) + "\", ";
      value(kind);
    });
    out += ")";
  }
  return out;
}

/// What a call's lanes share: the operand vector and closure texts are
/// reused from lane to lane and call to call on a thread (a string call runs
/// once per batch in hot shaders, so allocating per lane cost more than the
/// function itself), and the kinds are measured once per call.
struct LaneOperands {
  std::vector<StringValue> values;
  std::vector<std::string> closureTexts;
};

LaneOperands &threadLaneOperands() {
  static thread_local LaneOperands operands;
  return operands;
}

/// Lane `lane`'s operands from rows of `width` 32-bit values (`nkinds`
/// kinds): a string's handle becomes its text, a closure's its printed text.
void readLane(const char *kinds, size_t nkinds, const int32_t *rows, int32_t width,
              int32_t lane, LaneOperands &out) {
  out.values.resize(nkinds);
  out.closureTexts.clear();
  out.closureTexts.reserve(nkinds); // string_views into it must not move
  const int32_t *at = rows + lane;
  for (size_t k = 0; k < nkinds; ++k) {
    StringValue &o = out.values[k];
    o = StringValue();
    o.kind = kinds[k];
    for (int32_t c = 0; c < osl::stringOperandRows(o.kind); ++c, at += width) {
      o.i = *at;
      o.f[c] = floatOfWord(*at);
    }
    if (o.kind == 's')
      o.s = internTable().text(o.i);
    else if (o.kind == 'k')
      o.s = out.closureTexts.emplace_back(closureText(o.i));
  }
}

//===----------------------------------------------------------------------===//
// Dictionaries
//===----------------------------------------------------------------------===//

enum : int32_t {
  kDictFind = osl::stringFunctionCode("dict_find"),
  kDictFindNode = osl::stringFunctionCode("dict_find:node"),
  kDictNext = osl::stringFunctionCode("dict_next"),
  kDictValueFound = osl::stringFunctionCode("dict_value:found"),
  kDictValueInt = osl::stringFunctionCode("dict_value:int"),
  kDictValueFloat = osl::stringFunctionCode("dict_value:float"),
  kDictValueString = osl::stringFunctionCode("dict_value:string"),
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

/// A dictionary function's result for one lane.
int32_t callDictionary(int32_t function, const std::vector<StringValue> &a, std::string &error) {
  switch (function) {
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
      return wordOfFloat(0);
    parseNumbers(text, 0, false, numbers);
    return wordOfFloat(a[2].i >= 0 && size_t(a[2].i) < numbers.size()
                      ? float(numbers[size_t(a[2].i)])
                      : 0.0f);
  }
  case kDictValueString: {
    std::string text;
    return intern(osl::dictAttribute(a[0].i, a[1].s, text) ? text : "");
  }
  }
  return 0;
}

/// The result's 32 bits for one lane (`dictionary`: `function` is one of
/// the dictionary functions, which this process answers).
int32_t callLane(int32_t function, bool dictionary, const std::vector<StringValue> &a,
                 std::string &error) {
  if (dictionary)
    return callDictionary(function, a, error);
  osl::StringResult result = osl::evalStringFunction(function, a, error);
  return osl::kStringFunctions[function].result == 's' ? intern(result.text) : result.bits;
}

} // namespace

//===----------------------------------------------------------------------===//
// Entry points
//===----------------------------------------------------------------------===//

std::string osl::stringText(int32_t handle) { return std::string(internTable().text(handle)); }

int osl::stringErrors() {
  std::lock_guard<std::mutex> lock(errorMutex);
  return int(reportedErrors.size());
}

extern "C" int32_t osl_rt_string_intern(const char *text) { return intern(text); }

extern "C" int32_t osl_rt_string_intern_cached(const char *text, int32_t *slot) {
  // Threads racing on the first call store the same handle.
  int32_t handle = __atomic_load_n(slot, __ATOMIC_ACQUIRE);
  if (handle >= 0)
    return handle;
  handle = intern(text);
  __atomic_store_n(slot, handle, __ATOMIC_RELEASE);
  return handle;
}

extern "C" const char *osl_rt_string_bytes(int32_t handle, int32_t *length) {
  std::string_view text = internTable().text(handle);
  *length = int32_t(text.size());
  return text.data();
}

extern "C" void osl_rt_string_call(const char *where, int32_t function, const char *kinds,
                                   int32_t *rows, int32_t width, uint32_t laneMask) {
  size_t nkinds = std::strlen(kinds);
  int32_t resultRow = 0;
  for (size_t k = 0; k < nkinds; ++k)
    resultRow += osl::stringOperandRows(kinds[k]);
  int32_t *result = rows + size_t(resultRow) * size_t(width);
  LaneOperands &operands = threadLaneOperands();
  // Once per call, not per lane: it compares the function's name.
  bool dictionary = osl::isDictionaryFunction(osl::kStringFunctions[function].name);
  for (int32_t lane = 0; lane < width; ++lane) {
    result[lane] = 0;
    if (!(laneMask >> lane & 1))
      continue;
    readLane(kinds, nkinds, rows, width, lane, operands);
    std::string error;
    int32_t value = callLane(function, dictionary, operands.values, error);
    if (!error.empty() && dictionary) {
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
  size_t nkinds = std::strlen(kinds);
  LaneOperands &scratch = threadLaneOperands();
  const std::vector<StringValue> &operands = scratch.values;
  for (int32_t lane = 0; lane < width; ++lane) {
    if (!(laneMask >> lane & 1))
      continue;
    readLane(kinds, nkinds, rows, width, lane, scratch);
    std::string error;
    std::string text = osl::formatValues(operands[leading - 1].s, operands.data() + leading,
                                         operands.size() - leading, error, osl::FormatStyle::Fmt);
    if (!error.empty()) {
      reportOnce(where, error);
      continue;
    }
    osl::keepLaneText(stream, lane, leading > 1 ? std::string(operands[0].s) : std::string(),
                      std::move(text));
  }
}
