//===- Passes.h - osl-mlir passes -------------------------------*- C++ -*-===//
#ifndef OSLTRANSFORMS_PASSES_H
#define OSLTRANSFORMS_PASSES_H

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

#define GEN_PASS_DECL
#include "OslTransforms/Passes.h.inc"

/// The whole chain from front-end output to the LLVM dialect at `width`.
/// `reference`: one point at a time with ordinary branches (width 1, no
/// masks), the oracle of the differential tester. `countLanes`: masked
/// blocks report their active lanes (osl-run --lane-stats). `math`: how
/// math ops are computed (osl-approximate-math's level; Double also runs
/// osl-evaluate-in-double).
void buildOslToLLVMPipeline(OpPassManager &pm, int width, bool reference = false,
                            bool countLanes = false, MathLevel math = MathLevel::Default);

/// Its two halves. The osl-level passes (parameters, uniformity, masks)
/// are where op verifiers report the shader's own errors (an option that
/// must be uniform is varying), so a JIT verifies after each of them; the
/// lowering to the LLVM dialect works on IR ten times larger and can be
/// verified once at its end.
void buildOslLevelPipeline(OpPassManager &pm, bool reference = false,
                           bool countLanes = false);
void buildLoweringPipeline(OpPassManager &pm, int width, bool reference = false,
                           MathLevel math = MathLevel::Default);

/// Registers every pass and the `osl-to-llvm` pipeline with mlir-opt style
/// tools.
void registerOslPasses();

#define GEN_PASS_REGISTRATION
#include "OslTransforms/Passes.h.inc"

} // namespace mlir::osl

#endif // OSLTRANSFORMS_PASSES_H
