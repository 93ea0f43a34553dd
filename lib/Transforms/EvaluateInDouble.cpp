//===- EvaluateInDouble.cpp - every float value of the kernel in f64 ------===//
//
// The reference for measuring a whole shader's error (--math=double): after
// osl-approximate-math at the precise level (math ops already glibc's
// double functions), every f32 value the kernel computes becomes f64 --
// arithmetic, comparisons, selects, vector shuffles, loop-carried values --
// so the shader runs in double precision throughout. Only its boundaries
// stay f32: globals and tables are loaded as f32 and extended (exact),
// outputs are rounded once when stored, and a float reinterpreted as bits
// (arith.bitcast, e.g. hashnoise) is first rounded to the f32 the shader
// would have hashed.
//
//===----------------------------------------------------------------------===//
#include "OslDialect/OslDialect.h"
#include "OslTransforms/Passes.h"

#include "mlir/Dialect/SCF/Transforms/Patterns.h"
#include "mlir/Transforms/DialectConversion.h"

namespace mlir::osl {
#define GEN_PASS_DEF_EVALUATEINDOUBLE
#include "OslTransforms/Passes.h.inc"
} // namespace mlir::osl

using namespace mlir;

namespace {

/// f32 -> f64, vector<..xf32> -> vector<..xf64>; everything else unchanged.
struct DoubleTypeConverter : public TypeConverter {
  explicit DoubleTypeConverter(MLIRContext *ctx) {
    addConversion([](Type t) { return t; });
    addConversion([ctx](Float32Type) -> Type { return Float64Type::get(ctx); });
    addConversion([ctx](VectorType v) -> Type {
      return v.getElementType().isF32() ? v.clone(Float64Type::get(ctx)) : v;
    });
    auto extend = [](OpBuilder &b, Type type, ValueRange in, Location loc) -> Value {
      return b.create<arith::ExtFOp>(loc, type, in.front());
    };
    auto round = [](OpBuilder &b, Type type, ValueRange in, Location loc) -> Value {
      return b.create<arith::TruncFOp>(loc, type, in.front());
    };
    addTargetMaterialization(extend);
    addArgumentMaterialization(extend);
    addSourceMaterialization(round);
  }
};

/// Any arith/math/vector op with float operands or results is rebuilt on
/// the converted types (same name and attributes).
struct Retype : public ConversionPattern {
  Retype(const TypeConverter &tc, MLIRContext *ctx)
      : ConversionPattern(tc, MatchAnyOpTypeTag(), 1, ctx) {}
  LogicalResult matchAndRewrite(Operation *op, ArrayRef<Value> operands,
                                ConversionPatternRewriter &rewriter) const override {
    if (op->getNumRegions() != 0 || isa<arith::ConstantOp, arith::ExtFOp, arith::TruncFOp>(op))
      return failure();
    SmallVector<Type> results;
    if (failed(getTypeConverter()->convertTypes(op->getResultTypes(), results)))
      return failure();
    OperationState state(op->getLoc(), op->getName());
    state.addOperands(operands);
    state.addTypes(results);
    state.addAttributes(op->getAttrs());
    rewriter.replaceOp(op, rewriter.create(state)->getResults());
    return success();
  }
};

/// Float constants keep their (f32) values as f64.
struct RetypeConstant : public OpConversionPattern<arith::ConstantOp> {
  using OpConversionPattern::OpConversionPattern;
  LogicalResult matchAndRewrite(arith::ConstantOp op, OpAdaptor,
                                ConversionPatternRewriter &rewriter) const override {
    Type type = getTypeConverter()->convertType(op.getType());
    auto f64 = rewriter.getF64Type();
    TypedAttr value;
    if (auto f = dyn_cast<FloatAttr>(op.getValue()))
      value = FloatAttr::get(f64, f.getValueAsDouble());
    else if (auto dense = dyn_cast<DenseFPElementsAttr>(op.getValue()))
      value = dense.mapValues(f64, [](const APFloat &v) {
        return APFloat(double(v.convertToFloat())).bitcastToAPInt();
      });
    else
      return failure();
    rewriter.replaceOpWithNewOp<arith::ConstantOp>(op, type, value);
    return success();
  }
};

/// extf to f64 of a value that is now f64, and truncf to f32 (which becomes
/// f64) of an f64 value, vanish: precise's libm calls stay unrounded.
struct DropExtF : public OpConversionPattern<arith::ExtFOp> {
  using OpConversionPattern::OpConversionPattern;
  LogicalResult matchAndRewrite(arith::ExtFOp op, OpAdaptor adaptor,
                                ConversionPatternRewriter &rewriter) const override {
    if (adaptor.getIn().getType() != op.getType())
      return failure();
    rewriter.replaceOp(op, adaptor.getIn());
    return success();
  }
};
struct DropTruncF : public OpConversionPattern<arith::TruncFOp> {
  using OpConversionPattern::OpConversionPattern;
  LogicalResult matchAndRewrite(arith::TruncFOp op, OpAdaptor adaptor,
                                ConversionPatternRewriter &rewriter) const override {
    Type to = getTypeConverter()->convertType(op.getType());
    if (adaptor.getIn().getType() != to)
      return failure();
    rewriter.replaceOp(op, adaptor.getIn());
    return success();
  }
};

struct EvaluateInDoublePass
    : public mlir::osl::impl::EvaluateInDoubleBase<EvaluateInDoublePass> {
  void runOnOperation() override {
    MLIRContext *ctx = &getContext();
    DoubleTypeConverter converter(ctx);
    ConversionTarget target(*ctx);
    auto legal = [&](Operation *op) { return converter.isLegal(op); };
    target.addDynamicallyLegalDialect<arith::ArithDialect, math::MathDialect,
                                      vector::VectorDialect>(legal);
    // Reinterpreting bits needs the f32 the shader would have had.
    target.addLegalOp<arith::BitcastOp>();
    // A pick of float lanes carries its elements' doubles (it is a select).
    target.addDynamicallyLegalOp<osl::LanePickOp>(legal);
    target.markUnknownOpDynamicallyLegal([](Operation *) { return true; });
    RewritePatternSet patterns(ctx);
    patterns.add<Retype>(converter, ctx);
    patterns.add<RetypeConstant, DropExtF, DropTruncF>(converter, ctx);
    scf::populateSCFStructuralTypeConversionsAndLegality(converter, patterns, target);
    if (failed(applyPartialConversion(getOperation(), target, std::move(patterns))))
      signalPassFailure();
  }
};

} // namespace
