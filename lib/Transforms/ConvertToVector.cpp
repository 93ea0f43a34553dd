//===- ConvertToVector.cpp - osl to vector code of width W ----------------===//
//
// Varying values become vectors of W lanes (triples: vector<3 x W x f32>,
// one row per component, so each component is one SIMD register); uniform
// values stay scalar. Each lane-wise op is lowered component by component
// through LaneMath, which builds the same arith ops for scalars and
// vectors. The shader function becomes the batch kernel of
// OslAbi/GlobalsLayout.h.
//
//===----------------------------------------------------------------------===//
#include "OslDialect/OslDialect.h"
#include "OslAbi/GlobalsLayout.h"
#include "OslAbi/Closures.h"
#include "OslAbi/Print.h"
#include "OslAbi/Strings.h"
#include "OslAbi/Texture.h"
#include "OslLanes/ColorBuilder.h"
#include "OslLanes/ConstantTable.h"
#include "OslLanes/GaborBuilder.h"
#include "OslLanes/LaneMath.h"
#include "OslLanes/LibraryBuilders.h"
#include "OslLanes/NoiseBuilder.h"
#include "OslTransforms/Passes.h"
#include "VectorLowering.h"

#include "mlir/Dialect/SCF/Transforms/Patterns.h"
#include "mlir/IR/Matchers.h"
#include "mlir/Transforms/DialectConversion.h"

namespace mlir::osl {
#define GEN_PASS_DEF_CONVERTTOVECTOR
#include "OslTransforms/Passes.h.inc"
} // namespace mlir::osl

using namespace mlir;
using namespace mlir::osl;
using namespace mlir::osl::lowering;

