//===- ConvertToVector.cpp - osl to vector code of width W ----------------===//
//
// Varying values become vectors of W lanes (triples: vector<3 x W x f32>,
// one row per component, so each component is one SIMD register); uniform
// values stay scalar. Each lane-wise op is lowered component by component
// through LaneMath, which builds the same arith ops for scalars and
// vectors. The shader function becomes the batch kernel of
// OslAbi/GlobalsLayout.h. The patterns live by subject beside this file
// (KernelSignature, LaneOps, LibraryCalls, Closures, RuntimeCalls), each
// with its populate function (OslToVector.h).
//
//===----------------------------------------------------------------------===//
#include "OslToVector.h"
#include "OslConversion/Passes.h"

#include "mlir/Dialect/SCF/Transforms/Patterns.h"
#include "mlir/Transforms/DialectConversion.h"

namespace mlir::osl {
#define GEN_PASS_DEF_CONVERTTOVECTOR
#include "OslConversion/Passes.h.inc"
} // namespace mlir::osl

using namespace mlir;
using namespace mlir::osl;
using namespace mlir::osl::lowering;

namespace {

struct ConvertToVectorPass
    : public mlir::osl::impl::ConvertToVectorBase<ConvertToVectorPass> {
  using mlir::osl::impl::ConvertToVectorBase<ConvertToVectorPass>::ConvertToVectorBase;
  ConvertToVectorPass(const ConvertToVectorOptions &options, LibraryObjectAvailable available)
      : ConvertToVectorBase(options), available(std::move(available)) {}

  /// Which library routines are compiled already (none without).
  LibraryObjectAvailable available;

  void runOnOperation() override {
    if (width != 1 && width != 4 && width != 8 && width != 16) {
      getOperation().emitError("width must be 1, 4, 8 or 16, got ") << width;
      return signalPassFailure();
    }
    SmallVector<func::FuncOp> shaders;
    getOperation().walk([&](func::FuncOp f) {
      if (f.getNumArguments() == 0 && !f.isExternal())
        shaders.push_back(f);
    });
    if (shaders.size() != 1) {
      getOperation().emitError("expected one shader function, found ")
          << shaders.size();
      return signalPassFailure();
    }
    llvm::DenseMap<Operation *, int64_t> outputRow;
    int64_t row = 0;
    shaders[0].walk([&](OutputOp out) {
      outputRow[out] = row;
      row += isTriple(getUniformType(out.getValue().getType())) ? 3 : 1;
    });
    if (failed(checkSplineKnotCounts(shaders[0])))
      return signalPassFailure();
    makeKernelSignature(shaders[0]);

    MLIRContext *ctx = &getContext();
    VaryingTypeConverter converter(width);
    ConversionTarget target(*ctx);
    target.addIllegalDialect<OslDialect>();
    target.addLegalOp<LaneDerivOp, LanePickOp, CodegenFenceOp>();
    LibraryRoutineNeeds needs(shaders[0], orAssumedCompiled(available, assumeCompiled),
                              referenceMode);
    target.addLegalDialect<arith::ArithDialect, math::MathDialect,
                           vector::VectorDialect, LLVM::LLVMDialect,
                           func::FuncDialect>();
    RewritePatternSet patterns(ctx);
    populateKernelPatterns(converter, patterns, outputRow);
    populateLaneOpPatterns(converter, patterns, referenceMode);
    populateLibraryCallPatterns(converter, patterns);
    populateNoisePatterns(converter, patterns, needs);
    populateSplineInversePatterns(converter, patterns, needs);
    populateClosurePatterns(converter, patterns);
    populateRuntimeCallPatterns(converter, patterns);
    scf::populateSCFStructuralTypeConversionsAndLegality(converter, patterns, target);
    if (failed(applyPartialConversion(getOperation(), target, std::move(patterns))))
      return signalPassFailure();
    resetMessagesOnEntry(getOperation(), shaders[0]);
  }
};

} // namespace

std::unique_ptr<Pass> mlir::osl::createConvertToVector(const ConvertToVectorOptions &options,
                                                       LibraryObjectAvailable available) {
  return std::make_unique<ConvertToVectorPass>(options, std::move(available));
}
