//===- Diagnostics.cpp - Error reporting ----------------------------------===//
#include "Diagnostics.h"

using namespace osl::frontend;

void Diagnostics::error(SrcLoc loc, const llvm::Twine &message) {
  if (errors++ > 0)
    return;
  os << filename << ":" << loc.line << ":" << loc.col << ": error: " << message
     << "\n";
  os.flush();
}

void Diagnostics::error(const llvm::Twine &message) {
  if (errors++ > 0)
    return;
  os << filename << ": error: " << message << "\n";
  os.flush();
}
