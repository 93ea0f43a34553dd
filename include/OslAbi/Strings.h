//===- Strings.h - String handles and string functions: the ABI --*- C++ -*-===//
//
// A string computed at run time is an i32 handle into one process-wide,
// thread-safe, append-only intern table (like OpenImageIO's ustring): equal
// strings have equal handles, so == and != compare handles, and a handle
// stays valid for the life of the process. Handle 0 is "".
//
// Kernels call one entry point (osl_rt_string_call, EntryPoints.h) per
// osl.string_call and batch: each operand is one row of W 32-bit values (an
// int, a handle, or a float's bits; a triple takes three rows), followed by
// the result row. The dialect's verifier, the front end, the lowering and the
// runtime all read this table.
//
//===----------------------------------------------------------------------===//
#ifndef OSLABI_STRINGS_H
#define OSLABI_STRINGS_H

#include <cstdint>
#include <iterator>
#include <string_view>

namespace osl {

/// The string functions, with their operand and result kinds: s a string
/// handle, i an int, f a float, t a triple, k a closure (its handle, formatted
/// as OSL prints closures), `*` any number (possibly none) of the previous
/// kind, `?` an optional last operand, `.` any number of any kinds (format's
/// values).
struct StringFunction {
  const char *name;
  const char *operands;
  char result;
};

inline constexpr StringFunction kStringFunctions[] = {
    {"concat", "s*", 's'},        {"format", "s.", 's'},       {"strlen", "s", 'i'},
    {"hash", "s", 'i'},           {"startswith", "ss", 'i'},   {"endswith", "ss", 'i'},
    {"getchar", "si", 'i'},       {"substr", "sii?", 's'},     {"stoi", "s", 'i'},
    {"stof", "s", 'f'},           {"regex_search", "ss", 'i'}, {"regex_match", "ss", 'i'},
    // split(str, results[N], sep, maxsplit) is these two, named so that no
    // shader can call them: how many pieces fill results (at most N), and
    // piece k.
    {"split:count", "ssii", 'i'}, {"split:piece", "ssiii", 's'},
    // regex_search / regex_match(subject, results[N], regex) fill results
    // with entry k of each: (subject, regex, full match?, k, the entry's
    // old value) -> its new value.
    {"regex:result", "ssiii", 'i'},
    // Dictionaries (never folded when the shader is compiled: node ids
    // belong to the process that runs it). dict_find(node, query) is
    // "dict_find:node"; dict_value is "dict_value:found" (node, name, what
    // is wanted: 0 int, 1 float, 2 string, N >= 3 that many floats) and the
    // value itself, float k of it for "dict_value:float".
    {"dict_find", "ss", 'i'},     {"dict_find:node", "is", 'i'},
    {"dict_next", "i", 'i'},      {"dict_value:found", "isi", 'i'},
    {"dict_value:int", "is", 'i'}, {"dict_value:float", "isi", 'f'},
    {"dict_value:string", "is", 's'},
};

/// Whether string function `name` reads a dictionary (see above).
constexpr bool isDictionaryFunction(std::string_view name) {
  return name.substr(0, 5) == "dict_";
}

/// The index of a string function in kStringFunctions, or -1.
constexpr int32_t stringFunctionCode(std::string_view name) {
  for (int32_t i = 0; i < int32_t(std::size(kStringFunctions)); ++i)
    if (name == kStringFunctions[i].name)
      return i;
  return -1;
}

/// Do `kinds` (one letter per operand: s, i, f, t, k) fit the operand pattern
/// of function `code`?
constexpr bool stringOperandsMatch(int32_t code, std::string_view kinds) {
  std::string_view pattern = kStringFunctions[code].operands;
  size_t k = 0;
  for (size_t p = 0; p < pattern.size(); ++p) {
    char want = pattern[p];
    bool last = p + 1 == pattern.size();
    char next = last ? 0 : pattern[p + 1];
    if (want == '.') { // any kinds to the end
      for (; k < kinds.size(); ++k)
        if (kinds[k] != 's' && kinds[k] != 'i' && kinds[k] != 'f' && kinds[k] != 't' &&
            kinds[k] != 'k')
          return false;
      return true;
    }
    if (next == '*') {
      while (k < kinds.size() && kinds[k] == want)
        ++k;
      ++p;
      continue;
    }
    if (next == '?') {
      if (k < kinds.size() && kinds[k] == want)
        ++k;
      ++p;
      continue;
    }
    if (k >= kinds.size() || kinds[k] != want)
      return false;
    ++k;
  }
  return k == kinds.size();
}

/// The rows one operand of kind `kind` takes.
constexpr int32_t stringOperandRows(char kind) { return kind == 't' ? 3 : 1; }

} // namespace osl

#endif // OSLABI_STRINGS_H