namespace {

//===----------------------------------------------------------------------===//
// Conversion patterns
//===----------------------------------------------------------------------===//

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
    Lanes lanes{rewriter, loc, this->width};
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

/// Lower osl.global to loads of its rows from the globals block.
struct GlobalLowering : public OslPattern<GlobalOp> {
  using OslPattern::OslPattern;
  LogicalResult matchAndRewrite(GlobalOp op, OpAdaptor,
                                ConversionPatternRewriter &rewriter) const override {
    const ::osl::GlobalSlot *slot = ::osl::findGlobal(op.getName().str());
    Location loc = op.getLoc();
    Lanes lanes{rewriter, loc, width};
    // A uniform global (reference mode, see osl-uniform-reference) is lane 0.
    Type rowType = isVarying(op.getType())
                       ? Type(VectorType::get({width}, rewriter.getF32Type()))
                       : Type(rewriter.getF32Type());
    SmallVector<Value> rows;
    for (int i = 0; i < slot->rows; ++i) {
      Value addr = rowAddress(rewriter, loc, kernelArg(op, 0), slot->row + i, width);
      auto load = rewriter.create<LLVM::LoadOp>(loc, rowType, addr, 4);
      // osl-derivatives finds the derivative rows of what it loads.
      load->setAttr("osl.global_row", rewriter.getI64IntegerAttr(slot->row + i));
      rows.push_back(load);
    }
    rewriter.replaceOp(op, lanes.pack(rows, convert(op.getType())));
    return success();
  }
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

/// Lower osl.output to masked stores of its rows: lanes past nactive are
/// never written. Int and bool outputs are stored as float values.
struct OutputLowering : public OslPattern<OutputOp> {
  OutputLowering(const VaryingTypeConverter &converter, MLIRContext *ctx,
                 const llvm::DenseMap<Operation *, int64_t> &firstRow)
      : OslPattern(converter, ctx), firstRow(firstRow) {}
  LogicalResult matchAndRewrite(OutputOp op, OpAdaptor adaptor,
                                ConversionPatternRewriter &rewriter) const override {
    Location loc = op.getLoc();
    Lanes lanes{rewriter, loc, width};
    SmallVector<Value> rows =
        lanes.unpack(adaptor.getValue(), op.getValue().getType(), /*varying=*/true);
    bool unconditional = isa<func::FuncOp>(op->getParentOp());
    Value mask = unconditional ? Value() : activeLanes(rewriter, loc, op, width);
    bool closure = isa<ClosureType>(getUniformType(op.getValue().getType()));
    for (auto [i, row] : llvm::enumerate(rows)) {
      // A closure's handle keeps its bits (the renderer reads them back).
      Value value = closure ? rewriter.create<LLVM::BitcastOp>(
                                  loc, VectorType::get({width}, rewriter.getF32Type()), row)
                            : lane::convert(rewriter, loc, row, rewriter.getF32Type());
      // One NaN for every NaN: scalar and vector code (and LLVM's folds at
      // each width) may leave different NaN payloads, and the widths must
      // agree bit for bit. A NaN's payload is visible nowhere else.
      if (!closure && isa<FloatType>(getElementTypeOrSelf(row.getType()))) {
        Value nan = lane::constant(rewriter, loc, value.getType(),
                                   std::numeric_limits<double>::quiet_NaN());
        Value isNan =
            rewriter.create<arith::CmpFOp>(loc, arith::CmpFPredicate::UNO, value, value);
        value = rewriter.create<arith::SelectOp>(loc, isNan, nan, value);
      }
      Value addr = rowAddress(rewriter, loc, kernelArg(op, 1),
                              firstRow.lookup(op) + i, width);
      // The caller owns whole rows and reads only the active lanes, so an
      // output written once at the end of the shader stores every lane:
      // a plain store forwards to the caller's next load of the row, where
      // a masked store makes that load wait until the store has retired.
      if (unconditional)
        rewriter.create<LLVM::StoreOp>(loc, value, addr, 4);
      else
        rewriter.create<LLVM::MaskedStoreOp>(loc, value, addr, mask, 4);
    }
    rewriter.eraseOp(op);
    return success();
  }
  const llvm::DenseMap<Operation *, int64_t> &firstRow;
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
    rewriter.replaceOpWithNewOp<vector::ReductionOp>(op, vector::CombiningKind::OR,
                                                     adaptor.getMask());
    return success();
  }
};

struct BroadcastLowering : public OslPattern<BroadcastOp> {
  using OslPattern::OslPattern;
  LogicalResult matchAndRewrite(BroadcastOp op, OpAdaptor adaptor,
                                ConversionPatternRewriter &rewriter) const override {
    Lanes lanes{rewriter, op.getLoc(), width};
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
    Lanes lanes{rewriter, loc, width};
    auto lhs = lanes.unpack(adaptor.getLhs(), op.getLhs().getType(), varying);
    auto rhs = lanes.unpack(adaptor.getRhs(), op.getRhs().getType(), varying);
    rewriter.replaceOp(op, lane::compareComponents(rewriter, loc, op.getPredicate(), lhs, rhs,
                                                           op.getUnordered()));
    return success();
  }
};

struct ConvertLowering : public OslPattern<ConvertOp> {
  using OslPattern::OslPattern;
  LogicalResult matchAndRewrite(ConvertOp op, OpAdaptor adaptor,
                                ConversionPatternRewriter &rewriter) const override {
    Location loc = op.getLoc();
    Lanes lanes{rewriter, loc, width};
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
    Lanes lanes{rewriter, op.getLoc(), width};
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
    Lanes lanes{rewriter, op.getLoc(), width};
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
    Lanes lanes{rewriter, op.getLoc(), width};
    bool varying = isVarying(op.getType());
    auto comps = lanes.unpack(adaptor.getVector(), op.getVector().getType(), varying);
    comps[op.getIndex()] =
        lanes.unpack(adaptor.getValue(), op.getValue().getType(), varying)[0];
    rewriter.replaceOp(op, lanes.pack(comps, convert(op.getType())));
    return success();
  }
};

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

