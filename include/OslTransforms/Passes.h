//===- Passes.h - osl-mlir passes -------------------------------*- C++ -*-===//
#ifndef OSLTRANSFORMS_PASSES_H
#define OSLTRANSFORMS_PASSES_H

#include "OslLanes/LibraryFunctions.h"
#include "mlir/Dialect/Arith/IR/Arith.h"
#include "mlir/Dialect/ControlFlow/IR/ControlFlow.h"
#include "mlir/Dialect/Func/IR/FuncOps.h"
#include "mlir/Dialect/LLVMIR/LLVMDialect.h"
#include "mlir/Dialect/Math/IR/Math.h"
#include "mlir/Dialect/SCF/IR/SCF.h"
#include "mlir/Dialect/Vector/IR/VectorOps.h"
#include "mlir/Pass/Pass.h"
#include "mlir/Pass/PassManager.h"

#include <optional>

namespace mlir::osl {

/// How math ops are computed (osl-approximate-math's `level`, osl-run's
/// --math=). Every level gives bit-identical results at every width.
enum class MathLevel {
  Fast,       ///< per op the faster of OSL's and MLIR's; bounds in bench/MATH.md
  Default,    ///< OSL's own algorithms: reproduces OSL's results
  Precise,    ///< f64 libm per lane rounded to f32
  Polynomial, ///< MLIR's approximations for every op (measured, not a --math)
  Double,     ///< precise math and every float value in f64 (the reference
              ///< for whole-shader errors; osl-evaluate-in-double)
};
/// "fast", "default", "precise" or "double" (osl-run's --math); nullopt
/// otherwise.
std::optional<MathLevel> parseMathLevel(llvm::StringRef name);
const char *mathLevelName(MathLevel level);

/// osl-fold-constants' patterns: lane operations on constants evaluated as
/// the kernel would, selects and ifs on constant conditions decided.
void populateFoldConstantsPatterns(RewritePatternSet &patterns);

#define GEN_PASS_DECL
#include "OslTransforms/Passes.h.inc"

/// osl-derivatives told which dual routines are compiled already: those
/// are declared, not built (OslLanes/LibraryFunctions.h).
std::unique_ptr<Pass> createDerivatives(const DerivativesOptions &options,
                                        LibraryObjectAvailable available);

#define GEN_PASS_REGISTRATION
#include "OslTransforms/Passes.h.inc"

} // namespace mlir::osl

#endif // OSLTRANSFORMS_PASSES_H
