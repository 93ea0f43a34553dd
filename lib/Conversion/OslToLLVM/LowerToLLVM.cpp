//===- LowerToLLVM.cpp - vector/arith/math/scf to the LLVM dialect --------===//
//
// Math first becomes polynomial approximations in the same vector types
// (so a 16-wide sin stays in zmm registers instead of 16 sinf calls, and
// the same polynomial runs at every width), then everything is converted
// to LLVM in one full conversion.
//
//===----------------------------------------------------------------------===//
#include "OslConversion/Passes.h"
#include "OslSupport/PatternRoots.h"

#include "mlir/Conversion/ArithToLLVM/ArithToLLVM.h"
#include "mlir/Conversion/ControlFlowToLLVM/ControlFlowToLLVM.h"
#include "mlir/Conversion/FuncToLLVM/ConvertFuncToLLVM.h"
#include "mlir/Conversion/LLVMCommon/ConversionTarget.h"
#include "mlir/Conversion/LLVMCommon/TypeConverter.h"
#include "mlir/Conversion/MathToLLVM/MathToLLVM.h"
#include "mlir/Conversion/ReconcileUnrealizedCasts/ReconcileUnrealizedCasts.h"
#include "mlir/Pass/PassManager.h"
#include "mlir/Conversion/SCFToControlFlow/SCFToControlFlow.h"
#include "mlir/Conversion/VectorToLLVM/ConvertVectorToLLVM.h"
#include "mlir/Dialect/ControlFlow/IR/ControlFlow.h"
#include "mlir/Dialect/Math/Transforms/Passes.h"
#include "mlir/Dialect/LLVMIR/LLVMDialect.h"
#include "mlir/Dialect/Vector/Transforms/LoweringPatterns.h"
#include "mlir/IR/Matchers.h"
#include "mlir/Transforms/DialectConversion.h"
#include "mlir/Transforms/GreedyPatternRewriteDriver.h"

namespace mlir::osl {
#define GEN_PASS_DEF_LOWERTOLLVM
#include "OslConversion/Passes.h.inc"
} // namespace mlir::osl

using namespace mlir;

namespace {


LogicalResult lowerStructuredControlFlow(ModuleOp module) {
  RewritePatternSet patterns(module.getContext());
  populateSCFToControlFlowConversionPatterns(patterns);
  ConversionTarget target(*module.getContext());
  target.addIllegalDialect<scf::SCFDialect>();
  target.markUnknownOpDynamicallyLegal([](Operation *) { return true; });
  return applyPartialConversion(module, target, std::move(patterns));
}

/// The shift amount of `shift` when it is the same constant in every lane.
std::optional<uint64_t> constantShift(Value amount) {
  APInt value;
  if (!matchPattern(amount, m_ConstantInt(&value)))
    return std::nullopt;
  return value.getZExtValue();
}

/// (x << k) | (x >> (bits - k)) becomes one funnel shift, LLVM's rotate:
/// the noise hashes are mostly rotates, and handing them to codegen as three
/// instructions each left its instruction selection to find them again
/// (a quarter of marble's kernel is rotates).
void formRotates(ModuleOp module) {
  SmallVector<arith::OrIOp> ors;
  module.walk([&](arith::OrIOp op) { ors.push_back(op); });
  for (arith::OrIOp op : ors) {
    for (int order = 0; order < 2; ++order) {
      auto left = op->getOperand(order).getDefiningOp<arith::ShLIOp>();
      auto right = op->getOperand(1 - order).getDefiningOp<arith::ShRUIOp>();
      if (!left || !right || left.getLhs() != right.getLhs())
        continue;
      std::optional<uint64_t> k = constantShift(left.getRhs());
      std::optional<uint64_t> rest = constantShift(right.getRhs());
      unsigned bits = getElementTypeOrSelf(op.getType()).getIntOrFloatBitWidth();
      if (!k || !rest || *k == 0 || *k >= bits || *k + *rest != bits)
        continue;
      OpBuilder b(op);
      Value x = left.getLhs();
      Value rotated = b.create<LLVM::FshlOp>(op.getLoc(), op.getType(), x, x, left.getRhs());
      op.replaceAllUsesWith(rotated);
      op.erase();
      if (left->use_empty())
        left.erase();
      if (right->use_empty())
        right.erase();
      break;
    }
  }
}

LogicalResult convertToLLVM(ModuleOp module) {
  MLIRContext *ctx = module.getContext();
  {
    // n-D vector ops (triples of W lanes) become 1-D ones LLVM understands.
    RewritePatternSet patterns(ctx);
    vector::populateVectorBroadcastLoweringPatterns(patterns);
    vector::populateVectorMaskOpLoweringPatterns(patterns);
    vector::populateVectorShapeCastLoweringPatterns(patterns);
    // Only these rewrites: the driver's default block merging (Aggressive
    // region simplification) merged blocks of the unstructured control
    // flow whose arguments then no longer matched their branches (the
    // differential tester's seed 3619, in reference mode).
    GreedyRewriteConfig config;
    config.enableRegionSimplification = GreedySimplifyRegionLevel::Disabled;
    if (osl::hasPatternRoot(module, patterns) &&
        failed(applyPatternsAndFoldGreedily(module, std::move(patterns), config)))
      return failure();
  }
  LLVMTypeConverter converter(ctx);
  RewritePatternSet patterns(ctx);
  arith::populateArithToLLVMConversionPatterns(converter, patterns);
  populateMathToLLVMConversionPatterns(converter, patterns);
  populateVectorToLLVMConversionPatterns(converter, patterns);
  populateFuncToLLVMConversionPatterns(converter, patterns);
  cf::populateControlFlowToLLVMConversionPatterns(converter, patterns);
  LLVMConversionTarget target(*ctx);
  target.addLegalOp<ModuleOp>();
  return applyFullConversion(module, target, std::move(patterns));
}

struct LowerToLLVMPass
    : public mlir::osl::impl::LowerToLLVMBase<LowerToLLVMPass> {
  void runOnOperation() override {
    ModuleOp module = getOperation();
    formRotates(module);
    if (failed(lowerStructuredControlFlow(module)) ||
        failed(convertToLLVM(module)))
      return signalPassFailure();
    // Casts between converted and unconverted types pair up and vanish.
    OpPassManager cleanup(ModuleOp::getOperationName());
    cleanup.addPass(createReconcileUnrealizedCastsPass());
    if (failed(runPipeline(cleanup, module)))
      signalPassFailure();
  }
};

} // namespace
