//===- SharedGlobals.h - Globals a group's layers share ----------*- C++ -*-===//
//
// Private to lib/Transforms: OSL's layers share one set of globals, so a
// layer that assigns P (a displacement) changes what the layers run after it
// read. osl-link-group applies that once the layers are placed.
//
//===----------------------------------------------------------------------===//
#ifndef OSLTRANSFORMS_SHAREDGLOBALS_H
#define OSLTRANSFORMS_SHAREDGLOBALS_H

#include "mlir/Dialect/Func/IR/FuncOps.h"

namespace mlir::osl {

/// Each read of a global (osl.global, where the layer's statement reads it)
/// that comes after, and in a block within, a layer's osl.set_global of it
/// takes the latest such value; then the osl.set_global ops are erased. A write in one arm of an osl.if is
/// not seen after the if (OSL would see it on the lanes that took the arm).
void forwardWrittenGlobals(func::FuncOp group);

} // namespace mlir::osl

#endif // OSLTRANSFORMS_SHAREDGLOBALS_H
