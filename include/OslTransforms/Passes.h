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

/// How the chain from front-end output to the LLVM dialect lowers a shader.
/// ShaderCompiler fills it from its CompileOptions; osl-opt's
/// --osl-to-llvm="width=8 reference=false count-lanes=false math=default"
/// from its options.
struct OslToLLVMPipelineOptions {
  /// Lanes per batch: 1, 4, 8 or 16.
  int width = 8;
  /// One point at a time with ordinary branches (width 1, no masks), the
  /// oracle of the differential tester.
  bool reference = false;
  /// Masked blocks report their active lanes (osl-run --lane-stats).
  bool countLanes = false;
  /// How math ops are computed (osl-approximate-math's level; Double also
  /// runs osl-evaluate-in-double).
  MathLevel math = MathLevel::Default;
};

/// The whole chain.
void buildOslToLLVMPipeline(OpPassManager &pm, const OslToLLVMPipelineOptions &options);

/// Its two halves. The osl-level passes (parameters, uniformity, masks)
/// are where op verifiers report the shader's own errors (an option that
/// must be uniform is varying), so a JIT verifies after each of them; the
/// lowering to the LLVM dialect works on IR ten times larger and can be
/// verified once at its end.
void buildOslLevelPipeline(OpPassManager &pm, const OslToLLVMPipelineOptions &options);
void buildLoweringPipeline(OpPassManager &pm, const OslToLLVMPipelineOptions &options);

/// Registers every pass and the `osl-to-llvm` pipeline with mlir-opt style
/// tools.
void registerOslPasses();

#define GEN_PASS_REGISTRATION
#include "OslTransforms/Passes.h.inc"

} // namespace mlir::osl

#endif // OSLTRANSFORMS_PASSES_H
