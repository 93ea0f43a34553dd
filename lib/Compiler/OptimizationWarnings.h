//===- OptimizationWarnings.h - OSL's opt_warnings reports ------*- C++ -*-===//
//
// OSL's runtime optimizer can warn (ShadingSystem option opt_warnings) about
// work it could not fold away: strings created while shading, string
// characters read while shading, texture names that are not known handles.
// osl-mlir reports the same from the operations left after its osl-level
// passes, in OSL's words.
//
//===----------------------------------------------------------------------===//
#ifndef OSLCOMPILER_OPTIMIZATIONWARNINGS_H
#define OSLCOMPILER_OPTIMIZATIONWARNINGS_H

#include "mlir/IR/BuiltinOps.h"

#include <string>

namespace osl {

/// Marks the operations that may be warned about with their layer's name
/// (a group links its layers into one function), right after the front end.
void tagLayerForWarnings(mlir::ModuleOp module, llvm::StringRef layerName);

/// The warnings, one block per operation and source line, in the order
/// the operations come; empty when there is nothing to report. With
/// `errorCalls` (lazyerror=0) every error() call left is one too.
std::string optimizationWarnings(mlir::ModuleOp module, llvm::StringRef groupName,
                                 bool errorCalls);

} // namespace osl

#endif // OSLCOMPILER_OPTIMIZATIONWARNINGS_H
