//===- LibraryCalls.cpp - OSL's library functions on lanes ------------------===//
//
// Geometry, hashes, space transforms, colors and splines: each expands
// inline through its lane builder (OslLanes), the same code the front end
// folds constants with (noise: NoiseCalls.cpp).
//
//===----------------------------------------------------------------------===//
#include "OslToVector.h"

#include "OslAbi/Closures.h"
#include "OslLanes/ColorBuilder.h"
#include "OslLanes/ConstantTable.h"
#include "OslLanes/LaneMath.h"
#include "OslLanes/LibraryBuilders.h"
#include "OslLanes/NoiseBuilder.h"
#include "OslLanes/LibraryFunctions.h"
#include "mlir/Dialect/Arith/IR/Arith.h"
#include "mlir/Dialect/Math/IR/Math.h"
#include "mlir/IR/Matchers.h"

#include <limits>

using namespace mlir;
using namespace mlir::osl;
using namespace mlir::osl::lowering;

namespace {

/// Geometry on triples: dot, length, distance, cross, normalize.
template <typename OpTy>
struct GeometryLowering : public OslPattern<OpTy> {
  using OslPattern<OpTy>::OslPattern;

  /// x*u + y*v + z*w as OSL's library computes it (Imath's dot, compiled
  /// with contraction): fma(z, w, fma(x, u, y*v)).
  static Value dot(OpBuilder &b, Location loc, ArrayRef<Value> a, ArrayRef<Value> c) {
    Value s = b.create<math::FmaOp>(loc, a[0], c[0], lane::mul(b, loc, {a[1], c[1]}));
    return b.create<math::FmaOp>(loc, a[2], c[2], s);
  }

  /// Imath's length, which OSL's length() calls: sqrt of the dot product,
  /// but for a vector whose squared length is below 2 * FLT_MIN (it would
  /// lose its bits to denormals) the components are first divided by the
  /// largest of them. (OSL's distance() and normalize() take the plain
  /// square root: testshade gives normalize(vector(3e-23, 4e-23, 0)) =
  /// (0.566684, 0.755579, 0).)
  static Value length(OpBuilder &b, Location loc, ArrayRef<Value> a) {
    Value length2 = dot(b, loc, a, a);
    auto cst = [&](double v) { return lane::constantLike(b, loc, length2, v); };
    SmallVector<Value> magnitude;
    for (Value c : a)
      magnitude.push_back(b.create<math::AbsFOp>(loc, c));
    Value largest = lane::max(b, loc, {lane::max(b, loc, {magnitude[0], magnitude[1]}),
                                       magnitude[2]});
    SmallVector<Value> scaled;
    for (Value m : magnitude)
      scaled.push_back(b.create<arith::DivFOp>(loc, m, largest));
    Value tinyLength = b.create<arith::MulFOp>(
        loc, largest, lane::sqrt(b, loc, {dot(b, loc, scaled, scaled)}));
    Value zero = b.create<arith::CmpFOp>(loc, arith::CmpFPredicate::OEQ, largest, cst(0));
    tinyLength = b.create<arith::SelectOp>(loc, zero, cst(0), tinyLength);
    Value tiny = b.create<arith::CmpFOp>(loc, arith::CmpFPredicate::OLT, length2,
                                         cst(2 * double(std::numeric_limits<float>::min())));
    return b.create<arith::SelectOp>(loc, tiny, tinyLength, lane::sqrt(b, loc, {length2}));
  }

