//===- Pipeline.h - From front-end output to an LLVM-dialect kernel -*- C++ -*-===//
//
// The pass pipeline ShaderCompiler runs and osl-opt registers as
// osl-to-llvm: the osl-level transforms (OslTransforms), then the
// conversions (OslConversion).
//
//===----------------------------------------------------------------------===//
#ifndef OSLPIPELINE_PIPELINE_H
#define OSLPIPELINE_PIPELINE_H

#include "OslLanes/LibraryFunctions.h"
#include "OslTransforms/Passes.h"

#include "mlir/Pass/PassManager.h"

namespace mlir::osl {

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
  /// Library routines (noise) inline at each call, not in functions the
  /// JIT compiles once (osl-inline-library's keep-calls=false).
  bool inlineLibrary = false;
  /// Every library routine a function, however small (osl-inline-library's
  /// inline-ops=0): how the prebuilt library is built, so that it holds the
  /// routines a shader calls too often to inline.
  bool outlineEveryRoutine = false;
  /// Which library routines are compiled already, by recipe (the
  /// compiler's library objects): those no call needs the code of are
  /// declared, not built (OslLanes/LibraryFunctions.h). Null: all are built.
  LibraryObjectAvailable libraryAvailable;
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

/// The lowering's two steps: to the vector dialect with each library
/// routine a function (osl-inline-library keeps the calls that gain), then on to the LLVM dialect.
/// Between them a JIT turns the library functions whose objects it already
/// has into declarations (OslCompiler/LibraryObjects.h), so the second step
/// never lowers their bodies.
void buildVectorLevelPipeline(OpPassManager &pm, const OslToLLVMPipelineOptions &options);
void buildLLVMDialectPipeline(OpPassManager &pm, const OslToLLVMPipelineOptions &options);


/// Registers every pass (transforms and conversions) and the `osl-to-llvm`
/// pipeline with mlir-opt style tools.
void registerOslPasses();

} // namespace mlir::osl

#endif // OSLPIPELINE_PIPELINE_H
