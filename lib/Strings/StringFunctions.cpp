//===- StringFunctions.cpp - OSL's string functions on plain values -------===//
//
// Each function follows OSL 1.13's semantics: format is C printf applied
// value by value, hash is OpenImageIO's ustring hash, the regex functions
// use std::regex (ECMAScript), substr counts a negative start from the end,
// getchar out of range is 0, stoi/stof parse a prefix as atoi/atof do.
//
// Compiled with exceptions: std::regex reports a bad pattern by throwing.
//
//===----------------------------------------------------------------------===//
#include "OslStrings/StringFunctions.h"
#include "OslAbi/Words.h"

#include <OpenImageIO/strutil.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <regex>
#include <unordered_map>

using osl::StringResult;
using osl::StringValue;

namespace {

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
  if (letter != 's' && !isIntLetter(letter) && !isFloatLetter(letter) &&
      !std::strchr("mnpv", letter))
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

std::string formatNumber(const Conversion &c, double value, bool isInt, osl::FormatStyle style) {
  if (c.letter == 's') // a number printed as text: its usual form
    return isInt ? printfText(c.spec, 'd', int(value)) : printfText(c.spec, 'g', value);
  // oslc also takes %c, %m, %n, %p and %v for a float, which OSL prints as
  // %f (and C's meanings of %n and %p are never used).
  if (std::strchr("mnpv", c.letter) || (!isInt && c.letter == 'c'))
    return formatNumber({c.spec, isInt ? 'd' : 'f'}, value, isInt, style);
  if (style == osl::FormatStyle::Fmt && c.letter == 'o' && value < 0) {
    // OSL formats through fmt, whose octal of a negative int is its sign
    // and magnitude (-45), not C's two's complement (37777777733).
    std::string digits = printfText("%", 'o', unsigned(-int64_t(value)));
    return printfText(c.spec, 's', ("-" + digits).c_str()); // (width, '-' as C's)
  }
  if (isIntLetter(c.letter))
    return printfText(c.spec, c.letter, int(value));
  return printfText(c.spec, c.letter, value);
}

/// A string under `spec`; fmt puts a string at the left of its width
/// whatever the flags (OSL's printf of `%10s` is "abc       ").
std::string formatString(const std::string &spec, const char *text, osl::FormatStyle style) {
  std::string left = spec;
  if (style == osl::FormatStyle::Fmt && left.find('-') == std::string::npos)
    left.insert(1, "-");
  return printfText(left, 's', text);
}

/// One value under one conversion; triples print their components
/// separated by spaces, as OSL does; closures as OSL prints them.
std::string formatValue(const Conversion &c, const StringValue &v, osl::FormatStyle style) {
  switch (v.kind) {
  case 'k':
  case 's':
    return formatString(c.spec, std::string(v.s).c_str(), style);
  case 'i':
    return formatNumber(c, double(v.i), true, style);
  case 'f':
    return formatNumber(c, double(v.f[0]), false, style);
  default:
    return formatNumber(c, v.f[0], false, style) + " " + formatNumber(c, v.f[1], false, style) +
           " " + formatNumber(c, v.f[2], false, style);
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

} // namespace

std::string osl::formatValues(std::string_view format, const StringValue *values, size_t count,
                              std::string &error, FormatStyle style) {
  std::string out;
  size_t next = 0;
  error = walkFormat(format, out, [&](const Conversion &c) -> std::string {
    if (next >= count)
      return "format string \"" + std::string(format) + "\" needs more values than the " +
             std::to_string(count) + " given";
    out += formatValue(c, values[next++], style);
    return "";
  });
  return error.empty() ? out : std::string();
}


//===----------------------------------------------------------------------===//
// Regular expressions and pieces
//===----------------------------------------------------------------------===//

namespace {

/// Compiled patterns by text, per thread (std::regex is not meant to be
/// shared while matching); null for a bad pattern.
const std::regex *compiledRegex(std::string_view pattern, std::string &error) {
  thread_local std::unordered_map<std::string, std::unique_ptr<std::regex>> cache;
  auto it = cache.find(std::string(pattern));
  if (it == cache.end()) {
    std::unique_ptr<std::regex> re;
    try {
      re = std::make_unique<std::regex>(std::string(pattern), std::regex::ECMAScript);
    } catch (const std::regex_error &) {
    }
    it = cache.emplace(std::string(pattern), std::move(re)).first;
  }
  if (!it->second)
    error = osl::regexError(std::string(pattern));
  return it->second.get();
}

/// substr(s, start, length): a negative start counts from the end; both
/// are clamped to the string.
std::string_view substring(std::string_view s, int32_t start, int32_t length) {
  int32_t n = int32_t(s.size());
  int32_t b = start < 0 ? start + n : start;
  b = std::clamp(b, 0, n);
  return s.substr(size_t(b), size_t(std::clamp(length, 0, n)));
}

/// The pieces of `s` as OSL's split makes them (OpenImageIO's
/// Strutil::split): at most `limit` pieces, the last holding the rest of the
/// string; an empty `sep` splits at runs of whitespace and skips the
/// whitespace before each piece.
std::vector<std::string_view> splitPieces(std::string_view s, std::string_view sep,
                                          int32_t limit) {
  std::vector<std::string_view> pieces;
  if (limit <= 0 || s.empty())
    return pieces; // an empty string has no pieces
  auto last = [&] { return int32_t(pieces.size()) + 1 >= limit; };
  if (sep.empty()) {
    auto space = [](char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; };
    size_t i = 0;
    while (true) {
      while (i < s.size() && space(s[i]))
        ++i;
      if (i >= s.size())
        break;
      if (last()) {
        pieces.push_back(s.substr(i));
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
  while (!last()) {
    size_t at = s.find(sep, start);
    if (at == std::string_view::npos)
      break;
    pieces.push_back(s.substr(start, at - start));
    start = at + sep.size();
  }
  pieces.push_back(s.substr(start));
  return pieces;
}

/// split's limit on pieces: its maxsplit within [0, the results' length]
/// (OSL's osl_split).
int32_t splitLimit(int32_t maxsplit, int32_t resultLength) {
  return std::clamp(maxsplit, 0, std::max(resultLength, 0));
}

/// regex_search / regex_match's results entry `k`: entries 2i and 2i+1 are
/// where group i begins and ends (an unmatched group at the subject's end,
/// as std::regex leaves it, which OSL uses too); entries past the groups,
/// and every entry when nothing matches, are the pattern's length, as both
/// of OSL's backends write them (opstring.cpp, wide_opstring.cpp). A bad
/// pattern keeps `old`.
int32_t regexResult(std::string_view subject, std::string_view pattern, bool full, int32_t k,
                    int32_t old, std::string &error) {
  // The entries of one point are asked for one after another: the match is
  // kept per thread, so the regex runs once per point, not per entry.
  struct LastMatch {
    std::string subject, pattern;
    bool full = false, valid = false, found = false;
    std::vector<int32_t> positions; // begin and end of each group
  };
  thread_local LastMatch last;
  if (!last.valid || last.subject != subject || last.pattern != pattern || last.full != full) {
    const std::regex *re = compiledRegex(pattern, error);
    if (!re)
      return old;
    const char *begin = subject.data(), *end = begin + subject.size();
    std::cmatch m;
    bool found = full ? std::regex_match(begin, end, m, *re) : std::regex_search(begin, end, m, *re);
    last = {std::string(subject), std::string(pattern), full, true, found, {}};
    for (size_t g = 0; found && g < m.size(); ++g)
      for (const char *at : {m[g].first, m[g].second})
        last.positions.push_back(int32_t((m[g].matched ? at : end) - begin));
  }
  if (k < 0)
    return old;
  if (!last.found || size_t(k) >= last.positions.size())
    return int32_t(pattern.size());
  return last.positions[size_t(k)];
}

enum : int32_t {
  kConcat, kFormat, kStrlen, kHash, kStartswith, kEndswith, kGetchar, kSubstr,
  kStoi, kStof, kRegexSearch, kRegexMatch, kSplitCount, kSplitPiece, kRegexResult,
};

/// The result of a function whose result is a number.
int32_t numberResult(int32_t function, const std::vector<StringValue> &a, std::string &error) {
  switch (function) {
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
  case kStoi:
    return int32_t(std::atoi(std::string(a[0].s).c_str()));
  case kStof:
    return osl::wordOfFloat(float(std::atof(std::string(a[0].s).c_str())));
  case kRegexSearch:
  case kRegexMatch: {
    const std::regex *re = compiledRegex(a[1].s, error);
    if (!re)
      return 0;
    const char *begin = a[0].s.data(), *end = begin + a[0].s.size();
    return function == kRegexSearch ? std::regex_search(begin, end, *re)
                                    : std::regex_match(begin, end, *re);
  }
  case kRegexResult: // (subject, regex, full match?, k, old value)
    return regexResult(a[0].s, a[1].s, a[2].i != 0, a[3].i, a[4].i, error);
  case kSplitCount: // (str, sep, maxsplit, result length)
    return int32_t(splitPieces(a[0].s, a[1].s, splitLimit(a[2].i, a[3].i)).size());
  }
  return 0;
}

/// The result of a function whose result is a string.
std::string stringResult(int32_t function, const std::vector<StringValue> &a,
                         std::string &error) {
  switch (function) {
  case kConcat: {
    std::string s;
    for (const StringValue &o : a)
      s += o.s;
    return s;
  }
  case kFormat:
    return osl::formatValues(a[0].s, a.data() + 1, a.size() - 1, error);
  case kSubstr:
    return std::string(
        substring(a[0].s, a[1].i, a.size() > 2 ? a[2].i : int32_t(a[0].s.size())));
  case kSplitPiece: { // (str, sep, maxsplit, result length, k)
    std::vector<std::string_view> pieces =
        splitPieces(a[0].s, a[1].s, splitLimit(a[2].i, a[3].i));
    return a[4].i >= 0 && size_t(a[4].i) < pieces.size() ? std::string(pieces[size_t(a[4].i)])
                                                          : std::string();
  }
  }
  return std::string();
}

} // namespace

StringResult osl::evalStringFunction(int32_t code, const std::vector<StringValue> &operands,
                                     std::string &error) {
  StringResult result;
  if (kStringFunctions[code].result == 's')
    result.text = stringResult(code, operands, error);
  else
    result.bits = numberResult(code, operands, error);
  if (!error.empty())
    result = StringResult();
  return result;
}

std::string osl::printNumber(double value) { return printfText("%", 'g', value); }

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

/// `text` as a message quotes it: newlines and tabs escaped.
static std::string quoted(std::string_view text) {
  std::string out = "\"";
  for (char c : text)
    out += c == '\n' ? "\\n" : c == '\t' ? "\\t" : std::string(1, c);
  return out + "\"";
}

std::string osl::formatError(std::string_view format, std::string_view valueKinds) {
  std::string literal;
  size_t next = 0;
  return walkFormat(format, literal, [&](const Conversion &c) -> std::string {
    if (next >= valueKinds.size())
      return "format string " + quoted(format) + " needs more values than the " +
             std::to_string(valueKinds.size()) + " given";
    // oslc's pairs: ints take %d %i %o %x %X, floats (and triples' and
    // matrices' components) %f %g %e (and %c %m %n %p %v, printed as %f),
    // strings and closures %s.
    char kind = valueKinds[next++];
    const char *letters = kind == 'i' ? "dioxX" : kind == 'f' || kind == 't' ? "fgecmnpv" : "s";
    if (std::strchr(letters, c.letter))
      return "";
    const char *what = kind == 'i'                  ? "an int"
                       : kind == 'f' || kind == 't' ? "a float"
                       : kind == 'k'                ? "a closure"
                                                    : "a string";
    const char *wanted = kind == 'i'                  ? "%d, %i, %o, %x or %X"
                         : kind == 'f' || kind == 't' ? "%f, %g or %e"
                                                      : "%s";
    return "format string " + quoted(format) + " prints value " + std::to_string(next) +
           ", " + what + ", with '%" + c.letter + "': OSL takes " + wanted +
           " for it (oslc: mismatched format string and arguments)";
  });
}