  LogicalResult matchAndRewrite(OpTy op, typename OpTy::Adaptor adaptor,
                                ConversionPatternRewriter &rewriter) const override {
    Location loc = op.getLoc();
    Type resultType = op->getResult(0).getType();
    bool varying = isVarying(resultType);
    Components lanes{rewriter, loc, this->width};
    SmallVector<SmallVector<Value>> v =
        lanes.unpackAll(adaptor.getOperands(), op->getOperands(), varying);
    auto &b = rewriter;
    SmallVector<Value> out;
    if constexpr (std::is_same_v<OpTy, DotOp>) {
      out = {dot(b, loc, v[0], v[1])};
    } else if constexpr (std::is_same_v<OpTy, LengthOp>) {
      out = {length(b, loc, v[0])};
    } else if constexpr (std::is_same_v<OpTy, DistanceOp>) {
      SmallVector<Value> d;
      for (int i = 0; i < 3; ++i)
        d.push_back(lane::sub(b, loc, {v[0][i], v[1][i]}));
      out = {lane::sqrt(b, loc, {dot(b, loc, d, d)})};
    } else if constexpr (std::is_same_v<OpTy, CrossOp>) {
      for (int i = 0; i < 3; ++i) {
        int j = (i + 1) % 3, k = (i + 2) % 3;
        out.push_back(lane::sub(b, loc, {lane::mul(b, loc, {v[0][j], v[1][k]}),
                                         lane::mul(b, loc, {v[0][k], v[1][j]})}));
      }
    } else {
      // normalize as OSL's library: times 1/length where the length is
      // above 0, else the zero vector.
      Value len = lane::sqrt(b, loc, {dot(b, loc, v[0], v[0])});
      Value zero = lane::constantLike(b, loc, len, 0);
      Value positive = b.create<arith::CmpFOp>(loc, arith::CmpFPredicate::OGT, len, zero);
      Value inverse = b.create<arith::DivFOp>(loc, lane::constantLike(b, loc, len, 1), len);
      for (int i = 0; i < 3; ++i)
        out.push_back(b.create<arith::SelectOp>(
            loc, positive, b.create<arith::MulFOp>(loc, v[0][i], inverse), zero));
    }
    rewriter.replaceOp(op, lanes.pack(out, this->convert(resultType)));
    return success();
  }
};

struct TableReadLowering : public OslPattern<TableReadOp> {
  using OslPattern::OslPattern;
  LogicalResult matchAndRewrite(TableReadOp op, OpAdaptor adaptor,
                                ConversionPatternRewriter &rewriter) const override {
    LLVM::GlobalOp table = getConstantTable(rewriter, op.getLoc(), op.getTable());
    rewriter.replaceOp(op, lookupConstantTable(rewriter, op.getLoc(), table, adaptor.getIndex()));
    return success();
  }
};

struct HashLowering : public OslPattern<HashOp> {
  using OslPattern::OslPattern;
  LogicalResult matchAndRewrite(HashOp op, OpAdaptor adaptor,
                                ConversionPatternRewriter &rewriter) const override {
    Location loc = op.getLoc();
    Components lanes{rewriter, loc, width};
    SmallVector<Value> keys;
    for (auto &key : lanes.unpackAll(adaptor.getKeys(), op.getKeys(), isVarying(op.getType())))
      llvm::append_range(keys, key);
    if (keys.empty() || keys.size() > 5)
      return op.emitError("hash takes 1 to 5 key components");
    rewriter.replaceOp(op, buildIntHash(rewriter, loc, keys));
    return success();
  }
};

struct TransformLowering : public OslPattern<TransformOp> {
  using OslPattern::OslPattern;
  LogicalResult matchAndRewrite(TransformOp op, OpAdaptor adaptor,
                                ConversionPatternRewriter &rewriter) const override {
    std::optional<Matrix44> m = namedSpaceTransform(op.getFrom(), op.getTo());
    if (!m)
      return op.emitError("unknown coordinate space in transform from '")
             << op.getFrom() << "' to '" << op.getTo() << "'";
    Components lanes{rewriter, op.getLoc(), width};
    auto p = lanes.unpack(adaptor.getValue(), op.getValue().getType(),
                          isVarying(op.getType()));
    std::array<Value, 3> r =
        buildTransform(rewriter, op.getLoc(), *m, op.getKind(), {p[0], p[1], p[2]});
    rewriter.replaceOp(op, lanes.pack(r, convert(op.getType())));
    return success();
  }
};

/// transformc, blackbody, wavelength_color and luminance under the op's
/// working color space.
template <typename Op>
struct ColorLowering : public OslPattern<Op> {
  using OslPattern<Op>::OslPattern;
  LogicalResult matchAndRewrite(Op op, typename Op::Adaptor adaptor,
                                ConversionPatternRewriter &rewriter) const override {
    const ColorSystem *cs = ColorSystem::get(op.getColorspace());
    if (!cs)
      return op.emitError("unknown color space '") << op.getColorspace() << "'";
    Location loc = op.getLoc();
    Components lanes{rewriter, loc, this->width};
    SmallVector<Value> in = lanes.unpack(adaptor.getOperands()[0],
                                         op->getOperand(0).getType(), false);
    SmallVector<Value> out;
    if constexpr (std::is_same_v<Op, TransformcOp>) {
      FailureOr<LaneColor> r =
          buildTransformc(rewriter, loc, *cs, op.getFrom(), op.getTo(), {in[0], in[1], in[2]});
      if (failed(r))
        return op.emitError("unknown color space in transformc from '")
               << op.getFrom() << "' to '" << op.getTo() << "'";
      out.assign(r->begin(), r->end());
    } else if constexpr (std::is_same_v<Op, LuminanceOp>) {
      out.push_back(buildLuminance(rewriter, loc, *cs, {in[0], in[1], in[2]}));
    } else {
      LaneColor r = std::is_same_v<Op, BlackbodyOp>
                        ? buildBlackbody(rewriter, loc, *cs, in[0])
                        : buildWavelengthColor(rewriter, loc, *cs, in[0]);
      out.assign(r.begin(), r.end());
    }
    rewriter.replaceOp(op, lanes.pack(out, this->convert(op.getType())));
    return success();
  }
};

/// The lanes of spline's or splineinverse's x (or y), count and knots: x
/// and the count take the result's shape; knots stay as they are (the
/// builder broadcasts them). Fails (reported) below 4 knots.
template <typename Op>
LogicalResult splineOperands(Op op, typename Op::Adaptor adaptor, Components &lanes, Value &x,
                             Value &count, SmallVector<SmallVector<Value>> &knots) {
  bool varying = isVarying(op.getType());
  x = lanes.unpack(adaptor.getOperands()[0], op->getOperand(0).getType(), varying)[0];
  // (A constant count out of range was reported before the conversion:
  // checkSplineKnotCounts.)
  if (op.getCount())
    count = lanes.unpack(adaptor.getCount(), op.getCount().getType(), varying)[0];
  knots = lanes.unpackAll(adaptor.getKnots(), op.getKnots(), false);
  if (knots.size() < 4)
    return op.emitError("spline basis '")
           << splineBasisName(op.getBasis()) << "' needs at least 4 knots";
  return success();
}

/// spline, inline: a color ramp's constant knots fold into its code.
struct SplineLowering : public OslPattern<SplineOp> {
  using OslPattern::OslPattern;
  LogicalResult matchAndRewrite(SplineOp op, OpAdaptor adaptor,
                                ConversionPatternRewriter &rewriter) const override {
    Components lanes{rewriter, op.getLoc(), width};
    Value x, count;
    SmallVector<SmallVector<Value>> knots;
    if (failed(splineOperands(op, adaptor, lanes, x, count, knots)))
      return failure();
    FailureOr<SmallVector<Value>> r =
        buildSpline(rewriter, op.getLoc(), op.getBasis(), x, count, knots);
    rewriter.replaceOp(op, lanes.pack(*r, convert(op.getType())));
    return success();
  }
};

/// splineinverse, a call of a library function per basis, knot count and
/// signature: its bisection is a loop around a whole spline evaluation,
/// costly to compile at every call and cheap to call. Each knot is an
/// argument of its own (equal knots too), so the routine's code is the
/// same whatever the knots are, and a recipe names it: the prebuilt
/// library holds the common ones (noise_catalog.osl).
struct SplineInverseLowering : public OslPattern<SplineInverseOp> {
  SplineInverseLowering(const VaryingTypeConverter &converter, MLIRContext *ctx,
                        const LibraryRoutineNeeds &needs)
      : OslPattern(converter, ctx), needs(needs) {}

