//===- Pipeline.cpp - Pass registration and the osl-to-llvm pipeline ------===//
#include "OslPipeline/Pipeline.h"
#include "OslConversion/Passes.h"

#include "mlir/Pass/PassRegistry.h"
#include "mlir/Transforms/Passes.h"

using namespace mlir;

namespace {
/// osl-to-llvm's textual options, one per field of OslToLLVMPipelineOptions.
struct OslToLLVMOptions : public PassPipelineOptions<OslToLLVMOptions> {
  Option<int> width{*this, "width", llvm::cl::desc("lanes per batch: 1, 4, 8 or 16"),
                    llvm::cl::init(8)};
  Option<bool> reference{*this, "reference",
                         llvm::cl::desc("one point at a time, no masks (width 1)"),
                         llvm::cl::init(false)};
  Option<bool> countLanes{*this, "count-lanes",
                          llvm::cl::desc("masked blocks report their active lanes"),
                          llvm::cl::init(false)};
  Option<osl::MathLevel> math{
      *this, "math", llvm::cl::desc("how math ops are computed"),
      llvm::cl::init(osl::MathLevel::Default),
      llvm::cl::values(clEnumValN(osl::MathLevel::Fast, "fast", "MLIR's approximations"),
                       clEnumValN(osl::MathLevel::Default, "default", "OSL's algorithms"),
                       clEnumValN(osl::MathLevel::Precise, "precise",
                                  "f64 libm per lane"),
                       clEnumValN(osl::MathLevel::Double, "double",
                                  "everything in f64 (reference)"))};

  Option<bool> inlineLibrary{*this, "inline-library",
                             llvm::cl::desc("library routines inline at each call"),
                             llvm::cl::init(false)};
  Option<bool> outlineEveryRoutine{
      *this, "outline-every-routine",
      llvm::cl::desc("every library routine a function, however small"), llvm::cl::init(false)};
  osl::OslToLLVMPipelineOptions get() const {
    return {width, reference, countLanes, math, inlineLibrary, outlineEveryRoutine,
            /*libraryAvailable=*/nullptr};
  }
};
} // namespace

void mlir::osl::buildOslToLLVMPipeline(OpPassManager &pm,
                                       const OslToLLVMPipelineOptions &options) {
  buildOslLevelPipeline(pm, options);
  buildLoweringPipeline(pm, options);
}

void mlir::osl::buildOslLevelPipeline(OpPassManager &pm,
                                      const OslToLLVMPipelineOptions &options) {
  OpPassManager &fn = pm.nest<func::FuncOp>();
  // Instance values are constants already (the front end bound them); the
  // pass folds the remaining parameters to their defaults.
  fn.addPass(createBindParams());
  // Arithmetic on constants folds before the canonicalizer's own patterns
  // see it, as OSL's runtime optimizer folds (0 - 0 becomes a constant 0,
  // then 0^y is 0).
  fn.addPass(createFoldConstants());
  // Loops over small arrays with constant bounds become straight-line
  // code with constant indices.
  fn.addPass(createUnrollConstantLoops());
  fn.addPass(createCanonicalizerPass());
  if (options.reference)
    fn.addPass(createUniformReference());
  else
    fn.addPass(createVaryingPropagation());
  InsertMaskStackOptions maskOptions;
  maskOptions.countLanes = options.countLanes;
  fn.addPass(createInsertMaskStack(maskOptions));
  fn.addPass(createLaneGroupFilter());
}

void mlir::osl::buildLoweringPipeline(OpPassManager &pm,
                                      const OslToLLVMPipelineOptions &options) {
  buildVectorLevelPipeline(pm, options);
  buildLLVMDialectPipeline(pm, options);
}

void mlir::osl::buildVectorLevelPipeline(OpPassManager &pm,
                                         const OslToLLVMPipelineOptions &options) {
  MathLevel math = options.math;
  ConvertToVectorOptions vectorOptions;
  vectorOptions.width = options.reference ? 1 : options.width;
  vectorOptions.referenceMode = options.reference;
  // Not in double evaluation: its rewrite of every f32 value stays within
  // one function.
  InlineLibraryOptions inlineOptions;
  inlineOptions.keepCalls = math != MathLevel::Double && !options.inlineLibrary;
  // A routine compiled already is linked, not built, where it stays a call.
  // Reference mode differentiates routines in place: its values are all
  // uniform, which a dual routine's tangents are not.
  DerivativesOptions derivativeOptions;
  derivativeOptions.dualRoutines = !options.reference;
  LibraryObjectAvailable available = inlineOptions.keepCalls ? options.libraryAvailable : nullptr;
  pm.addPass(createConvertToVector(vectorOptions, available));
  pm.addPass(createDerivatives(derivativeOptions, available));
  if (options.outlineEveryRoutine)
    inlineOptions.inlineOps = 0;
  pm.addPass(createInlineLibrary(inlineOptions));
}

void mlir::osl::buildLLVMDialectPipeline(OpPassManager &pm,
                                         const OslToLLVMPipelineOptions &options) {
  MathLevel math = options.math;
  ApproximateMathOptions mathOptions;
  mathOptions.level = math;
  pm.addPass(createApproximateMath(mathOptions));
  if (math == MathLevel::Double)
    pm.addPass(createEvaluateInDouble());
  pm.addPass(createCanonicalizerPass());
  pm.addPass(createCSEPass());
  if (math == MathLevel::Fast)
    pm.addPass(createContractFma());
  pm.addPass(createLowerToLLVM());
}

void mlir::osl::registerOslPasses() {
  registerOslTransformsPasses();
  registerOslConversionPasses();
  PassPipelineRegistration<OslToLLVMOptions>(
      "osl-to-llvm", "Lower an osl shader to an LLVM-dialect batch kernel",
      [](OpPassManager &pm, const OslToLLVMOptions &options) {
        buildOslToLLVMPipeline(pm, options.get());
      });
}
