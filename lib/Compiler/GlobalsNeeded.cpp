//===- GlobalsNeeded.cpp - The globals a group reads, as OSL reports ------===//
#include "GlobalsNeeded.h"

#include "OslDialect/OslDialect.h"

#include "llvm/ADT/StringSwitch.h"

#include <set>

using namespace mlir;

namespace osl {

std::string globalsNeededReport(ModuleOp module) {
  std::set<std::string> names;
  module.walk([&](mlir::osl::GlobalOp g) {
    // A derivative row belongs to the global whose derivative it is.
    names.insert(llvm::StringSwitch<std::string>(g.getName())
                     .Cases("dPdx", "dPdy", "P")
                     .Cases("dudx", "dudy", "u")
                     .Cases("dvdx", "dvdy", "v")
                     .Default(g.getName().str()));
  });
  std::string report = "Need " + std::to_string(names.size()) + " globals: ";
  for (const std::string &n : names)
    report += " " + n;
  return report + "\n";
}

} // namespace osl
