//===- OslMathApproximation.cpp - math ops computed as OSL computes them --===//
//
// OSL's default (fast-math) build evaluates the transcendental functions
// with OpenImageIO's fast_* routines; reproducing their algorithms step by
// step is what makes our results match OSL's, including where those
// routines are inaccurate (large sin/cos arguments) or saturate (exp2 is
// clamped to [-126, 126]). The published constants are facts of the
// algorithms; the code is ours.
//
//  sin, cos  reduce by the nearest multiple of pi, with pi/4 split in four
//            float parts (Cody-Waite); SLEEF's minimax polynomials; values
//            pushed outside [-1, 1] by a failed reduction become 0.
//  tan       the same with pi/2; -1/p on odd quadrants.
//  exp2      clamp to [-126, 126], split off the integer part (truncated),
//            degree-5 polynomial, scale by 2^m.
//  log2      clamp to [FLT_MIN, FLT_MAX], exponent from the bits, a
//            polynomial in the mantissa.
//  exp, log, log10, pow   through exp2 and log2 (pow of |x|; the sign and
//            special cases are lane::pow's).
//  atan, atan2  a rational approximation on [0, 1] after folding the
//            argument, then the quadrant from the signs (the sign bit of y,
//            so atan2(-0, -1) is -pi).
//
//  tanh, expm1, sinh, cosh   OIIO's fast_* through exp (expm1 is
//            x + x^2/2 below |x| = 0.03, sinh a polynomial below 1).
//  asin, acos  sqrt(1 - |x|) times a cubic (OIIO's fast_acos).
//  erf, cbrt   OIIO's fast_erf (Abramowitz and Stegun 7.1.28; erfc is
//            1 - erf, as OIIO's), fast_cbrt (a guess from the bits and
//            two Newton steps).
//
// madd(a, b, c) is one fused multiply-add: OSL's library is compiled with
// contraction on, and its JIT fuses a*b + c wherever the CPU has FMA, as on
// the machines that made the reference images (checked against testshade:
// sin, cos, exp, exp2 and pow agree bit for bit only fused).
//
//===----------------------------------------------------------------------===//
#include "MathLevels.h"
#include "OslLanes/LaneMath.h"
#include "OslTransforms/Passes.h"
#include "OslSupport/PatternRoots.h"

#include "mlir/Dialect/Arith/IR/Arith.h"
#include "mlir/Dialect/Math/IR/Math.h"
#include "mlir/Dialect/Math/Transforms/Approximation.h"
#include "mlir/Dialect/Math/Transforms/Passes.h"
#include "mlir/IR/PatternMatch.h"
#include "llvm/ADT/TypeSwitch.h"
#include "mlir/Transforms/GreedyPatternRewriteDriver.h"

#include <cfloat>

using namespace mlir;
using namespace mlir::osl;

namespace {

/// The parts of pi/4 (their sum is pi/4 to ~2^-64).
constexpr float kPi4Parts[] = {0.78515625f, 0.00024187564849853515625f,
                               3.7747668102383613586e-08f, 1.2816720341285448015e-12f};

/// Lane arithmetic on one f32 lane shape.
struct LaneBuilder {
  OpBuilder &b;
  Location loc;
  Type type;

  Value c(double v) { return lane::constant(b, loc, type, v); }
  Value mul(Value x, Value y) { return b.create<arith::MulFOp>(loc, x, y); }
  Value add(Value x, Value y) { return b.create<arith::AddFOp>(loc, x, y); }
  Value sub(Value x, Value y) { return b.create<arith::SubFOp>(loc, x, y); }
  Value neg(Value x) { return b.create<arith::NegFOp>(loc, x); }
  Value madd(Value x, Value y, Value z) { return b.create<math::FmaOp>(loc, x, y, z); }
  Value div(Value x, Value y) { return b.create<arith::DivFOp>(loc, x, y); }
  Value abs(Value x) { return b.create<math::AbsFOp>(loc, x); }
  Value copySign(Value x, Value y) { return b.create<math::CopySignOp>(loc, x, y); }
  Value less(Value x, double v) {
    return b.create<arith::CmpFOp>(loc, arith::CmpFPredicate::OLT, x, c(v));
  }
  Value exp(Value x) { return exp2(mul(x, c(float(1 / M_LN2)))); }