  LogicalResult matchAndRewrite(SplineInverseOp op, OpAdaptor adaptor,
                                ConversionPatternRewriter &rewriter) const override {
    Location loc = op.getLoc();
    Components lanes{rewriter, loc, width};
    Value y, count;
    SmallVector<SmallVector<Value>> knots;
    if (failed(splineOperands(op, adaptor, lanes, y, count, knots)))
      return failure();
    // (Its knots are floats, one value each: the op's verifier.)
    SmallVector<Value> operands{y};
    if (count)
      operands.push_back(count);
    for (const SmallVector<Value> &knot : knots)
      operands.push_back(knot[0]);
    auto type = FunctionType::get(getContext(), ValueRange(operands).getTypes(), y.getType());
    std::string name = ("splineinverse_" + splineBasisName(op.getBasis())).str();
    std::replace(name.begin(), name.end(), '-', '_');
    std::string text;
    llvm::raw_string_ostream os(text);
    os << "splineinverse " << splineBasisName(op.getBasis()) << " width " << width << " (";
    llvm::interleaveComma(type.getInputs(), os);
    os << ") -> " << y.getType();
    bool needCode = needs.needCode(text, needs.derivativeOf.contains(op));
    SplineBasis basis = op.getBasis();
    bool counted = bool(count);
    func::FuncOp func = libraryFunction(
        rewriter, op, name, text, type, needCode, [&] { return needs.available(text); },
        [&](OpBuilder &b, ValueRange args) -> SmallVector<Value> {
          SmallVector<SmallVector<Value>> knotArgs;
          for (Value knot : args.drop_front(counted ? 2 : 1))
            knotArgs.push_back({knot});
          return {*buildSplineInverse(b, loc, basis, args[0], counted ? args[1] : Value(),
                                      knotArgs)};
        });
    auto call = rewriter.create<func::CallOp>(loc, func, operands);
    call->setAttr(kKeepCallAttr, rewriter.getUnitAttr());
    rewriter.replaceOp(op, lanes.pack({call.getResult(0)}, convert(op.getType())));
    return success();
  }

