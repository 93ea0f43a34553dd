//===- FoldConstants.cpp - Evaluate osl operations on constants -----------===//
//
// Folding goes through the same LaneMath builders as the lowering, then
// arith's folders: a folded value has exactly the bits the kernel would
// have computed at run time, at every width, which a second implementation
// of OSL's edge rules (safe division, int conversion...) could not promise.
//
//===----------------------------------------------------------------------===//
#include "OslDialect/OslDialect.h"
#include "OslLanes/LaneMath.h"
#include "OslTransforms/Passes.h"

#include "mlir/IR/Matchers.h"
#include "mlir/IR/PatternMatch.h"
#include "mlir/Transforms/GreedyPatternRewriteDriver.h"

namespace mlir::osl {
#define GEN_PASS_DEF_FOLDCONSTANTS
#include "OslTransforms/Passes.h.inc"
} // namespace mlir::osl

using namespace mlir;
using namespace mlir::osl;

namespace {

using LaneFn = Value (*)(OpBuilder &, Location, ValueRange);

/// A uniform constant's components as scalar constants (one for a scalar,
/// three for a triple); empty if `v` is not a constant.
SmallVector<Value> constantComponents(PatternRewriter &b, Location loc, Value v) {
  Attribute attr;
  if (isVarying(v.getType()) || !matchPattern(v, m_Constant(&attr)))
    return {};
  if (auto dense = dyn_cast<DenseElementsAttr>(attr)) {
    if (!isTriple(v.getType()))
      return {};
    SmallVector<Value> comps;
    for (APFloat f : dense.getValues<APFloat>())
      comps.push_back(b.create<arith::ConstantOp>(loc, b.getF32FloatAttr(f.convertToFloat())));
    return comps;
  }
  return {v};
}

std::optional<bool> constantBool(Value v) {
  if (auto broadcast = v.getDefiningOp<BroadcastOp>())
    return constantBool(broadcast.getValue());
  llvm::APInt bits;
  if (!matchPattern(v, m_ConstantInt(&bits)) || bits.getBitWidth() != 1)
    return std::nullopt;
  return bits.getBoolValue();
}

bool allConstant(Operation *op) {
  return llvm::all_of(op->getOperands(), [](Value v) {
    return !isVarying(v.getType()) && matchPattern(v, m_Constant());
  });
}

/// A triple from three f32 values (folded by ConstructOfConstants).
Value pack(PatternRewriter &b, Location loc, ArrayRef<Value> comps) {
  if (comps.size() == 1)
    return comps[0];
  return b.create<ConstructOp>(loc, comps[0], comps[1], comps[2]);
}

/// An exactly defined lane op on constants: its LaneMath lowering.
struct LaneOpOnConstants : public RewritePattern {
  LaneOpOnConstants(MLIRContext *ctx, StringRef opName, LaneFn fn)
      : RewritePattern(opName, /*benefit=*/1, ctx), fn(fn) {}

