//===- LaneOps.cpp - osl ops that work lane by lane -------------------------===//
//
// Arithmetic, math, comparisons, conversions, element access, masks and
// derivative requests: each becomes the same lane computation (LaneMath) on
// scalars (uniform values) or vectors of W lanes (varying ones).
//
//===----------------------------------------------------------------------===//
#include "OslToVector.h"

#include "OslLanes/LaneMath.h"
#include "mlir/Dialect/Arith/IR/Arith.h"
#include "mlir/IR/Matchers.h"

using namespace mlir;
using namespace mlir::osl;
using namespace mlir::osl::lowering;

namespace {

/// Lower a lane-wise op by applying a LaneMath function to each component.
/// Scalar operands of triple ops (a select's condition) repeat per component.
template <typename OpTy>
struct ComponentwiseLowering : public OslPattern<OpTy> {
  ComponentwiseLowering(const VaryingTypeConverter &converter, MLIRContext *ctx,
                        LaneFn fn)
      : OslPattern<OpTy>(converter, ctx), fn(fn) {}

  LogicalResult matchAndRewrite(OpTy op, typename OpTy::Adaptor adaptor,
                                ConversionPatternRewriter &rewriter) const override {
    Location loc = op.getLoc();
    Type resultType = op->getResult(0).getType();
    bool varying = isVarying(resultType);
    Components lanes{rewriter, loc, this->width};
    size_t ncomp = isTriple(getUniformType(resultType)) ? 3 : 1;
    SmallVector<SmallVector<Value>> operands =
        lanes.unpackAll(adaptor.getOperands(), op->getOperands(), varying);
    SmallVector<Value> comps;
    for (size_t c = 0; c < ncomp; ++c) {
      SmallVector<Value> args;
      for (auto &o : operands)
        args.push_back(o.size() == 1 ? o[0] : o[c]);
      comps.push_back(fn(rewriter, loc, args));
    }
    rewriter.replaceOp(op, lanes.pack(comps, this->convert(resultType)));
    return success();
  }
  LaneFn fn;
};

/// osl.deriv: uniform values have derivative 0; varying ones become
/// osl.lane_deriv for osl-derivatives.
struct DerivLowering : public OslPattern<DerivOp> {
  DerivLowering(const VaryingTypeConverter &converter, MLIRContext *ctx, bool referenceMode)
      : OslPattern(converter, ctx), referenceMode(referenceMode) {}
  bool referenceMode;
  LogicalResult matchAndRewrite(DerivOp op, OpAdaptor adaptor,
                                ConversionPatternRewriter &rewriter) const override {
    Type type = convert(op.getType());
    // Uniform values have no derivatives, except in reference mode, where
    // every value is uniform (one point at a time).
    if (!isVarying(op.getValue().getType()) && !referenceMode)
      rewriter.replaceOpWithNewOp<arith::ConstantOp>(op, rewriter.getZeroAttr(type));
    else
      rewriter.replaceOpWithNewOp<LaneDerivOp>(op, adaptor.getValue().getType(),
                                               adaptor.getValue(), op.getAxis());
    return success();
  }
};

struct BatchMaskLowering : public OslPattern<BatchMaskOp> {
  using OslPattern::OslPattern;
  LogicalResult matchAndRewrite(BatchMaskOp op, OpAdaptor,
                                ConversionPatternRewriter &rewriter) const override {
    rewriter.replaceOp(op, activeLanes(rewriter, op.getLoc(), op, width));
    return success();
  }
};

struct AnyLowering : public OslPattern<AnyOp> {
  using OslPattern::OslPattern;
  LogicalResult matchAndRewrite(AnyOp op, OpAdaptor adaptor,
                                ConversionPatternRewriter &rewriter) const override {
    if (!isVarying(op.getMask().getType())) {
      rewriter.replaceOp(op, adaptor.getMask());
      return success();
    }
    auto any = rewriter.replaceOpWithNewOp<vector::ReductionOp>(
        op, vector::CombiningKind::OR, adaptor.getMask());
    if (op->hasAttr(kColdArmAttr))
      any->setAttr(kColdArmAttr, rewriter.getUnitAttr());
    return success();
  }
};

struct BroadcastLowering : public OslPattern<BroadcastOp> {
  using OslPattern::OslPattern;
  LogicalResult matchAndRewrite(BroadcastOp op, OpAdaptor adaptor,
                                ConversionPatternRewriter &rewriter) const override {
    Components lanes{rewriter, op.getLoc(), width};
    rewriter.replaceOp(op, lanes.pack(lanes.unpack(adaptor.getValue(),
                                                   op.getValue().getType(), true),
                                      convert(op.getType())));
    return success();
  }
};

struct CmpLowering : public OslPattern<CmpOp> {
  using OslPattern::OslPattern;
  LogicalResult matchAndRewrite(CmpOp op, OpAdaptor adaptor,
                                ConversionPatternRewriter &rewriter) const override {
    Location loc = op.getLoc();
    bool varying = isVarying(op.getType());
    Components lanes{rewriter, loc, width};
    auto lhs = lanes.unpack(adaptor.getLhs(), op.getLhs().getType(), varying);
    auto rhs = lanes.unpack(adaptor.getRhs(), op.getRhs().getType(), varying);
    rewriter.replaceOp(op, lane::compareComponents(rewriter, loc, stringifyCmpPredicate(op.getPredicate()), lhs, rhs,
                                                           op.getUnordered()));
    return success();
  }
};

struct ConvertLowering : public OslPattern<ConvertOp> {
  using OslPattern::OslPattern;
  LogicalResult matchAndRewrite(ConvertOp op, OpAdaptor adaptor,
                                ConversionPatternRewriter &rewriter) const override {
    Location loc = op.getLoc();
    Components lanes{rewriter, loc, width};
    Type to = getUniformType(op.getType());
    bool varying = isVarying(op.getType());
    Value x = lanes.unpack(adaptor.getValue(), op.getValue().getType(), varying)[0];
    if (isTriple(to)) {
      Value f = lane::convert(rewriter, loc, x, rewriter.getF32Type());
      rewriter.replaceOp(op, lanes.pack({f, f, f}, convert(op.getType())));
      return success();
    }
    rewriter.replaceOp(op, lane::convert(rewriter, loc, x, to));
    return success();
  }
};

struct ConstructLowering : public OslPattern<ConstructOp> {
  using OslPattern::OslPattern;
  LogicalResult matchAndRewrite(ConstructOp op, OpAdaptor adaptor,
                                ConversionPatternRewriter &rewriter) const override {
    Components lanes{rewriter, op.getLoc(), width};
    bool varying = isVarying(op.getType());
    SmallVector<Value> comps;
    for (auto &c : lanes.unpackAll(adaptor.getOperands(), op->getOperands(), varying))
      comps.push_back(c[0]);
    rewriter.replaceOp(op, lanes.pack(comps, convert(op.getType())));
    return success();
  }
};

struct ExtractLowering : public OslPattern<ExtractOp> {
  using OslPattern::OslPattern;
  LogicalResult matchAndRewrite(ExtractOp op, OpAdaptor adaptor,
                                ConversionPatternRewriter &rewriter) const override {
    Components lanes{rewriter, op.getLoc(), width};
    auto comps = lanes.unpack(adaptor.getVector(), op.getVector().getType(),
                              isVarying(op.getType()));
    rewriter.replaceOp(op, comps[op.getIndex()]);
    return success();
  }
};

struct InsertLowering : public OslPattern<InsertOp> {
  using OslPattern::OslPattern;
  LogicalResult matchAndRewrite(InsertOp op, OpAdaptor adaptor,
                                ConversionPatternRewriter &rewriter) const override {
    Components lanes{rewriter, op.getLoc(), width};
    bool varying = isVarying(op.getType());
    auto comps = lanes.unpack(adaptor.getVector(), op.getVector().getType(), varying);
    comps[op.getIndex()] =
        lanes.unpack(adaptor.getValue(), op.getValue().getType(), varying)[0];
    rewriter.replaceOp(op, lanes.pack(comps, convert(op.getType())));
    return success();
  }
};

/// osl.pick: one osl.lane_pick per component, over the elements made
/// varying where the result is.
struct PickLowering : public OslPattern<PickOp> {
  using OslPattern::OslPattern;
  LogicalResult matchAndRewrite(PickOp op, OpAdaptor adaptor,
                                ConversionPatternRewriter &rewriter) const override {
    Location loc = op.getLoc();
    bool varying = isVarying(op.getType());
    Components lanes{rewriter, loc, width};
    SmallVector<SmallVector<Value>> elements =
        lanes.unpackAll(adaptor.getElements(), op.getElements(), varying);
    SmallVector<Value> comps;
    for (size_t c = 0; c < elements.front().size(); ++c) {
      SmallVector<Value> column;
      for (auto &e : elements)
        column.push_back(e[c]);
      comps.push_back(rewriter.create<LanePickOp>(loc, column.front().getType(),
                                                  adaptor.getIndex(), column));
    }
    rewriter.replaceOp(op, lanes.pack(comps, convert(op.getType())));
    return success();
  }
};

/// osl.first_lane: the lowest set lane of the mask selects the value.
struct FirstLaneLowering : public OslPattern<FirstLaneOp> {
  using OslPattern::OslPattern;
  LogicalResult matchAndRewrite(FirstLaneOp op, OpAdaptor adaptor,
                                ConversionPatternRewriter &rewriter) const override {
    if (!isVarying(op.getValue().getType())) {
      rewriter.replaceOp(op, adaptor.getValue());
      return success();
    }
    Location loc = op.getLoc();
    Value mask = adaptor.getMask();
    if (!isa<VectorType>(mask.getType()))
      mask = lane::broadcast(rewriter, loc, mask, width);
    Value bits = maskBits(rewriter, loc, mask);
    Value lead = rewriter.create<LLVM::CountTrailingZerosOp>(loc, bits.getType(), bits, false);
    // Each component (a triple's three) at the lead lane.
    Components lanes{rewriter, loc, width};
    SmallVector<Value> leads;
    for (Value c : lanes.unpack(adaptor.getValue(), op.getValue().getType(), true))
      leads.push_back(rewriter.create<vector::ExtractElementOp>(loc, c, lead));
    rewriter.replaceOp(op, lanes.pack(leads, convert(op.getType())));
    return success();
  }
};

/// osl.is_constant: answered now that parameters are bound and constants
/// folded, as OSL answers isconstant() after its runtime optimizer.
struct IsConstantLowering : public OslPattern<IsConstantOp> {
  using OslPattern::OslPattern;
  LogicalResult matchAndRewrite(IsConstantOp op, OpAdaptor adaptor,
                                ConversionPatternRewriter &rewriter) const override {
    bool constant = matchPattern(op.getValue(), m_Constant());
    rewriter.replaceOpWithNewOp<arith::ConstantIntOp>(op, constant ? 1 : 0, 32);
    return success();
  }
};

} // namespace

