//===- Passes.h - osl-mlir conversions --------------------------*- C++ -*-===//
//
// osl-convert-to-vector (osl at a width W to vector/arith/math/scf, the
// shader becoming the batch kernel) and osl-lower-to-llvm (that to the LLVM
// dialect).
//
//===----------------------------------------------------------------------===//
#ifndef OSLCONVERSION_PASSES_H
#define OSLCONVERSION_PASSES_H

#include "mlir/Dialect/Arith/IR/Arith.h"
#include "mlir/Dialect/ControlFlow/IR/ControlFlow.h"
#include "mlir/Dialect/Func/IR/FuncOps.h"
#include "mlir/Dialect/LLVMIR/LLVMDialect.h"
#include "mlir/Dialect/Math/IR/Math.h"
#include "mlir/Dialect/SCF/IR/SCF.h"
#include "mlir/Dialect/Vector/IR/VectorOps.h"
#include "OslLanes/LibraryFunctions.h"
#include "mlir/Pass/Pass.h"

namespace mlir::osl {

#define GEN_PASS_DECL
#include "OslConversion/Passes.h.inc"

/// osl-convert-to-vector told which library routines are compiled already:
/// their code is not built where nothing needs it (OslLanes/LibraryFunctions.h).
std::unique_ptr<Pass> createConvertToVector(const ConvertToVectorOptions &options,
                                            LibraryObjectAvailable available);

#define GEN_PASS_REGISTRATION
#include "OslConversion/Passes.h.inc"

} // namespace mlir::osl

#endif // OSLCONVERSION_PASSES_H