  /// OIIO's fast_tanh: 1 - 2 / (1 + e^(2|x|)), with x's sign.
  Value tanh(Value x) {
    Value e = exp(mul(c(2), abs(x)));
    return copySign(sub(c(1), div(c(2), add(c(1), e))), x);
  }
  /// OIIO's fast_expm1: x + x^2/2 below |x| = 0.03, else e^x - 1.
  Value expm1(Value x) {
    Value y = crush(x, 1);
    Value small = copySign(madd(c(0.5), mul(y, y), y), x);
    return select(less(abs(x), 0.03), small, sub(exp(x), c(1)));
  }
  /// OIIO's fast_sinh: from e = e^|x|, 0.5 e - 0.5 / e past |x| = 1, a
  /// degree-7 odd polynomial below.
  Value sinh(Value x) {
    Value a = abs(x);
    Value e = exp(a);
    Value wide = madd(c(0.5), e, neg(div(c(0.5), e)));
    Value m = crush(a, 1);
    Value m2 = mul(m, m);
    Value r = madd(c(2.03945513931e-4f), m2, c(8.32990277558e-3f));
    r = madd(r, m2, c(0.1666673421859f));
    r = madd(mul(r, m), m2, m);
    Value isWide = b.create<arith::CmpFOp>(loc, arith::CmpFPredicate::OGT, a, c(1));
    return copySign(select(isWide, wide, r), x);
  }
  /// OIIO's fast_cosh: 0.5 e + 0.5 / e with e = e^|x|.
  Value cosh(Value x) {
    Value e = exp(abs(x));
    return madd(c(0.5), e, div(c(0.5), e));
  }
  /// sqrt(1 - m) p(m) for OIIO's fast_acos and fast_asin, m = min(|x|, 1).
  std::pair<Value, Value> acosParts(Value x) {
    Value f = abs(x);
    Value m = select(less(f, 1), crush(f, 1), c(1));
    Value p = madd(m, c(-0.02164095f), c(0.077980478f));
    p = madd(m, p, c(-0.213300989f));
    p = madd(m, p, c(1.5707963267f));
    return {b.create<math::SqrtOp>(loc, sub(c(1), m)), p};
  }
  Value asin(Value x) {
    auto [s, p] = acosParts(x);
    return copySign(madd(neg(s), p, c(float(M_PI_2))), x);
  }
  Value acos(Value x) {
    auto [s, p] = acosParts(x);
    Value a = mul(s, p);
    return select(less(x, 0), sub(c(float(M_PI)), a), a);
  }
  /// OIIO's fast_erf (Abramowitz and Stegun 7.1.28): 1 - 1/r^16.
  Value erf(Value x) {
    Value a = crush(abs(x), 1);
    Value r = c(0.0000430638f);
    for (float k : {0.0002765672f, 0.0001520143f, 0.0092705272f, 0.0422820123f,
                    0.0705230784f, 1.0f})
      r = madd(r, a, c(k));
    for (int i = 0; i < 4; ++i)
      r = mul(r, r);
    return copySign(sub(c(1), div(c(1), r)), x);
  }
  /// OIIO's fast_cbrt: a guess from the bits, two Newton steps.
  Value cbrt(Value x) {
    Value mag = abs(x);
    Value third = b.create<arith::DivSIOp>(loc, toBits(mag), ci(3));
    Value a = fromBits(b.create<arith::AddIOp>(loc, ci(0x2a5137a0), third));
    for (int i = 0; i < 2; ++i)
      a = mul(c(0.333333333f), madd(c(2), a, div(mag, mul(a, a))));
    Value isZero = b.create<arith::CmpFOp>(loc, arith::CmpFPredicate::OEQ, mag, c(0));
    return copySign(select(isZero, c(0), a), x);
  }

  Value select(Value cond, Value t, Value f) {
    return b.create<arith::SelectOp>(loc, cond, t, f);
  }
  Value clamp(Value x, double lo, double hi) {
    return lane::clamp(b, loc, {x, c(lo), c(hi)});
  }
  Type intType() { return lane::withElement(type, b.getI32Type()); }
  Value ci(int64_t v) { return lane::constant(b, loc, intType(), double(v)); }
  Value toBits(Value x) { return b.create<arith::BitcastOp>(loc, intType(), x); }
  Value fromBits(Value x) { return b.create<arith::BitcastOp>(loc, type, x); }
  /// OIIO's "crush denormals": k - (k - x).
  Value crush(Value x, float k) { return sub(c(k), sub(c(k), x)); }