  LogicalResult matchAndRewrite(Operation *op, PatternRewriter &b) const override {
    if (!allConstant(op))
      return failure();
    Location loc = op->getLoc();
    SmallVector<SmallVector<Value>> operands;
    for (Value v : op->getOperands())
      operands.push_back(constantComponents(b, loc, v));
    size_t n = isTriple(getUniformType(op->getResult(0).getType())) ? 3 : 1;
    SmallVector<Value> comps;
    for (size_t c = 0; c < n; ++c) {
      SmallVector<Value> args;
      for (auto &o : operands)
        args.push_back(o.size() == 1 ? o[0] : o[c]);
      comps.push_back(fn(b, loc, args));
    }
    b.replaceOp(op, pack(b, loc, comps));
    return success();
  }
  LaneFn fn;
};

/// Triples compare equal when every component does, as in the lowering.
struct CmpOfConstants : public OpRewritePattern<CmpOp> {
  using OpRewritePattern::OpRewritePattern;
  LogicalResult matchAndRewrite(CmpOp op, PatternRewriter &b) const override {
    if (!allConstant(op))
      return failure();
    Location loc = op.getLoc();
    SmallVector<Value> lhs = constantComponents(b, loc, op.getLhs());
    SmallVector<Value> rhs = constantComponents(b, loc, op.getRhs());
    b.replaceOp(op, lane::compareComponents(b, loc, stringifyCmpPredicate(op.getPredicate()), lhs,
                                            rhs, op.getUnordered()));
    return success();
  }
};

struct ConvertOfConstant : public OpRewritePattern<ConvertOp> {
  using OpRewritePattern::OpRewritePattern;
  LogicalResult matchAndRewrite(ConvertOp op, PatternRewriter &b) const override {
    if (!allConstant(op))
      return failure();
    Location loc = op.getLoc();
    Type to = getUniformType(op.getType());
    if (isTriple(to)) {
      Value f = lane::convert(b, loc, op.getValue(), b.getF32Type());
      b.replaceOp(op, pack(b, loc, {f, f, f}));
      return success();
    }
    b.replaceOp(op, lane::convert(b, loc, op.getValue(), to));
    return success();
  }
};

struct ConstructOfConstants : public OpRewritePattern<ConstructOp> {
  using OpRewritePattern::OpRewritePattern;
  LogicalResult matchAndRewrite(ConstructOp op, PatternRewriter &b) const override {
    SmallVector<float> xyz;
    for (Value v : op->getOperands()) {
      FloatAttr f;
      if (isVarying(v.getType()) || !matchPattern(v, m_Constant(&f)))
        return failure();
      xyz.push_back(f.getValue().convertToFloat());
    }
    auto type = VectorType::get({3}, b.getF32Type());
    b.replaceOpWithNewOp<arith::ConstantOp>(op, DenseElementsAttr::get(type, ArrayRef(xyz)));
    return success();
  }
};

struct ExtractOfKnownTriple : public OpRewritePattern<ExtractOp> {
  using OpRewritePattern::OpRewritePattern;
  LogicalResult matchAndRewrite(ExtractOp op, PatternRewriter &b) const override {
    int64_t index = op.getIndex();
    if (auto construct = op.getVector().getDefiningOp<ConstructOp>()) {
      b.replaceOp(op, construct->getOperand(index));
      return success();
    }
    SmallVector<Value> comps = constantComponents(b, op.getLoc(), op.getVector());
    if (comps.size() != 3)
      return failure();
    b.replaceOp(op, comps[index]);
    return success();
  }
};

/// Whether `v`'s type may still change in osl-varying-propagation: it is a
/// loop's (or an if's) result or block argument, typed uniform until the
/// pass finds it varying, or computed from one (looked up a few ops back).
bool typePending(Value v, int depth = 6) {
  Operation *def = v.getDefiningOp();
  if (!def || def->getNumRegions() > 0)
    return true;
  if (depth == 0)
    return def->getNumOperands() > 0;
  return llvm::any_of(def->getOperands(),
                      [&](Value operand) { return typePending(operand, depth - 1); });
}

/// `v` where a value of `type` was. A value whose type is pending that
/// replaces a varying one is broadcast, so its users (a derivative,
/// luminance) keep types that verify; the broadcast folds once the value
/// is varying. Anything else replaces as it is, so that what folded away
/// no longer makes its users varying.
Value asTypeOf(PatternRewriter &b, Location loc, Value v, Type type) {
  if (v.getType() == type || !isa<VaryingType>(type) || isa<VaryingType>(v.getType()) ||
      !typePending(v))
    return v;
  return b.create<BroadcastOp>(loc, type, v);
}

struct SelectOnConstant : public OpRewritePattern<SelectOp> {
  using OpRewritePattern::OpRewritePattern;
  LogicalResult matchAndRewrite(SelectOp op, PatternRewriter &b) const override {
    std::optional<bool> cond = constantBool(op.getCondition());
    if (!cond)
      return failure();
    b.replaceOp(op, asTypeOf(b, op.getLoc(), *cond ? op.getTrueValue() : op.getFalseValue(),
                             op.getType()));
    return success();
  }
};

/// The arm a constant condition takes replaces the if.
struct IfOnConstant : public OpRewritePattern<IfOp> {
  using OpRewritePattern::OpRewritePattern;
  LogicalResult matchAndRewrite(IfOp op, PatternRewriter &b) const override {
    std::optional<bool> cond = constantBool(op.getCondition());
    if (!cond)
      return failure();
    Block &arm = *cond ? op.getThenRegion().front() : op.getElseRegion().front();
    auto yield = cast<YieldOp>(arm.getTerminator());
    SmallVector<Value> results(yield.getValues());
    b.eraseOp(yield);
    b.inlineBlockBefore(&arm, op);
    b.setInsertionPoint(op);
    for (auto [value, result] : llvm::zip(results, op.getResults()))
      value = asTypeOf(b, op.getLoc(), value, result.getType());
    b.replaceOp(op, results);
    return success();
  }
};

} // namespace

void mlir::osl::populateFoldConstantsPatterns(RewritePatternSet &patterns) {
  MLIRContext *ctx = patterns.getContext();
  auto lane = [&](StringRef name, LaneFn fn) { patterns.add<LaneOpOnConstants>(ctx, name, fn); };
  lane(AddOp::getOperationName(), lane::add);
  lane(SubOp::getOperationName(), lane::sub);
  lane(MulOp::getOperationName(), lane::mul);
  lane(DivOp::getOperationName(), lane::div);
  lane(ModOp::getOperationName(), lane::mod);
  lane(NegOp::getOperationName(), lane::neg);
  lane(MinOp::getOperationName(), lane::min);
  lane(MaxOp::getOperationName(), lane::max);
  lane(AbsOp::getOperationName(), lane::abs);
  lane(AndOp::getOperationName(), lane::logicalAnd);
  lane(OrOp::getOperationName(), lane::logicalOr);
  lane(NotOp::getOperationName(), lane::logicalNot);
  lane(BitAndOp::getOperationName(), lane::bitAnd);
  lane(BitOrOp::getOperationName(), lane::bitOr);
  lane(BitXorOp::getOperationName(), lane::bitXor);
  lane(BitNotOp::getOperationName(), lane::bitNot);
  lane(ShlOp::getOperationName(), lane::shl);
  lane(ShrOp::getOperationName(), lane::shr);
  lane(StepOp::getOperationName(), lane::step);
  lane(MixOp::getOperationName(), lane::mix);
  lane(ClampOp::getOperationName(), lane::clamp);
  patterns.add<CmpOfConstants, ConvertOfConstant, ConstructOfConstants, ExtractOfKnownTriple,
               SelectOnConstant, IfOnConstant>(ctx);
  IfOp::getCanonicalizationPatterns(patterns, ctx);
  MulOp::getCanonicalizationPatterns(patterns, ctx); // x * 0 before evaluating
}

namespace {
struct FoldConstantsPass : public mlir::osl::impl::FoldConstantsBase<FoldConstantsPass> {
  void runOnOperation() override {
    RewritePatternSet patterns(&getContext());
    populateFoldConstantsPatterns(patterns);
    if (failed(applyPatternsAndFoldGreedily(getOperation(), std::move(patterns))))
      signalPassFailure();
  }
};
} // namespace
