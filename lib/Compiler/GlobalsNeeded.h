//===- GlobalsNeeded.h - The globals a group reads, as OSL reports -*- C++ -*-===//
//
// With debugging on (testshade -debug), OSL reports which shader globals an
// optimized group still needs, so a renderer can skip computing the rest:
// the global variables it reads and the renderer state its operations
// read (backfacing, flipHandedness, raytype, surfacearea).
//
//===----------------------------------------------------------------------===//
#ifndef OSLCOMPILER_GLOBALSNEEDED_H
#define OSLCOMPILER_GLOBALSNEEDED_H

#include "mlir/IR/BuiltinOps.h"

#include <string>

namespace osl {

/// "Need N globals:  a b\n", the names sorted bytewise as OSL's are, from
/// the operations left after the osl-level passes.
std::string globalsNeededReport(mlir::ModuleOp module);

} // namespace osl

#endif // OSLCOMPILER_GLOBALSNEEDED_H