  const LibraryRoutineNeeds &needs;
};

} // namespace

/// A knot count known to be out of range is the shader's error (OSL reads
/// past the knots); one message, before the conversion would fail too.
LogicalResult mlir::osl::lowering::checkSplineKnotCounts(Operation *root) {
  bool ok = true;
  root->walk([&](Operation *op) {
    if (!isa<SplineOp, SplineInverseOp>(op))
      return;
    Value count = isa<SplineOp>(op) ? cast<SplineOp>(op).getCount()
                                    : cast<SplineInverseOp>(op).getCount();
    int64_t len = isa<SplineOp>(op) ? cast<SplineOp>(op).getKnots().size()
                                    : cast<SplineInverseOp>(op).getKnots().size();
    APInt known;
    if (count && matchPattern(count, m_ConstantInt(&known)) &&
        (known.getSExtValue() < 0 || known.getSExtValue() > len)) {
      op->emitError("knot count ") << known.getSExtValue() << " is out of range (0 to "
                                   << len << ")";
      ok = false;
    }
  });
  return success(ok);
}

void mlir::osl::lowering::populateSplineInversePatterns(const VaryingTypeConverter &converter,
                                                        RewritePatternSet &patterns,
                                                        const LibraryRoutineNeeds &needs) {
  patterns.add<SplineInverseLowering>(converter, patterns.getContext(), needs);
}

void mlir::osl::lowering::populateLibraryCallPatterns(const VaryingTypeConverter &converter,
                                                      RewritePatternSet &patterns) {
  patterns.add<GeometryLowering<DotOp>, GeometryLowering<LengthOp>,
               GeometryLowering<DistanceOp>, GeometryLowering<CrossOp>,
               GeometryLowering<NormalizeOp>, HashLowering, TableReadLowering,
               TransformLowering,
               SplineLowering,
               ColorLowering<TransformcOp>, ColorLowering<BlackbodyOp>,
               ColorLowering<WavelengthColorOp>, ColorLowering<LuminanceOp>>(
      converter, patterns.getContext());
}
