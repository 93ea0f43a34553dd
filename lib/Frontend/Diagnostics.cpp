//===- Diagnostics.cpp - Error reporting ----------------------------------===//
#include "Diagnostics.h"

using namespace osl::frontend;

void Diagnostics::error(SrcLoc loc, const llvm::Twine &message) {
  if (errors++ > 0)
    return;
  os << files[loc.file] << ":" << loc.line << ":" << loc.col << ": error: " << message
     << "\n";
  os.flush();
}

void Diagnostics::error(const llvm::Twine &message) {
  if (errors++ > 0)
    return;
  os << files[0] << ": error: " << message << "\n";
  os.flush();
}
