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

bool Diagnostics::warning(SrcLoc loc, const std::string &message) {
  if (nowarn.count({loc.file, loc.line}))
    return true;
  if (warningMode == WarningMode::AsErrors) {
    error(loc, message);
    return false;
  }
  if (warningMode == WarningMode::Hide || !warned.insert({loc.file, loc.line, message}).second)
    return true;
  os << files[loc.file] << ":" << loc.line << ": warning: " << message << "\n";
  os.flush();
  return true;
}

void Diagnostics::error(const llvm::Twine &message) {
  if (errors++ > 0)
    return;
  os << files[0] << ": error: " << message << "\n";
  os.flush();
}
