//===- ContractFma.cpp - a*b+c as one fused multiply-add (--math=fast) ----===//
#include "OslTransforms/Passes.h"

#include "mlir/Dialect/Arith/IR/Arith.h"
#include "mlir/Dialect/Math/IR/Math.h"
#include "mlir/IR/PatternMatch.h"
#include "mlir/Transforms/GreedyPatternRewriteDriver.h"

namespace mlir::osl {
#define GEN_PASS_DEF_CONTRACTFMA
#include "OslTransforms/Passes.h.inc"
} // namespace mlir::osl

using namespace mlir;

namespace {

/// The product `v` is, if it feeds nothing else.
arith::MulFOp singleUseProduct(Value v) {
  auto mul = v.getDefiningOp<arith::MulFOp>();
  return mul && mul->hasOneUse() ? mul : arith::MulFOp();
}

/// addf(mulf(a, b), c) and addf(c, mulf(a, b)) -> fma(a, b, c).
struct FuseAdd : public OpRewritePattern<arith::AddFOp> {
  using OpRewritePattern::OpRewritePattern;
  LogicalResult matchAndRewrite(arith::AddFOp add, PatternRewriter &rewriter) const override {
    for (auto [product, addend] : {std::pair(add.getLhs(), add.getRhs()),
                                   std::pair(add.getRhs(), add.getLhs())})
      if (arith::MulFOp mul = singleUseProduct(product)) {
        rewriter.replaceOpWithNewOp<math::FmaOp>(add, mul.getLhs(), mul.getRhs(), addend);
        return success();
      }
    return failure();
  }
};

/// subf(mulf(a, b), c) -> fma(a, b, -c); subf(c, mulf(a, b)) -> fma(-a, b, c).
struct FuseSub : public OpRewritePattern<arith::SubFOp> {
  using OpRewritePattern::OpRewritePattern;
  LogicalResult matchAndRewrite(arith::SubFOp sub, PatternRewriter &rewriter) const override {
    Location loc = sub.getLoc();
    if (arith::MulFOp mul = singleUseProduct(sub.getLhs())) {
      Value negated = rewriter.create<arith::NegFOp>(loc, sub.getRhs());
      rewriter.replaceOpWithNewOp<math::FmaOp>(sub, mul.getLhs(), mul.getRhs(), negated);
      return success();
    }
    if (arith::MulFOp mul = singleUseProduct(sub.getRhs())) {
      Value negated = rewriter.create<arith::NegFOp>(loc, mul.getLhs());
      rewriter.replaceOpWithNewOp<math::FmaOp>(sub, negated, mul.getRhs(), sub.getLhs());
      return success();
    }
    return failure();
  }
};

struct ContractFmaPass : public mlir::osl::impl::ContractFmaBase<ContractFmaPass> {
  void runOnOperation() override {
    RewritePatternSet patterns(&getContext());
    patterns.add<FuseAdd, FuseSub>(&getContext());
    GreedyRewriteConfig config;
    // Keep the kernel's blocks as they are (see osl-lower-to-llvm).
    config.enableRegionSimplification = GreedySimplifyRegionLevel::Disabled;
    if (failed(applyPatternsAndFoldGreedily(getOperation(), std::move(patterns), config)))
      signalPassFailure();
  }
};

} // namespace
