//===- RunFlags.h - osl-run's flags as a table ------------------*- C++ -*-===//
//
// Each flag is a name (or a prefix, for forms such as --width=8 and
// --param:type=float) and a handler that reads its arguments from the
// command line into RunOptions.
//
//===----------------------------------------------------------------------===//
#ifndef OSLRUN_RUNFLAGS_H
#define OSLRUN_RUNFLAGS_H

#include "RunOptions.h"

#include <string>

namespace osl {

/// The command line as the handlers see it: `argv[i]` is the flag (spelled
/// `flag`, testshade's single-dash forms made double), its arguments
/// follow.
struct FlagParser {
  int argc;
  char **argv;
  int i;
  RunOptions &o;
  std::string &error;
  std::string flag;
  /// --scene is on the command line: -o takes one file.
  bool render = false;
  /// testshade's `--layer NAME` names the next positional shader.
  std::string pendingLayer;

  /// Whether `n` arguments follow; if not, says so in `error`.
  bool need(int n, const char *name) {
    if (i + n < argc)
      return true;
    error = std::string(name) + " needs " + std::to_string(n) + " argument" +
            (n > 1 ? "s" : "");
    return false;
  }
  bool need(int n) { return need(n, flag.c_str()); }
  /// The next argument (after need()).
  const char *next() { return argv[++i]; }
  bool fail(std::string message) {
    error = std::move(message);
    return false;
  }
};

using FlagHandler = bool (*)(FlagParser &);

/// The handler of `flag` (exact names first, then prefixes), or null.
FlagHandler findFlag(const std::string &flag);

/// Parses an int in [-2^30, 2^30], the whole text.
bool parseInt(const char *text, int &out);

/// testshade names shaders without extension: NAME.osl unless NAME is a
/// file.
std::string shaderFile(std::string name);

} // namespace osl

#endif // OSLRUN_RUNFLAGS_H
