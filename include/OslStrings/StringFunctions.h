//===- StringFunctions.h - OSL's string functions, pure -----------*- C++ -*-===//
//
// OSL 1.13's string functions and format on plain values: no handles, no
// intern table, no runtime. The runtime runs them lane by lane on handles
// (osl_rt_string_call, osl_rt_print); the front end folds calls whose
// operands are known when the shader is compiled and checks constant format
// strings and regular expressions, with the same code.
//
//===----------------------------------------------------------------------===//
#ifndef OSLSTRINGS_STRINGFUNCTIONS_H
#define OSLSTRINGS_STRINGFUNCTIONS_H

#include "OslAbi/Strings.h"

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace osl {

/// One operand of a string function, or one value to format, for one point.
struct StringValue {
  char kind;             ///< s, i, f, t; k a closure (its printed text in `s`)
  int32_t i = 0;         ///< an int
  float f[3] = {0, 0, 0}; ///< a float, or a triple's components
  std::string_view s;    ///< a string's text
};

/// A string function's result: `text` for a string, else `bits` (an int, or
/// a float's bits).
struct StringResult {
  int32_t bits = 0;
  std::string text;
};

/// Runs string function `code` (kStringFunctions; not a dictionary function)
/// on one point's operands. On an error (a bad regular expression or
/// format) sets `error` and returns OSL's 0 or "".
StringResult evalStringFunction(int32_t code, const std::vector<StringValue> &operands,
                                std::string &error);

/// How a conversion is rendered: format() is C's printf; printf, fprintf,
/// warning and error go through fmt in OSL, which differs for strings with
/// a width (always at the left) and for %o of a negative int (sign and
/// magnitude).
enum class FormatStyle { C, Fmt };

/// `format` applied to `values` as OSL's printf and format do: C printf
/// value by value (with `style`'s differences), triples as three numbers
/// separated by spaces. On an error sets `error` and returns "".
std::string formatValues(std::string_view format, const StringValue *values, size_t count,
                         std::string &error, FormatStyle style = FormatStyle::C);

/// Why `pattern` is not a valid regular expression (std::regex,
/// ECMAScript), or "" when it is.
std::string regexError(const std::string &pattern);

/// Why format string `format` does not fit `valueKinds` (the kinds of the
/// values after it), or "" when it does.
std::string formatError(std::string_view format, std::string_view valueKinds);

/// `format` with its k-th conversion written counts[k] times, separated by
/// spaces: how OSL prints an array's elements or a matrix's 16 values
/// under one conversion.
std::string repeatConversions(std::string_view format, const std::vector<int> &counts);

/// "%g" of `value`, as OSL prints a closure's numbers.
std::string printNumber(double value);

} // namespace osl

#endif // OSLSTRINGS_STRINGFUNCTIONS_H
