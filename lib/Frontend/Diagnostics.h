//===- Diagnostics.h - Source positions and error reporting -----*- C++ -*-===//
#ifndef OSLFRONTEND_DIAGNOSTICS_H
#define OSLFRONTEND_DIAGNOSTICS_H

#include "llvm/ADT/StringRef.h"
#include "llvm/ADT/Twine.h"
#include "llvm/Support/raw_ostream.h"

#include <set>
#include <string>
#include <tuple>
#include <vector>

namespace osl::frontend {

/// A 1-based line and column (columns count bytes) in a source file
/// (0: the main file; others are #included, see Diagnostics::addFile).
struct SrcLoc {
  unsigned line = 1;
  unsigned col = 1;
  unsigned file = 0;
};

/// What happens to warnings: printed, dropped, or errors (oslc's -Werror).
enum class WarningMode { Show, Hide, AsErrors };

/// Prints `file:line:col: error: message`. The front end stops at the
/// first error, so `hadError` is checked by every phase.
class Diagnostics {
public:
  Diagnostics(llvm::StringRef filename, llvm::raw_ostream &os)
      : files{filename.str()}, os(os) {}

  /// Reports an error; only the first one is printed (later ones would
  /// mostly be consequences of it).
  void error(SrcLoc loc, const llvm::Twine &message);
  /// An error with no source position (`file: error: message`).
  void error(const llvm::Twine &message);
  /// Reports a warning as oslc does (`file:line: warning: message`, so
  /// outputs compare with OSL's), once per position and message: a
  /// function's body is emitted at every call. An error under AsErrors;
  /// returns false then.
  bool warning(SrcLoc loc, const std::string &message);
  void setWarningMode(WarningMode mode) { warningMode = mode; }
  /// oslc's `#pragma osl nowarn`: no warnings at `line` of `file`.
  void noWarningsOnLine(unsigned file, unsigned line) { nowarn.insert({file, line}); }
  bool hadError() const { return errors > 0; }
  llvm::StringRef getFilename() const { return files[0]; }
  /// The name of source file `file` of a SrcLoc.
  llvm::StringRef fileName(unsigned file) const { return files[file]; }
  unsigned fileCount() const { return unsigned(files.size()); }
  /// Registers an #included file; returns its SrcLoc::file.
  unsigned addFile(llvm::StringRef name) {
    files.push_back(name.str());
    return unsigned(files.size() - 1);
  }
  /// A file name only messages use (#line's): not a file that was read.
  unsigned addFileName(llvm::StringRef name) {
    namesOnly.insert(unsigned(files.size()));
    return addFile(name);
  }
  bool isFileNameOnly(unsigned file) const { return namesOnly.count(file) != 0; }

private:
  std::vector<std::string> files;
  llvm::raw_ostream &os;
  unsigned errors = 0;
  WarningMode warningMode = WarningMode::Show;
  std::set<std::tuple<unsigned, unsigned, std::string>> warned;
  std::set<std::pair<unsigned, unsigned>> nowarn;
  std::set<unsigned> namesOnly;
};

} // namespace osl::frontend

#endif // OSLFRONTEND_DIAGNOSTICS_H
