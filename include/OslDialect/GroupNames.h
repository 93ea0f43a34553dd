//===- GroupNames.h - testshade's names of connected values -----*- C++ -*-===//
//
// How a shader group names what it connects, shared by the group builder
// (which marks inputs) and osl-link-group (which resolves them).
//
//===----------------------------------------------------------------------===//
#ifndef OSLDIALECT_GROUPNAMES_H
#define OSLDIALECT_GROUPNAMES_H

#include "llvm/ADT/StringRef.h"

#include <utility>

namespace mlir::osl {

/// "NAME[k]" with k in 0..2 names component k of a triple: NAME and k;
/// any other name is itself and -1.
inline std::pair<llvm::StringRef, int> splitComponentName(llvm::StringRef name) {
  if (name.size() > 3 && name.ends_with("]") && name[name.size() - 3] == '[') {
    char digit = name[name.size() - 2];
    if (digit >= '0' && digit <= '2')
      return {name.drop_back(3), digit - '0'};
  }
  return {name, -1};
}

} // namespace mlir::osl

#endif // OSLDIALECT_GROUPNAMES_H