  /// x reduced by the nearest multiple q of the period (4 pi/4 parts per
  /// pi: scale 4; pi/2: scale 2); also whether q is odd.
  std::pair<Value, Value> reduce(Value x, double inversePeriod, float scale) {
    // fast_rint rounds to nearest, ties to even (one roundps on SSE4).
    Value qf = b.create<math::RoundEvenOp>(loc, mul(x, c(float(inversePeriod))));
    for (float part : kPi4Parts)
      x = madd(qf, c(-part * scale), x);
    Value q = b.create<arith::FPToSIOp>(loc, intType(), qf);
    Value odd = b.create<arith::CmpIOp>(loc, arith::CmpIPredicate::ne,
                                        b.create<arith::AndIOp>(loc, q, ci(1)), ci(0));
    return {x, odd};
  }
  /// Values a failed reduction pushes outside [-1, 1] become 0.
  Value zeroOutsideUnit(Value u) {
    Value outside = b.create<arith::CmpFOp>(loc, arith::CmpFPredicate::OGT,
                                            b.create<math::AbsFOp>(loc, u), c(1));
    return select(outside, c(0), u);
  }

  Value sin(Value x) {
    auto [r, odd] = reduce(x, 0.31830988618379067154, 4);
    r = crush(r, float(M_PI_2));
    Value s = mul(r, r);
    r = select(odd, neg(r), r);
    Value u = c(2.6083159809786593541503e-06f);
    u = madd(u, s, c(-0.0001981069071916863322258f));
    u = madd(u, s, c(0.00833307858556509017944336f));
    u = madd(u, s, c(-0.166666597127914428710938f));
    return zeroOutsideUnit(madd(s, mul(u, r), r));
  }
  Value cos(Value x) {
    auto [r, odd] = reduce(x, 0.31830988618379067154, 4);
    r = crush(r, float(M_PI_2));
    Value s = mul(r, r);
    Value u = c(-2.71811842367242206819355e-07f);
    u = madd(u, s, c(2.47990446951007470488548e-05f));
    u = madd(u, s, c(-0.00138888787478208541870117f));
    u = madd(u, s, c(0.0416666641831398010253906f));
    u = madd(u, s, c(-0.5f));
    u = madd(u, s, c(1.0f));
    return zeroOutsideUnit(select(odd, neg(u), u));
  }
  Value tan(Value x) {
    auto [r, odd] = reduce(x, 0.63661977236758134308, 2);
    // Tiny values are flushed only where the result is not inverted.
    r = select(odd, r, crush(r, float(M_PI_4)));
    Value s = mul(r, r);
    Value u = c(0.00927245803177356719970703f);
    u = madd(u, s, c(0.00331984995864331722259521f));
    u = madd(u, s, c(0.0242998078465461730957031f));
    u = madd(u, s, c(0.0534495301544666290283203f));
    u = madd(u, s, c(0.133383005857467651367188f));
    u = madd(u, s, c(0.333331853151321411132812f));
    u = madd(s, mul(u, r), r);
    return select(odd, neg(b.create<arith::DivFOp>(loc, c(1), u)), u);
  }
  /// OIIO's rational atan on s in [0, 1].
  Value atanCore(Value s) {
    s = crush(s, 1.0f);
    Value t = mul(s, s);
    Value num = mul(s, madd(c(0.430165678f), t, c(1.0f)));
    Value den = madd(madd(c(0.0579354987f), t, c(0.763007998f)), t, c(1.0f));
    return b.create<arith::DivFOp>(loc, num, den);
  }
  Value atan(Value x) {
    Value a = b.create<math::AbsFOp>(loc, x);
    Value big = b.create<arith::CmpFOp>(loc, arith::CmpFPredicate::OGT, a, c(1));
    Value k = select(big, b.create<arith::DivFOp>(loc, c(1), a), a);
    Value r = atanCore(k);
    r = select(big, sub(c(1.570796326794896557998982f), r), r);
    return b.create<math::CopySignOp>(loc, r, x);
  }
  Value atan2(Value y, Value x) {
    Value a = b.create<math::AbsFOp>(loc, x), bb = b.create<math::AbsFOp>(loc, y);
    Value bGreater = b.create<arith::CmpFOp>(loc, arith::CmpFPredicate::OGT, bb, a);
    Value ratio = select(bGreater, b.create<arith::DivFOp>(loc, a, bb),
                         b.create<arith::DivFOp>(loc, bb, a));
    Value equal = b.create<arith::CmpFOp>(loc, arith::CmpFPredicate::OEQ, a, bb);
    Value bZero = b.create<arith::CmpFOp>(loc, arith::CmpFPredicate::OEQ, bb, c(0));
    Value k = select(bZero, c(0), select(equal, c(1), ratio));
    Value r = atanCore(k);
    r = select(bGreater, sub(c(1.570796326794896557998982f), r), r);
    Value xNegative = b.create<arith::CmpIOp>(loc, arith::CmpIPredicate::slt, toBits(x), ci(0));
    r = select(xNegative, sub(c(float(M_PI)), r), r);
    return b.create<math::CopySignOp>(loc, r, y);
  }
  Value exp2(Value x) {
    x = clamp(x, -126.0, 126.0);
    Value m = b.create<arith::FPToSIOp>(loc, intType(), x); // truncates
    x = sub(x, b.create<arith::SIToFPOp>(loc, type, m));
    x = crush(x, 1.0f);
    Value r = c(1.33336498402e-3f);
    r = madd(x, r, c(9.810352697968e-3f));
    r = madd(x, r, c(5.551834031939e-2f));
    r = madd(x, r, c(0.2401793301105f));
    r = madd(x, r, c(0.693144857883f));
    r = madd(x, r, c(1.0f));
    // 2^m added into the exponent bits (r is in (0.5, 2), so no overflow).
    Value shifted = b.create<arith::ShLIOp>(loc, m, ci(23));
    return fromBits(b.create<arith::AddIOp>(loc, toBits(r), shifted));
  }
  Value log2(Value x) {
    x = clamp(x, FLT_MIN, FLT_MAX);
    Value bits = toBits(x);
    Value exponent = b.create<arith::SubIOp>(
        loc, b.create<arith::ShRUIOp>(loc, bits, ci(23)), ci(127));
    Value mantissa = b.create<arith::OrIOp>(
        loc, b.create<arith::AndIOp>(loc, bits, ci(0x007FFFFF)), ci(0x3f800000));
    Value f = sub(fromBits(mantissa), c(1.0f));
    Value f2 = mul(f, f), f4 = mul(f2, f2);
    Value hi = madd(f, c(-0.00931049621349f), c(0.05206469089414f));
    Value lo = madd(f, c(0.47868480909345f), c(-0.72116591947498f));
    hi = madd(f, hi, c(-0.13753123777116f));
    hi = madd(f, hi, c(0.24187369696082f));
    hi = madd(f, hi, c(-0.34730547155299f));
    lo = madd(f, lo, c(1.442689881667200f));
    // (f4 hi + f lo) + exponent, the first product fused as clang
    // contracts it.
    return add(madd(f4, hi, mul(f, lo)), b.create<arith::SIToFPOp>(loc, type, exponent));
  }
};

/// The OSL algorithm for `op`, or null for an op OSL computes otherwise.
Value expandOslMath(OpBuilder &b, Operation *op) {
  if (op->getNumResults() != 1 || !isa<Float32Type>(getElementTypeOrSelf(op->getResult(0))))
    return Value();
  LaneBuilder l{b, op->getLoc(), op->getResult(0).getType()};
  auto arg = [&](unsigned i) { return op->getOperand(i); };
  return llvm::TypeSwitch<Operation *, Value>(op)
      .Case<math::SinOp>([&](auto) { return l.sin(arg(0)); })
      .Case<math::CosOp>([&](auto) { return l.cos(arg(0)); })
      .Case<math::TanOp>([&](auto) { return l.tan(arg(0)); })
      .Case<math::AtanOp>([&](auto) { return l.atan(arg(0)); })
      .Case<math::Atan2Op>([&](auto) { return l.atan2(arg(0), arg(1)); })
      .Case<math::Exp2Op>([&](auto) { return l.exp2(arg(0)); })
      .Case<math::ExpOp>([&](auto) { return l.exp2(l.mul(arg(0), l.c(float(1 / M_LN2)))); })
      .Case<math::Log2Op>([&](auto) { return l.log2(arg(0)); })
      .Case<math::LogOp>([&](auto) { return l.mul(l.log2(arg(0)), l.c(float(M_LN2))); })
      .Case<math::Log10Op>(
          [&](auto) { return l.mul(l.log2(arg(0)), l.c(float(M_LN2 / M_LN10))); })
      .Case<math::PowFOp>([&](auto) { return l.exp2(l.mul(arg(1), l.log2(arg(0)))); })
      .Case<math::TanhOp>([&](auto) { return l.tanh(arg(0)); })
      .Case<math::ExpM1Op>([&](auto) { return l.expm1(arg(0)); })
      .Case<math::SinhOp>([&](auto) { return l.sinh(arg(0)); })
      .Case<math::CoshOp>([&](auto) { return l.cosh(arg(0)); })
      .Case<math::AsinOp>([&](auto) { return l.asin(arg(0)); })
      .Case<math::AcosOp>([&](auto) { return l.acos(arg(0)); })
      .Case<math::ErfOp>([&](auto) { return l.erf(arg(0)); })
      .Case<math::CbrtOp>([&](auto) { return l.cbrt(arg(0)); })
      .Default([](Operation *) { return Value(); });
}

} // namespace