  LogicalResult matchAndRewrite(OpTy op, typename OpTy::Adaptor adaptor,
                                ConversionPatternRewriter &rewriter) const override {
    Location loc = op.getLoc();
    Type resultType = op->getResult(0).getType();
    bool varying = isVarying(resultType);
    Lanes lanes{rewriter, loc, this->width};
    SmallVector<SmallVector<Value>> v =
        lanes.unpackAll(adaptor.getOperands(), op->getOperands(), varying);
    auto &b = rewriter;
    SmallVector<Value> out;
    if constexpr (std::is_same_v<OpTy, DotOp>) {
      out = {dot(b, loc, v[0], v[1])};
    } else if constexpr (std::is_same_v<OpTy, LengthOp>) {
      out = {lane::sqrt(b, loc, {dot(b, loc, v[0], v[0])})};
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

/// Gabor noise: the point (and its derivatives and period) made 3D, the
/// options read as scalars (the verifier keeps them uniform).
void lowerGabor(NoiseOp op, NoiseOp::Adaptor adaptor, Lanes &lanes, Type resultType,
                ConversionPatternRewriter &rewriter) {
  Location loc = op.getLoc();
  bool varying = isVarying(op.getType());
  SmallVector<Value> flat;
  for (auto &c : lanes.unpackAll(adaptor.getCoords(), op.getCoords(), varying))
    llvm::append_range(flat, c);
  // A triple point has 3 values, a float domain 1 or 2 (a 4th coordinate
  // and its period are ignored, as OSL does).
  size_t ncoords = op.getPeriodic() ? op.getCoords().size() / 2 : op.getCoords().size();
  bool triple = isTriple(getUniformType(op.getCoords()[0].getType()));
  size_t pointSize = triple ? 3 : ncoords;
  size_t domainSize = triple ? (ncoords == 2 ? 4 : 3) : ncoords;
  Type laneType = flat[0].getType();
  auto point3 = [&](ArrayRef<Value> v) {
    std::array<Value, 3> p;
    for (size_t k = 0; k < 3; ++k)
      p[k] = k < v.size() ? v[k] : lane::constant(rewriter, loc, laneType, 0.0);
    return p;
  };
  ArrayRef<Value> all(flat);
  GaborPoint point;
  point.p = point3(all.take_front(pointSize));
  if (op.getPeriodic())
    point.period = point3(all.drop_front(domainSize).take_front(pointSize));
  if (!op.getDerivs().empty()) {
    SmallVector<Value> d;
    for (auto &c : lanes.unpackAll(adaptor.getDerivs(), op.getDerivs(), varying))
      llvm::append_range(d, c);
    point.dPdx = point3(ArrayRef<Value>(d).take_front(pointSize));
    point.dPdy = point3(ArrayRef<Value>(d).drop_front(pointSize));
  }
  GaborOptions options;
  auto scalar = [&](Value converted, Value original) {
    return converted ? lanes.unpack(converted, original.getType(), false)[0] : Value();
  };
  options.anisotropic = scalar(adaptor.getAnisotropic(), op.getAnisotropic());
  options.bandwidth = scalar(adaptor.getBandwidth(), op.getBandwidth());
  options.impulses = scalar(adaptor.getImpulses(), op.getImpulses());
  options.doFilter = scalar(adaptor.getDoFilter(), op.getDoFilter());
  if (op.getDirection()) {
    SmallVector<Value> dir = lanes.unpack(adaptor.getDirection(), op.getDirection().getType(), false);
    options.direction = {dir[0], dir[1], dir[2]};
  }
  if (isTriple(getUniformType(op.getType()))) {
    std::array<Value, 3> r = buildGaborTriple(rewriter, loc, point, options);
    rewriter.replaceOp(op, lanes.pack(r, resultType));
  } else {
    rewriter.replaceOp(op, buildGaborFloat(rewriter, loc, point, options));
  }
}

struct HashLowering : public OslPattern<HashOp> {
  using OslPattern::OslPattern;
  LogicalResult matchAndRewrite(HashOp op, OpAdaptor adaptor,
                                ConversionPatternRewriter &rewriter) const override {
    Location loc = op.getLoc();
    Lanes lanes{rewriter, loc, width};
    SmallVector<Value> keys;
    for (auto &key : lanes.unpackAll(adaptor.getKeys(), op.getKeys(), isVarying(op.getType())))
      llvm::append_range(keys, key);
    if (keys.empty() || keys.size() > 5)
      return op.emitError("hash takes 1 to 5 key components");
    rewriter.replaceOp(op, buildIntHash(rewriter, loc, keys));
    return success();
  }
};

struct NoiseLowering : public OslPattern<NoiseOp> {
  using OslPattern::OslPattern;
  LogicalResult matchAndRewrite(NoiseOp op, OpAdaptor adaptor,
                                ConversionPatternRewriter &rewriter) const override {
    if (op.getKind() == "gabor") {
      Lanes lanes{rewriter, op.getLoc(), width};
      lowerGabor(op, adaptor, lanes, convert(op.getType()), rewriter);
      return success();
    }
    std::optional<NoiseKind> kind = parseNoiseName(op.getKind());
    if (!kind)
      return op.emitError("noise type '") << op.getKind() << "' is not supported yet";
    Location loc = op.getLoc();
    bool varying = isVarying(op.getType());
    Lanes lanes{rewriter, loc, width};
    SmallVector<Value> coords;
    for (auto &c : lanes.unpackAll(adaptor.getCoords(), op.getCoords(), varying))
      llvm::append_range(coords, c);
    if (op.getPeriodic()) {
      ArrayRef<Value> all(coords);
      ArrayRef<Value> points = all.take_front(all.size() / 2);
      ArrayRef<Value> periods = all.drop_front(all.size() / 2);
      if (isTriple(getUniformType(op.getType()))) {
        std::array<Value, 3> r =
            buildPeriodicNoiseTriple(rewriter, loc, *kind, points, periods);
        if (!r[0])
          return op.emitError("periodic '") << op.getKind() << "' noise is not defined";
        rewriter.replaceOp(op, lanes.pack(r, convert(op.getType())));
      } else {
        Value r = buildPeriodicNoiseFloat(rewriter, loc, *kind, points, periods);
        if (!r)
          return op.emitError("periodic '") << op.getKind() << "' noise is not defined";
        rewriter.replaceOp(op, r);
      }
      return success();
    }
    if (isTriple(getUniformType(op.getType()))) {
      std::array<Value, 3> r = buildNoiseTriple(rewriter, loc, *kind, coords);
      rewriter.replaceOp(op, lanes.pack(r, convert(op.getType())));
    } else {
      rewriter.replaceOp(op, buildNoiseFloat(rewriter, loc, *kind, coords));
    }
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
    Lanes lanes{rewriter, op.getLoc(), width};
    auto p = lanes.unpack(adaptor.getValue(), op.getValue().getType(),
                          isVarying(op.getType()));
    std::array<Value, 3> r =
        buildTransform(rewriter, op.getLoc(), *m, op.getKind(), {p[0], p[1], p[2]});
    rewriter.replaceOp(op, lanes.pack(r, convert(op.getType())));
    return success();
  }
};

/// osl.first_lane: the lowest set lane of the mask selects the value.
struct FirstLaneLowering : public OslPattern<FirstLaneOp> {
  using OslPattern::OslPattern;
  LogicalResult matchAndRewrite(FirstLaneOp op, OpAdaptor adaptor,
                                ConversionPatternRewriter &rewriter) const override {
    if (!isa<VectorType>(adaptor.getValue().getType())) {
      rewriter.replaceOp(op, adaptor.getValue());
      return success();
    }
    Location loc = op.getLoc();
    Value mask = adaptor.getMask();
    if (!isa<VectorType>(mask.getType()))
      mask = lane::broadcast(rewriter, loc, mask, width);
    Value bits = maskBits(rewriter, loc, mask);
    Value lead = rewriter.create<LLVM::CountTrailingZerosOp>(loc, bits.getType(), bits, false);
    rewriter.replaceOpWithNewOp<vector::ExtractElementOp>(op, adaptor.getValue(), lead);
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
    Lanes lanes{rewriter, loc, this->width};
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

/// spline and splineinverse: x (or y) and the count take the result's
/// shape; knots stay as they are (the builder broadcasts them).
template <typename Op>
struct SplineFamilyLowering : public OslPattern<Op> {
  using OslPattern<Op>::OslPattern;
  LogicalResult matchAndRewrite(Op op, typename Op::Adaptor adaptor,
                                ConversionPatternRewriter &rewriter) const override {
    Location loc = op.getLoc();
    bool varying = isVarying(op.getType());
    Lanes lanes{rewriter, loc, this->width};
    Value x = lanes.unpack(adaptor.getOperands()[0], op->getOperand(0).getType(), varying)[0];
    Value count;
    if (op.getCount()) {
      APInt known;
      int64_t len = op.getKnots().size();
      if (matchPattern(op.getCount(), m_ConstantInt(&known)) &&
          (known.getSExtValue() < 4 || known.getSExtValue() > len))
        return op.emitError("knot count ")
               << known.getSExtValue() << " is out of range (4 to " << len << ")";
      count = lanes.unpack(adaptor.getCount(), op.getCount().getType(), varying)[0];
    }
    SmallVector<SmallVector<Value>> knots =
        lanes.unpackAll(adaptor.getKnots(), op.getKnots(), false);
    FailureOr<SmallVector<Value>> r;
    if constexpr (std::is_same_v<Op, SplineOp>) {
      r = buildSpline(rewriter, loc, op.getBasis(), x, count, knots);
    } else {
      FailureOr<Value> inv = buildSplineInverse(rewriter, loc, op.getBasis(), x, count, knots);
      if (succeeded(inv))
        r = SmallVector<Value>{*inv};
    }
    if (failed(r))
      return op.emitError("spline basis '") << op.getBasis() << "' needs at least 4 knots";
    rewriter.replaceOp(op, lanes.pack(*r, this->convert(op.getType())));
    return success();
  }
};


//===----------------------------------------------------------------------===//
// Closures
//===----------------------------------------------------------------------===//

/// Stores `operands` (converted, with their osl types) as 32-bit rows of a
/// block for a closure entry point, calls `callee` with the block, and reads
/// the result row of handles back. Uniform ops run one lane.
Value callClosureEntry(ConversionPatternRewriter &rewriter, Operation *op, int64_t width,
                       LLVM::LLVMFuncOp callee, ArrayRef<Value> leading, ValueRange converted,
                       ValueRange original) {
  Location loc = op->getLoc();
  bool varying = isVarying(op->getResult(0).getType());
  int64_t lanes = varying ? width : 1;
  Lanes unpacker{rewriter, loc, width};
  SmallVector<Value> rows;
  for (auto [c, o] : llvm::zip(converted, original))
    for (Value comp : unpacker.unpack(c, o.getType(), varying))
      rows.push_back(comp);
  Value block = entryBlockRows(rewriter, loc, op, int64_t(rows.size() + 1) * lanes);
  for (auto [i, comp] : llvm::enumerate(rows))
    rewriter.create<LLVM::StoreOp>(loc, comp, rowAddress(rewriter, loc, block, i, lanes), 4);
  Value mask = varying ? activeLanes(rewriter, loc, op, width)
                       : rewriter.create<arith::ConstantIntOp>(loc, 1, 1).getResult();
  Type i32 = rewriter.getI32Type();
  SmallVector<Value> args(leading.begin(), leading.end());
  args.append({block, rewriter.create<arith::ConstantIntOp>(loc, lanes, 32),
               maskBits(rewriter, loc, mask)});
  rewriter.create<LLVM::CallOp>(loc, callee, args);
  Type laneType = varying ? Type(VectorType::get({lanes}, i32)) : i32;
  auto load = rewriter.create<LLVM::LoadOp>(
      loc, laneType, rowAddress(rewriter, loc, block, int64_t(rows.size()), lanes), 4);
  load->setAttr(kNoDerivativeAttr, rewriter.getUnitAttr());
  return load.getResult();
}

struct ClosureEmptyLowering : public OslPattern<ClosureEmptyOp> {
  using OslPattern::OslPattern;
  LogicalResult matchAndRewrite(ClosureEmptyOp op, OpAdaptor,
                                ConversionPatternRewriter &rewriter) const override {
    rewriter.replaceOpWithNewOp<arith::ConstantIntOp>(op, 0, 32);
    return success();
  }
};

/// osl.closure_component: osl_rt_closure_component(id, rows, lanes, mask).
struct ClosureComponentLowering : public OslPattern<ClosureComponentOp> {
  using OslPattern::OslPattern;
  LogicalResult matchAndRewrite(ClosureComponentOp op, OpAdaptor adaptor,
                                ConversionPatternRewriter &rewriter) const override {
    Value id = rewriter.create<arith::ConstantIntOp>(op.getLoc(),
                                                     ::osl::closureId(op.getName()), 32);
    rewriter.replaceOp(op, callClosureEntry(rewriter, op, width,
                                            runtimeDeclaration(rewriter, op,
                                                               entry::osl_rt_closure_component),
                                            {id}, adaptor.getArgs(), op.getArgs()));
    return success();
  }
};

/// osl.closure_mul and osl.closure_add: their entry point on the operands' rows.
template <typename Op>
struct ClosureArithLowering : public OslPattern<Op> {
  using OslPattern<Op>::OslPattern;
  LogicalResult matchAndRewrite(Op op, typename Op::Adaptor adaptor,
                                ConversionPatternRewriter &rewriter) const override {
    LLVM::LLVMFuncOp callee =
        std::is_same_v<Op, ClosureMulOp>
            ? runtimeDeclaration(rewriter, op, entry::osl_rt_closure_mul)
            : runtimeDeclaration(rewriter, op, entry::osl_rt_closure_add);
    rewriter.replaceOp(op, callClosureEntry(rewriter, op, this->width, callee, {},
                                            adaptor.getOperands(), op->getOperands()));
    return success();
  }
};

void populateLaneOpPatterns(const VaryingTypeConverter &converter,
                            RewritePatternSet &patterns) {
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
  LANE(ErfcOp, erfc); LANE(LogbOp, logb); LANE(LinearStepOp, linearstep); LANE(FloorOp, floor); LANE(CeilOp, ceil);
  LANE(RoundOp, round); LANE(TruncOp, trunc); LANE(SignOp, sign);
  LANE(PowOp, pow); LANE(FmodOp, fmod); LANE(StepOp, step); LANE(MixOp, mix);
  LANE(ClampOp, clamp); LANE(SmoothStepOp, smoothstep); LANE(SelectOp, select);
#undef LANE
  patterns.add<ClosureArithLowering<ClosureMulOp>, ClosureArithLowering<ClosureAddOp>>(converter,
                                                                                     ctx);
  patterns.add<ClosureEmptyLowering, ClosureComponentLowering>(converter, ctx);
  populateRuntimeCallPatterns(converter, patterns);
  patterns.add<GlobalLowering, BatchMaskLowering, AnyLowering, BroadcastLowering,
               CmpLowering, ConvertLowering, ConstructLowering, ExtractLowering,
               InsertLowering, GeometryLowering<DotOp>, GeometryLowering<LengthOp>,
               GeometryLowering<DistanceOp>, GeometryLowering<CrossOp>,
               GeometryLowering<NormalizeOp>, NoiseLowering, HashLowering, TransformLowering,
               SplineFamilyLowering<SplineOp>,
               SplineFamilyLowering<SplineInverseOp>, ColorLowering<TransformcOp>,
               ColorLowering<BlackbodyOp>, ColorLowering<WavelengthColorOp>,
               ColorLowering<LuminanceOp>, FirstLaneLowering, IsConstantLowering>(converter, ctx);
}

//===----------------------------------------------------------------------===//
// Convert osl to vector pass
//===----------------------------------------------------------------------===//

/// Gives the shader function the batch-kernel signature.
void makeKernelSignature(func::FuncOp func) {
  MLIRContext *ctx = func.getContext();
  auto ptr = LLVM::LLVMPointerType::get(ctx);
  auto i32 = IntegerType::get(ctx, 32);
  func->setAttr("osl.shader_name", StringAttr::get(ctx, func.getSymName()));
  func.setSymName("osl_batch");
  func.setType(FunctionType::get(ctx, {ptr, ptr, i32}, {}));
  Location loc = func.getLoc();
  func.getBody().front().addArguments({ptr, ptr, i32}, {loc, loc, loc});
}

struct ConvertToVectorPass
    : public mlir::osl::impl::ConvertToVectorBase<ConvertToVectorPass> {
  using mlir::osl::impl::ConvertToVectorBase<ConvertToVectorPass>::ConvertToVectorBase;

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
    makeKernelSignature(shaders[0]);

    MLIRContext *ctx = &getContext();
    VaryingTypeConverter converter(width);
    ConversionTarget target(*ctx);
    target.addIllegalDialect<OslDialect>();
    target.addLegalOp<LaneDerivOp>();
    target.addLegalDialect<arith::ArithDialect, math::MathDialect,
                           vector::VectorDialect, LLVM::LLVMDialect,
                           func::FuncDialect>();
    RewritePatternSet patterns(ctx);
    populateLaneOpPatterns(converter, patterns);
    patterns.add<OutputLowering>(converter, ctx, outputRow);
    patterns.add<DerivLowering>(converter, ctx, referenceMode);
    scf::populateSCFStructuralTypeConversionsAndLegality(converter, patterns, target);
    if (failed(applyPartialConversion(getOperation(), target, std::move(patterns))))
      return signalPassFailure();
    resetMessagesOnEntry(shaders[0]);
  }

  /// A kernel that passes messages starts each batch without any.
  void resetMessagesOnEntry(func::FuncOp kernel) {
    ModuleOp module = getOperation();
    if (!module.lookupSymbol(entry::osl_rt_setmessage.name) &&
        !module.lookupSymbol(entry::osl_rt_getmessage.name))
      return;
    OpBuilder b(&getContext());
    b.setInsertionPointToStart(&kernel.getBody().front());
    LLVM::LLVMFuncOp reset = runtimeDeclaration(b, kernel, entry::osl_rt_message_reset);
    b.create<LLVM::CallOp>(kernel.getLoc(), reset, ValueRange{});
  }
};

} // namespace
