//===- Diagnostics.h - Source positions and error reporting -----*- C++ -*-===//
#ifndef OSLFRONTEND_DIAGNOSTICS_H
#define OSLFRONTEND_DIAGNOSTICS_H

#include "llvm/ADT/StringRef.h"
#include "llvm/ADT/Twine.h"
#include "llvm/Support/raw_ostream.h"

#include <string>

namespace osl::frontend {

/// A 1-based line and column (columns count bytes).
struct SrcLoc {
  unsigned line = 1;
  unsigned col = 1;
};

/// Prints `file:line:col: error: message`. The front end stops at the
/// first error, so `hadError` is checked by every phase.
class Diagnostics {
public:
  Diagnostics(llvm::StringRef filename, llvm::raw_ostream &os)
      : filename(filename.str()), os(os) {}

  /// Reports an error; only the first one is printed (later ones would
  /// mostly be consequences of it).
  void error(SrcLoc loc, const llvm::Twine &message);
  /// An error with no source position (`file: error: message`).
  void error(const llvm::Twine &message);
  bool hadError() const { return errors > 0; }
  llvm::StringRef getFilename() const { return filename; }

private:
  std::string filename;
  llvm::raw_ostream &os;
  unsigned errors = 0;
};

} // namespace osl::frontend

#endif // OSLFRONTEND_DIAGNOSTICS_H