void mlir::osl::lowering::populateLaneOpPatterns(const VaryingTypeConverter &converter,
                                                 RewritePatternSet &patterns,
                                                 bool referenceMode) {
  MLIRContext *ctx = patterns.getContext();
#define LANE(Op, fn) patterns.add<ComponentwiseLowering<Op>>(converter, ctx, &lane::fn)
  LANE(AddOp, add); LANE(SubOp, sub); LANE(MulOp, mul); LANE(DivOp, div);
  LANE(ModOp, mod); LANE(NegOp, neg); LANE(MinOp, min); LANE(MaxOp, max);
  LANE(AbsOp, abs); LANE(AndOp, logicalAnd); LANE(OrOp, logicalOr);
  LANE(NotOp, logicalNot); LANE(BitAndOp, bitAnd); LANE(BitOrOp, bitOr);
  LANE(BitXorOp, bitXor); LANE(BitNotOp, bitNot); LANE(ShlOp, shl);
  LANE(ShrOp, shr); LANE(SinOp, sin); LANE(CosOp, cos); LANE(TanOp, tan);
  LANE(AsinOp, asin); LANE(AcosOp, acos); LANE(AtanOp, atan);
  LANE(Atan2Op, atan2); LANE(ExpOp, exp); LANE(Exp2Op, exp2); LANE(LogOp, log);
  LANE(Log2Op, log2); LANE(Log10Op, log10); LANE(SqrtOp, sqrt);
  LANE(InverseSqrtOp, inverseSqrt); LANE(SinhOp, sinh); LANE(CoshOp, cosh);
  LANE(TanhOp, tanh); LANE(Expm1Op, expm1); LANE(CbrtOp, cbrt); LANE(ErfOp, erf);
  LANE(ErfcOp, erfc); LANE(LogbOp, logb); LANE(LinearStepOp, linearstep);
  LANE(FloorOp, floor); LANE(CeilOp, ceil); LANE(RoundOp, round); LANE(TruncOp, trunc);
  LANE(SignOp, sign); LANE(PowOp, pow); LANE(FmodOp, fmod); LANE(StepOp, step);
  LANE(MixOp, mix); LANE(ClampOp, clamp); LANE(SmoothStepOp, smoothstep);
  LANE(SelectOp, select);
#undef LANE
  patterns.add<BatchMaskLowering, AnyLowering, BroadcastLowering, CmpLowering, ConvertLowering,
               ConstructLowering, ExtractLowering, InsertLowering, PickLowering, FirstLaneLowering,
               IsConstantLowering>(converter, ctx);
  patterns.add<DerivLowering>(converter, ctx, referenceMode);
}