//===----------------------------------------------------------------------===//
// osl-approximate-math
//===----------------------------------------------------------------------===//

namespace mlir::osl {
#define GEN_PASS_DEF_APPROXIMATEMATH
#include "OslTransforms/Passes.h.inc"
} // namespace mlir::osl

namespace {
struct ApproximateMathPass
    : public mlir::osl::impl::ApproximateMathBase<ApproximateMathPass> {
  using ApproximateMathBase::ApproximateMathBase;

  void runOnOperation() override {
    if (level == MathLevel::Precise || level == MathLevel::Double) {
      if (failed(computeInDoubleWithLibm(getOperation())))
        signalPassFailure();
      return;
    }
    if (level == MathLevel::Fast || level == MathLevel::Polynomial)
      guardFastMath(getOperation(), level == MathLevel::Fast);
    if (level == MathLevel::Default || level == MathLevel::Fast) {
      // OSL's algorithms, op by op: a pattern driver would fold constant
      // operands with libm first, which is what this pass must avoid.
      SmallVector<Operation *> ops;
      getOperation().walk([&](Operation *op) {
        if (op->getDialect() && isa<math::MathDialect>(op->getDialect()) &&
            (level == MathLevel::Default || isOslFasterAt(op)))
          ops.push_back(op);
      });
      for (Operation *op : ops) {
        OpBuilder b(op);
        if (Value r = expandOslMath(b, op)) {
          op->getResult(0).replaceAllUsesWith(r);
          op->erase();
        }
      }
    }
    if (level != MathLevel::Default) {
      // The ops MLIR has no approximation of, as osl-mlir's own formulas.
      SmallVector<Operation *> own;
      getOperation().walk([&](Operation *op) {
        if (isa<math::AsinOp, math::AcosOp, math::SinhOp, math::CoshOp, math::Log10Op>(op) &&
            !(level == MathLevel::Fast && isOslFasterAt(op)))
          own.push_back(op);
      });
      for (Operation *op : own) {
        OpBuilder b(op);
        Location loc = op->getLoc();
        Value x = op->getOperand(0);
        Value r = llvm::TypeSwitch<Operation *, Value>(op)
                      .Case<math::AsinOp>([&](auto) { return lane::asinFromAtan2(b, loc, x); })
                      .Case<math::AcosOp>([&](auto) { return lane::acosFromAtan2(b, loc, x); })
                      .Case<math::SinhOp>([&](auto) { return lane::sinhFromExp(b, loc, x); })
                      .Case<math::CoshOp>([&](auto) { return lane::coshFromExp(b, loc, x); })
                      .Case<math::Log10Op>([&](auto) { return lane::log10FromLog(b, loc, x); });
        op->getResult(0).replaceAllUsesWith(r);
        op->erase();
      }
    }
    // MLIR's approximations for the rest (erf, tanh...; at `fast`, all);
    // these can still be folded on constant operands.
    RewritePatternSet patterns(&getContext());
    populateFastMathPatterns(patterns);
    // Nothing left to rewrite in most shaders once OSL's algorithms are
    // in; then the canonicalizer after this pass does the folding.
    if (!hasPatternRoot(getOperation(), patterns))
      return;
    if (failed(applyPatternsAndFoldGreedily(getOperation(), std::move(patterns))))
      signalPassFailure();
  }
};
} // namespace
