//===- LaneMath.cpp - OSL semantics on lane values ------------------------===//
#include "OslLanes/LaneMath.h"
#include "OslLanes/UniformDivisor.h"

#include "mlir/Dialect/Arith/IR/Arith.h"
#include "mlir/Dialect/Math/IR/Math.h"
#include "mlir/Dialect/Vector/IR/VectorOps.h"
#include "mlir/IR/BuiltinAttributes.h"
#include "mlir/IR/Matchers.h"
#include "mlir/IR/TypeUtilities.h"
#include "llvm/ADT/StringSwitch.h"

#include <cfloat>
#include <cmath>
#include <optional>

using namespace mlir;
using namespace mlir::osl;

Type lane::withElement(Type laneType, Type element) {
  if (auto vec = dyn_cast<VectorType>(laneType))
    return vec.clone(element);
  return element;
}

Value lane::constant(OpBuilder &b, Location loc, Type like, double value) {
  Type element = getElementTypeOrSelf(like);
  TypedAttr scalar;
  if (isa<FloatType>(element))
    scalar = b.getFloatAttr(element, value);
  else
    scalar = b.getIntegerAttr(element, int64_t(value));
  if (auto vec = dyn_cast<VectorType>(like))
    return b.create<arith::ConstantOp>(loc, DenseElementsAttr::get(vec, scalar));
  return b.create<arith::ConstantOp>(loc, scalar);
}

Value lane::constantLike(OpBuilder &b, Location loc, Value like, double value) {
  return constant(b, loc, like.getType(), value);
}

Value lane::broadcast(OpBuilder &b, Location loc, Value scalar, int64_t width) {
  if (width == 0 || isa<VectorType>(scalar.getType()))
    return scalar;
  return b.create<vector::BroadcastOp>(
      loc, VectorType::get({width}, scalar.getType()), scalar);
}

Value lane::any(OpBuilder &b, Location loc, Value mask) {
  if (!isa<VectorType>(mask.getType()))
    return mask;
  return b.create<vector::ReductionOp>(loc, vector::CombiningKind::OR, mask);
}

static bool isFloat(Value v) {
  return isa<FloatType>(getElementTypeOrSelf(v.getType()));
}
static bool isBool(Value v) {
  return getElementTypeOrSelf(v.getType()).isInteger(1);
}
static Value cst(OpBuilder &b, Location loc, Value like, double v) {
  return lane::constantLike(b, loc, like, v);
}
static Value sel(OpBuilder &b, Location loc, Value c, Value t, Value f) {
  return b.create<arith::SelectOp>(loc, c, t, f);
}
static Value fcmp(OpBuilder &b, Location loc, arith::CmpFPredicate p, Value x,
                  Value y) {
  return b.create<arith::CmpFOp>(loc, p, x, y);
}
static Value icmp(OpBuilder &b, Location loc, arith::CmpIPredicate p, Value x,
                  Value y) {
  return b.create<arith::CmpIOp>(loc, p, x, y);
}

//===----------------------------------------------------------------------===//
// Arithmetic
//===----------------------------------------------------------------------===//

Value lane::add(OpBuilder &b, Location loc, ValueRange x) {
  if (isFloat(x[0]))
    return b.create<arith::AddFOp>(loc, x[0], x[1]);
  return b.create<arith::AddIOp>(loc, x[0], x[1]);
}

Value lane::sub(OpBuilder &b, Location loc, ValueRange x) {
  if (isFloat(x[0]))
    return b.create<arith::SubFOp>(loc, x[0], x[1]);
  return b.create<arith::SubIOp>(loc, x[0], x[1]);
}

Value lane::mul(OpBuilder &b, Location loc, ValueRange x) {
  if (isFloat(x[0]))
    return b.create<arith::MulFOp>(loc, x[0], x[1]);
  return b.create<arith::MulIOp>(loc, x[0], x[1]);
}

/// OSL's safe division: x/0 = 0. For ints the divisor is also made safe
/// first, since every lane executes the division (x86 traps on /0 and on
/// INT_MIN/-1).
/// The value every lane of `v` holds when it is a compile-time constant:
/// a scalar constant, or a broadcast of one or of a constant triple's
/// component (as the lowering unpacks uniform constants).
static std::optional<double> constantLaneValue(Value v) {
  while (true) {
    Operation *def = v.getDefiningOp();
    if (!def)
      return std::nullopt;
    if (isa<vector::BroadcastOp, vector::SplatOp>(def) &&
        !isa<VectorType>(def->getOperand(0).getType())) {
      v = def->getOperand(0);
      continue;
    }
    if (auto extract = dyn_cast<vector::ExtractOp>(def)) {
      DenseElementsAttr dense;
      if (!matchPattern(extract.getVector(), m_Constant(&dense)) ||
          extract.hasDynamicPosition() || extract.getStaticPosition().size() != 1)
        return std::nullopt;
      int64_t at = extract.getStaticPosition()[0];
      if (!isa<FloatType>(dense.getElementType()) || at < 0 || at >= dense.getNumElements())
        return std::nullopt;
      return (*(dense.getValues<APFloat>().begin() + at)).convertToDouble();
    }
    FloatAttr f;
    if (matchPattern(v, m_Constant(&f)))
      return f.getValueAsDouble();
    DenseElementsAttr splat;
    if (matchPattern(v, m_Constant(&splat)) && splat.isSplat() &&
        isa<FloatType>(splat.getElementType()))
      return splat.getSplatValue<APFloat>().convertToDouble();
    return std::nullopt;
  }
}

/// OSL's float division: by a non-zero constant, a plain division (OSL's
/// scalar JIT emits no check); otherwise a quotient that is not finite
/// (x/0, inf/y, a NaN, an overflow) is 0.
Value lane::div(OpBuilder &b, Location loc, ValueRange x) {
  Value num = x[0], den = x[1];
  if (isFloat(num)) {
    Value q = b.create<arith::DivFOp>(loc, num, den);
    if (auto k = constantLaneValue(den); k && *k != 0)
      return q;
    Value finite = fcmp(b, loc, arith::CmpFPredicate::OLT, b.create<math::AbsFOp>(loc, q),
                        cst(b, loc, q, INFINITY));
    return sel(b, loc, finite, q, cst(b, loc, num, 0));
  }
  if (Value d = uniformDivisorOf(den))
    return divideByUniform(b, loc, num, d);
  Value zero = cst(b, loc, den, 0), one = cst(b, loc, den, 1);
  Value isZero = icmp(b, loc, arith::CmpIPredicate::eq, den, zero);
  Value overflow = b.create<arith::AndIOp>(
      loc, icmp(b, loc, arith::CmpIPredicate::eq, num, cst(b, loc, num, INT32_MIN)),
      icmp(b, loc, arith::CmpIPredicate::eq, den, cst(b, loc, den, -1)));
  Value unsafe = b.create<arith::OrIOp>(loc, isZero, overflow);
  Value safeDen = sel(b, loc, unsafe, one, den);
  Value q = b.create<arith::DivSIOp>(loc, num, safeDen);
  q = sel(b, loc, overflow, num, q);
  return sel(b, loc, isZero, zero, q);
}

/// int x % 0 = 0, truncating like C.
Value lane::mod(OpBuilder &b, Location loc, ValueRange x) {
  Value num = x[0], den = x[1];
  if (Value d = uniformDivisorOf(den))
    return remainderByUniform(b, loc, num, d);
  Value zero = cst(b, loc, den, 0);
  Value isZero = icmp(b, loc, arith::CmpIPredicate::eq, den, zero);
  Value isMinusOne = icmp(b, loc, arith::CmpIPredicate::eq, den, cst(b, loc, den, -1));
  Value unsafe = b.create<arith::OrIOp>(loc, isZero, isMinusOne);
  Value r = b.create<arith::RemSIOp>(loc, num, sel(b, loc, unsafe, cst(b, loc, den, 1), den));
  return sel(b, loc, unsafe, zero, r);
}

Value lane::neg(OpBuilder &b, Location loc, ValueRange x) {
  if (isFloat(x[0]))
    return b.create<arith::NegFOp>(loc, x[0]);
  return b.create<arith::SubIOp>(loc, cst(b, loc, x[0], 0), x[0]);
}

// min/max as compare+select, like OSL's (b < a ? b : a): NaN handling is
// then the same at every width.
Value lane::min(OpBuilder &b, Location loc, ValueRange x) {
  Value less = isFloat(x[0]) ? fcmp(b, loc, arith::CmpFPredicate::OLT, x[1], x[0])
                             : icmp(b, loc, arith::CmpIPredicate::slt, x[1], x[0]);
  return sel(b, loc, less, x[1], x[0]);
}

/// As OSL: max(a, b) is b when a <= b (so max(0, -0) is -0), else a (a NaN
/// in a); min(a, b) is b when b < a, else a.
Value lane::max(OpBuilder &b, Location loc, ValueRange x) {
  Value notAbove = isFloat(x[0]) ? fcmp(b, loc, arith::CmpFPredicate::OLE, x[0], x[1])
                                 : icmp(b, loc, arith::CmpIPredicate::sle, x[0], x[1]);
  return sel(b, loc, notAbove, x[1], x[0]);
}

Value lane::abs(OpBuilder &b, Location loc, ValueRange x) {
  if (isFloat(x[0]))
    return b.create<math::AbsFOp>(loc, x[0]);
  return b.create<math::AbsIOp>(loc, x[0]);
}

Value lane::logicalAnd(OpBuilder &b, Location loc, ValueRange x) {
  return b.create<arith::AndIOp>(loc, x[0], x[1]);
}
Value lane::logicalOr(OpBuilder &b, Location loc, ValueRange x) {
  return b.create<arith::OrIOp>(loc, x[0], x[1]);
}
Value lane::logicalNot(OpBuilder &b, Location loc, ValueRange x) {
  return b.create<arith::XOrIOp>(loc, x[0], cst(b, loc, x[0], 1));
}
Value lane::bitAnd(OpBuilder &b, Location loc, ValueRange x) {
  return b.create<arith::AndIOp>(loc, x[0], x[1]);
}
Value lane::bitOr(OpBuilder &b, Location loc, ValueRange x) {
  return b.create<arith::OrIOp>(loc, x[0], x[1]);
}
Value lane::bitXor(OpBuilder &b, Location loc, ValueRange x) {
  return b.create<arith::XOrIOp>(loc, x[0], x[1]);
}
Value lane::bitNot(OpBuilder &b, Location loc, ValueRange x) {
  return b.create<arith::XOrIOp>(loc, x[0], cst(b, loc, x[0], -1));
}

/// Shift counts are masked to 0..31 so no lane hits LLVM's poison.
static Value shiftCount(OpBuilder &b, Location loc, Value n) {
  return b.create<arith::AndIOp>(loc, n, cst(b, loc, n, 31));
}
Value lane::shl(OpBuilder &b, Location loc, ValueRange x) {
  return b.create<arith::ShLIOp>(loc, x[0], shiftCount(b, loc, x[1]));
}
Value lane::shr(OpBuilder &b, Location loc, ValueRange x) {
  return b.create<arith::ShRSIOp>(loc, x[0], shiftCount(b, loc, x[1]));
}

//===----------------------------------------------------------------------===//
// Float math. math.* ops stay until osl-lower-to-llvm, which computes them
// as OSL does (OslMathApproximation.cpp), so osl-derivatives still sees
// them; the rules for edge inputs are applied here.
//===----------------------------------------------------------------------===//

Value lane::sin(OpBuilder &b, Location loc, ValueRange x) {
  return b.create<math::SinOp>(loc, x[0]);
}
Value lane::cos(OpBuilder &b, Location loc, ValueRange x) {
  return b.create<math::CosOp>(loc, x[0]);
}
Value lane::tan(OpBuilder &b, Location loc, ValueRange x) {
  return b.create<math::TanOp>(loc, x[0]);
}

/// `v` is an internal step of a library function (kOneRoundingAttr).
static Value oneRounding(Value v) {
  if (Operation *op = v.getDefiningOp())
    op->setAttr(kOneRoundingAttr, UnitAttr::get(op->getContext()));
  return v;
}

static Value clampUnit(OpBuilder &b, Location loc, Value x) {
  return lane::clamp(b, loc, {x, cst(b, loc, x, -1), cst(b, loc, x, 1)});
}
/// sqrt(1 - x^2) as sqrt((1-x)(1+x)), accurate near |x| = 1.
static Value cosOfAsin(OpBuilder &b, Location loc, Value x) {
  Value one = cst(b, loc, x, 1);
  Value p = oneRounding(b.create<arith::MulFOp>(loc, oneRounding(b.create<arith::SubFOp>(loc, one, x)),
                                          oneRounding(b.create<arith::AddFOp>(loc, one, x))));
  return oneRounding(b.create<math::SqrtOp>(loc, p));
}
// asin, acos, sinh and cosh are math ops of their own (on a clamped input
// for asin and acos) that each math level computes its way
// (osl-approximate-math): OSL's algorithms by default, libm at precise,
// and at fast and polynomial the formulas below on MLIR's exp and atan2.
Value lane::asin(OpBuilder &b, Location loc, ValueRange x) {
  return b.create<math::AsinOp>(loc, clampUnit(b, loc, x[0]));
}
Value lane::acos(OpBuilder &b, Location loc, ValueRange x) {
  return b.create<math::AcosOp>(loc, clampUnit(b, loc, x[0]));
}
Value lane::asinFromAtan2(OpBuilder &b, Location loc, Value c) {
  return oneRounding(b.create<math::Atan2Op>(loc, c, cosOfAsin(b, loc, c)));
}
Value lane::acosFromAtan2(OpBuilder &b, Location loc, Value c) {
  return oneRounding(b.create<math::Atan2Op>(loc, cosOfAsin(b, loc, c), c));
}
Value lane::atan(OpBuilder &b, Location loc, ValueRange x) {
  return b.create<math::AtanOp>(loc, x[0]);
}
/// atan2 of two zeros is OSL's (and IEEE's) +-0 or +-pi by the signs, not
/// an approximation's NaN: pi where x is -0, with y's sign.
Value lane::atan2(OpBuilder &b, Location loc, ValueRange x) {
  Value zero = cst(b, loc, x[0], 0);
  Value bothZero = b.create<arith::AndIOp>(
      loc, fcmp(b, loc, arith::CmpFPredicate::OEQ, x[0], zero),
      fcmp(b, loc, arith::CmpFPredicate::OEQ, x[1], zero));
  // The sign bit of x (also of -0), in any float width (--math=double).
  Value xNegative = fcmp(b, loc, arith::CmpFPredicate::OLT,
                         b.create<math::CopySignOp>(loc, cst(b, loc, x[1], 1), x[1]), zero);
  Value onAxis = b.create<math::CopySignOp>(
      loc, sel(b, loc, xNegative, cst(b, loc, x[0], M_PI), zero), x[0]);
  auto angle = b.create<math::Atan2Op>(loc, x[0], x[1]);
  // OSL's dual atan2 has the opposite sign of the true derivative; its
  // derivatives are the ones to reproduce (see osl-derivatives).
  angle->setAttr(kDualRuleAttr, b.getStringAttr(kDualRuleOslAtan2));
  return sel(b, loc, bothZero, onAxis, angle);
}
Value lane::exp(OpBuilder &b, Location loc, ValueRange x) {
  return b.create<math::ExpOp>(loc, x[0]);
}
Value lane::exp2(OpBuilder &b, Location loc, ValueRange x) {
  return b.create<math::Exp2Op>(loc, x[0]);
}

/// OSL: the log of x <= 0 is the log of FLT_MIN, never -inf or NaN.
static Value logOfPositive(OpBuilder &b, Location loc, Value x, double scale,
                           bool base2) {
  Value positive = fcmp(b, loc, arith::CmpFPredicate::OGT, x, cst(b, loc, x, 0));
  Value safe = sel(b, loc, positive, x, cst(b, loc, x, FLT_MIN));
  Value l = base2 ? b.create<math::Log2Op>(loc, safe).getResult()
                  : b.create<math::LogOp>(loc, safe).getResult();
  if (scale != 1.0)
    l = oneRounding(b.create<arith::MulFOp>(loc, l, cst(b, loc, x, scale)));
  return l;
}
Value lane::log(OpBuilder &b, Location loc, ValueRange x) {
  return logOfPositive(b, loc, x[0], 1.0, false);
}
Value lane::log2(OpBuilder &b, Location loc, ValueRange x) {
  return logOfPositive(b, loc, x[0], 1.0, true);
}
/// A math op of its own, like asin (see there): OSL's is log2 times
/// log10(2), which ln times 1/ln(10) does not round alike.
Value lane::log10(OpBuilder &b, Location loc, ValueRange x) {
  Value positive = fcmp(b, loc, arith::CmpFPredicate::OGT, x[0], cst(b, loc, x[0], 0));
  Value safe = sel(b, loc, positive, x[0], cst(b, loc, x[0], FLT_MIN));
  return b.create<math::Log10Op>(loc, safe);
}
Value lane::log10FromLog(OpBuilder &b, Location loc, Value x) {
  return logOfPositive(b, loc, x, 1.0 / M_LN10, false);
}

/// (e^x -+ e^-x) / 2 from one exp; near 0 sinh is x plus a cubic term,
/// which avoids the cancellation of the difference.
/// e^x and e^-x from one exp, shared by sinh and cosh.
static std::pair<Value, Value> expPair(OpBuilder &b, Location loc, Value x) {
  Value e = b.create<math::ExpOp>(loc, x);
  return {e, oneRounding(b.create<arith::DivFOp>(loc, cst(b, loc, x, 1), e))};
}
Value lane::sinh(OpBuilder &b, Location loc, ValueRange x) {
  return b.create<math::SinhOp>(loc, x[0]);
}
Value lane::cosh(OpBuilder &b, Location loc, ValueRange x) {
  return b.create<math::CoshOp>(loc, x[0]);
}
Value lane::sinhFromExp(OpBuilder &b, Location loc, Value x0) {
  ValueRange x(x0);
  auto [e, inv] = expPair(b, loc, x[0]);
  Value wide = oneRounding(b.create<arith::MulFOp>(loc, oneRounding(b.create<arith::SubFOp>(loc, e, inv)),
                                             cst(b, loc, x[0], 0.5)));
  Value x2 = b.create<arith::MulFOp>(loc, x[0], x[0]);
  // x + x^3/6 + x^5/120: below |x| = 2^-4 the next term is under 1 ULP.
  Value poly = b.create<arith::AddFOp>(
      loc, cst(b, loc, x[0], 1.0 / 6),
      b.create<arith::MulFOp>(loc, x2, cst(b, loc, x[0], 1.0 / 120)));
  Value small = b.create<arith::AddFOp>(
      loc, x[0], b.create<arith::MulFOp>(loc, b.create<arith::MulFOp>(loc, x[0], x2), poly));
  Value isSmall = fcmp(b, loc, arith::CmpFPredicate::OLT,
                       b.create<math::AbsFOp>(loc, x[0]), cst(b, loc, x[0], 0.0625));
  return sel(b, loc, isSmall, small, wide);
}
Value lane::coshFromExp(OpBuilder &b, Location loc, Value x0) {
  ValueRange x(x0);
  auto [e, inv] = expPair(b, loc, x[0]);
  return oneRounding(b.create<arith::MulFOp>(loc, oneRounding(b.create<arith::AddFOp>(loc, e, inv)),
                                       cst(b, loc, x[0], 0.5)));
}
Value lane::tanh(OpBuilder &b, Location loc, ValueRange x) {
  return b.create<math::TanhOp>(loc, x[0]);
}
Value lane::expm1(OpBuilder &b, Location loc, ValueRange x) {
  return b.create<math::ExpM1Op>(loc, x[0]);
}
/// Computed by the math level: OSL's own algorithm by default.
Value lane::cbrt(OpBuilder &b, Location loc, ValueRange x) {
  return b.create<math::CbrtOp>(loc, x[0]);
}
Value lane::erf(OpBuilder &b, Location loc, ValueRange x) {
  return b.create<math::ErfOp>(loc, x[0]);
}
Value lane::erfc(OpBuilder &b, Location loc, ValueRange x) {
  return oneRounding(b.create<arith::SubFOp>(loc, cst(b, loc, x[0], 1),
                                       b.create<math::ErfOp>(loc, x[0])));
}
/// The binary exponent of max(|x|, FLT_MIN), read from the bits, so
/// logb(0) = -126 as in OSL and exact powers of two are exact.
Value lane::logb(OpBuilder &b, Location loc, ValueRange x) {
  Value mag = b.create<math::AbsFOp>(loc, x[0]);
  mag = max(b, loc, {mag, cst(b, loc, mag, FLT_MIN)});
  Type intLane = withElement(mag.getType(), b.getI32Type());
  Value bits = b.create<arith::BitcastOp>(loc, intLane, mag);
  Value exponent = b.create<arith::ShRUIOp>(loc, bits, constant(b, loc, intLane, 23));
  exponent = b.create<arith::SubIOp>(loc, exponent, constant(b, loc, intLane, 127));
  return b.create<arith::SIToFPOp>(loc, mag.getType(), exponent);
}
/// linearstep as stdosl.h has it: x clamped between the edges (which,
/// reversed, gives edge0 and so -0), then scaled; a step when e0 == e1.
Value lane::linearstep(OpBuilder &b, Location loc, ValueRange x) {
  Value clamped = clamp(b, loc, {x[2], x[0], x[1]});
  Value ramp = b.create<arith::DivFOp>(loc, b.create<arith::SubFOp>(loc, clamped, x[0]),
                                       b.create<arith::SubFOp>(loc, x[1], x[0]));
  Value degenerate = fcmp(b, loc, arith::CmpFPredicate::OEQ, x[0], x[1]);
  return sel(b, loc, degenerate, step(b, loc, {x[0], x[2]}), ramp);
}

Value lane::sqrt(OpBuilder &b, Location loc, ValueRange x) {
  Value negative = fcmp(b, loc, arith::CmpFPredicate::OLT, x[0], cst(b, loc, x[0], 0));
  return sel(b, loc, negative, cst(b, loc, x[0], 0),
             b.create<math::SqrtOp>(loc, x[0]));
}
Value lane::inverseSqrt(OpBuilder &b, Location loc, ValueRange x) {
  Value positive = fcmp(b, loc, arith::CmpFPredicate::OGT, x[0], cst(b, loc, x[0], 0));
  Value r = b.create<arith::DivFOp>(loc, cst(b, loc, x[0], 1),
                                    b.create<math::SqrtOp>(loc, x[0]));
  return sel(b, loc, positive, r, cst(b, loc, x[0], 0));
}

Value lane::floor(OpBuilder &b, Location loc, ValueRange x) {
  return b.create<math::FloorOp>(loc, x[0]);
}
Value lane::ceil(OpBuilder &b, Location loc, ValueRange x) {
  return b.create<math::CeilOp>(loc, x[0]);
}
Value lane::trunc(OpBuilder &b, Location loc, ValueRange x) {
  return b.create<math::TruncOp>(loc, x[0]);
}
/// Halves round away from zero. Built from trunc, which is one instruction
/// on every width (llvm.round on vectors can become per-lane libm calls).
Value lane::round(OpBuilder &b, Location loc, ValueRange x) {
  Value t = b.create<math::TruncOp>(loc, x[0]);
  Value frac = b.create<math::AbsFOp>(loc, b.create<arith::SubFOp>(loc, x[0], t));
  Value up = fcmp(b, loc, arith::CmpFPredicate::OGE, frac, cst(b, loc, x[0], 0.5));
  Value away = b.create<math::CopySignOp>(loc, cst(b, loc, x[0], 1), x[0]);
  return sel(b, loc, up, b.create<arith::AddFOp>(loc, t, away), t);
}
Value lane::sign(OpBuilder &b, Location loc, ValueRange x) {
  Value zero = cst(b, loc, x[0], 0);
  Value pos = fcmp(b, loc, arith::CmpFPredicate::OGT, x[0], zero);
  Value negv = fcmp(b, loc, arith::CmpFPredicate::OLT, x[0], zero);
  return sel(b, loc, pos, cst(b, loc, x[0], 1),
             sel(b, loc, negv, cst(b, loc, x[0], -1), zero));
}

namespace {
/// OSL's safe pow: pow(x, 0) = 1; pow(0, y) = 0 for y != 0; a negative
/// base needs an integer exponent (odd ones keep the sign), else 0.
Value safePow(OpBuilder &b, Location loc, Value base, Value e) {
  Value zero = cst(b, loc, base, 0), one = cst(b, loc, base, 1);
  Value mag = b.create<math::PowFOp>(loc, b.create<math::AbsFOp>(loc, base), e);
  Value isInt = fcmp(b, loc, arith::CmpFPredicate::OEQ,
                     b.create<math::FloorOp>(loc, e), e);
  Value half = b.create<arith::MulFOp>(loc, e, cst(b, loc, e, 0.5));
  Value isOdd = b.create<arith::AndIOp>(
      loc, isInt,
      fcmp(b, loc, arith::CmpFPredicate::UNE, b.create<math::FloorOp>(loc, half), half));
  Value negBase = fcmp(b, loc, arith::CmpFPredicate::OLT, base, zero);
  Value r = sel(b, loc, b.create<arith::AndIOp>(loc, negBase, isOdd),
                b.create<arith::NegFOp>(loc, mag), mag);
  Value notInt = b.create<arith::XOrIOp>(loc, isInt, cst(b, loc, isInt, 1));
  r = sel(b, loc, b.create<arith::AndIOp>(loc, negBase, notInt), zero, r);
  // OSL (fast_safe_pow) is exact for x^1 and x^2 (the square capped at
  // FLT_MAX); as for v = 0 below, its derivative is the general formula's.
  auto valueOnly = [&](Value cond, Value special, Value general) {
    Value v = sel(b, loc, cond, special, general);
    if (Operation *op = v.getDefiningOp())
      op->setAttr(kDualRuleAttr, b.getStringAttr(kDualRuleValueOnly));
    return v;
  };
  Value square = lane::min(b, loc, {b.create<arith::MulFOp>(loc, base, base), cst(b, loc, base, FLT_MAX)});
  r = valueOnly(fcmp(b, loc, arith::CmpFPredicate::OEQ, e, cst(b, loc, e, 2)), square, r);
  r = valueOnly(fcmp(b, loc, arith::CmpFPredicate::OEQ, e, one), base, r);
  r = sel(b, loc, fcmp(b, loc, arith::CmpFPredicate::OEQ, base, zero), zero, r);
  return sel(b, loc, fcmp(b, loc, arith::CmpFPredicate::OEQ, e, zero), one, r);
}
} // namespace

/// pow(x, y) as OSL computes it: safe pow, except where a derivative is
/// taken, where OSL's dual pow computes x^(y-1) * x (so 0^0 is 0 there,
/// and other values may round differently). Both are built; the
/// derivatives pass picks (kDualRuleOslPow), and the unused one folds away.
Value lane::pow(OpBuilder &b, Location loc, ValueRange x) {
  Value base = x[0], e = x[1];
  Value plain = safePow(b, loc, base, e);
  Value below = safePow(b, loc, base, b.create<arith::SubFOp>(loc, e, cst(b, loc, e, 1)));
  Value dual = b.create<arith::MulFOp>(loc, below, base);
  // Always false; its operands tell osl-derivatives x and y.
  Value carrier = fcmp(b, loc, arith::CmpFPredicate::AlwaysFalse, base, e);
  Value result = sel(b, loc, carrier, dual, plain);
  result.getDefiningOp()->setAttr(kDualRuleAttr, b.getStringAttr(kDualRuleOslPow));
  return result;
}

/// x - N*y for N = trunc(x * (1/y)), corrected by one where that quotient
/// rounded across an integer; exact (the remainder for the right N is
/// representable and one fused multiply-add makes it) while |x/y| < 2^22.
static Value remainderStep(OpBuilder &b, Location loc, Value x, Value y, double divisor) {
  Value q = b.create<arith::MulFOp>(loc, x, cst(b, loc, x, double(1.0f / float(divisor))));
  Value n = b.create<math::TruncOp>(loc, q);
  Value r = b.create<math::FmaOp>(loc, b.create<arith::NegFOp>(loc, n), y, x);
  Value zero = cst(b, loc, x, 0);
  // Overshot: the remainder's sign is not x's; undershot: |r| >= |y|.
  Value over = sel(b, loc, fcmp(b, loc, arith::CmpFPredicate::OLT, x, zero),
                   fcmp(b, loc, arith::CmpFPredicate::OGT, r, zero),
                   fcmp(b, loc, arith::CmpFPredicate::OLT, r, zero));
  Value under = fcmp(b, loc, arith::CmpFPredicate::OGE, b.create<math::AbsFOp>(loc, r),
                     b.create<math::AbsFOp>(loc, y));
  Value qSign = b.create<math::CopySignOp>(loc, cst(b, loc, q, 1), q);
  Value step = sel(b, loc, over, b.create<arith::NegFOp>(loc, qSign),
                   sel(b, loc, under, qSign, zero));
  return b.create<math::FmaOp>(
      loc, b.create<arith::NegFOp>(loc, b.create<arith::AddFOp>(loc, n, step)), y, x);
}

/// fmod by a constant, nonzero divisor: C's remainder, exactly, as OSL's
/// scalar backend computes it (LLVM's frem; its batched backend uses frem
/// for every divisor): fmod(2.1, 0.7) is 0.699999928, where x - N*y gives
/// -5.96e-08. Remainders by y * 2^44 and y * 2^22 first (multiples of y,
/// so the remainder is the same; a step whose divisor overflows is left
/// out) keep each step's quotient below 2^22: exact for |x/y| < 2^66, as a
/// libm call per lane would be, at a fraction of the cost (the quotients
/// multiply by the reciprocal: the steps correct N). Past 2^66 the result
/// is inexact (fmod(1e30, 0.1)).
static Value fmodByConstant(OpBuilder &b, Location loc, Value x, Value y, double divisor) {
  std::vector<double> steps;
  for (int k = 2; k >= 1; --k) {
    double coarse = double(float(std::ldexp(divisor, 22 * k)));
    if (std::isfinite(coarse) && std::isfinite(1.0f / float(coarse)))
      steps.push_back(coarse);
  }
  Value r = x;
  for (double coarse : steps)
    r = remainderStep(b, loc, r, cst(b, loc, y, coarse), coarse);
  r = remainderStep(b, loc, r, y, divisor);
  // A zero remainder has x's sign, as C's (-0 for a negative x, -0 too).
  Value zero = cst(b, loc, x, 0);
  Value isZero = fcmp(b, loc, arith::CmpFPredicate::OEQ, r, zero);
  Value result = sel(b, loc, isZero, b.create<math::CopySignOp>(loc, zero, x), r);
  if (Operation *op = result.getDefiningOp())
    op->setAttr(kDualRuleAttr, b.getStringAttr(kDualRuleValueOnly));
  return result;
}

/// fmod: by a constant, C's remainder (fmodByConstant); otherwise OSL's
/// (OIIO's) safe_fmod, which OSL's scalar backend calls where the divisor
/// is not a constant: x - N*y with N = int(x/y), and 0 where y = 0. N
/// converts as x86 does, INT_MIN when x/y is out of int's range (or NaN),
/// so huge quotients give OSL's large results, not C fmod's remainder. The
/// derivative is x's alone, as OSL's dual fmod has it, also where y = 0.
Value lane::fmod(OpBuilder &b, Location loc, ValueRange x) {
  std::optional<double> constantDivisor = constantLaneValue(x[1]);
  if (constantDivisor && *constantDivisor != 0 && std::isfinite(float(*constantDivisor)) &&
      std::isfinite(1.0f / float(*constantDivisor)))
    return fmodByConstant(b, loc, x[0], x[1], *constantDivisor);
  Value zero = cst(b, loc, x[1], 0);
  Value isZero = fcmp(b, loc, arith::CmpFPredicate::OEQ, x[1], zero);
  // y made safe, and without derivative: x - N*y then keeps x's alone (N
  // is piecewise constant).
  Value safeDen = sel(b, loc, isZero, cst(b, loc, x[1], 1), x[1]);
  if (Operation *op = safeDen.getDefiningOp())
    op->setAttr(kDualRuleAttr, b.getStringAttr(kDualRuleNone));
  Value q = b.create<arith::DivFOp>(loc, x[0], safeDen);
  Value intMin = cst(b, loc, q, -2147483648.0);
  Value inRange = b.create<arith::AndIOp>(
      loc, fcmp(b, loc, arith::CmpFPredicate::OGE, q, intMin),
      fcmp(b, loc, arith::CmpFPredicate::OLT, q, cst(b, loc, q, 2147483648.0)));
  Value n = sel(b, loc, inRange, b.create<math::TruncOp>(loc, q), intMin);
  // x - N*y is one fused multiply-add in OSL's library (as madd is, see
  // OslMathApproximation.cpp).
  Value r = b.create<math::FmaOp>(loc, b.create<arith::NegFOp>(loc, n), safeDen, x[0]);
  Value result = sel(b, loc, isZero, zero, r);
  if (Operation *op = result.getDefiningOp())
    op->setAttr(kDualRuleAttr, b.getStringAttr(kDualRuleValueOnly));
  return result;
}

Value lane::step(OpBuilder &b, Location loc, ValueRange x) {
  Value below = fcmp(b, loc, arith::CmpFPredicate::OLT, x[1], x[0]);
  return sel(b, loc, below, cst(b, loc, x[1], 0), cst(b, loc, x[1], 1));
}

/// a*(1-t) + b*t, OSL's operation order.
Value lane::mix(OpBuilder &b, Location loc, ValueRange x) {
  Value oneMinusT = b.create<arith::SubFOp>(loc, cst(b, loc, x[2], 1), x[2]);
  return b.create<arith::AddFOp>(loc, b.create<arith::MulFOp>(loc, x[0], oneMinusT),
                                 b.create<arith::MulFOp>(loc, x[1], x[2]));
}

/// OSL's order, max(min(x, hi), lo): with inverted bounds lo wins.
Value lane::clamp(OpBuilder &b, Location loc, ValueRange x) {
  return max(b, loc, {min(b, loc, {x[0], x[2]}), x[1]});
}

Value lane::smoothstep(OpBuilder &b, Location loc, ValueRange x) {
  Value e0 = x[0], e1 = x[1], v = x[2];
  Value t = b.create<arith::DivFOp>(loc, b.create<arith::SubFOp>(loc, v, e0),
                                    b.create<arith::SubFOp>(loc, e1, e0));
  Value three = cst(b, loc, v, 3), two = cst(b, loc, v, 2);
  Value poly = b.create<arith::MulFOp>(
      loc, b.create<arith::MulFOp>(loc, t, t),
      b.create<arith::SubFOp>(loc, three, b.create<arith::MulFOp>(loc, two, t)));
  Value below = fcmp(b, loc, arith::CmpFPredicate::OLT, v, e0);
  Value above = fcmp(b, loc, arith::CmpFPredicate::OGE, v, e1);
  return sel(b, loc, below, cst(b, loc, v, 0),
             sel(b, loc, above, cst(b, loc, v, 1), poly));
}

Value lane::select(OpBuilder &b, Location loc, ValueRange x) {
  return sel(b, loc, x[0], x[1], x[2]);
}

/// As OSL: every component compared, the results and-ed, except != whose
/// are or-ed.
Value lane::compareComponents(OpBuilder &b, Location loc, StringRef predicate,
                              ValueRange lhs, ValueRange rhs, bool unordered) {
  Value result;
  for (auto [l, r] : llvm::zip(lhs, rhs)) {
    Value c = compare(b, loc, predicate, l, r, unordered);
    if (!result)
      result = c;
    else if (predicate == "ne")
      result = b.create<arith::OrIOp>(loc, result, c);
    else
      result = b.create<arith::AndIOp>(loc, result, c);
  }
  return result;
}

/// Ordered, except != (true with a NaN), unless `unordered`: OSL's JIT
/// compares a shader's floats unordered (every comparison with a NaN is
/// true), while library functions such as isinf and smoothstep, which the
/// front end builds from osl.cmp, need ordered ones.
Value lane::compare(OpBuilder &b, Location loc, StringRef p, Value lhs, Value rhs,
                    bool unordered) {
  if (isFloat(lhs) && p == "same") {
    // Compare the bits: the same float bits make the same results.
    Type bits = b.getIntegerType(getElementTypeOrSelf(lhs.getType()).getIntOrFloatBitWidth());
    if (auto v = dyn_cast<VectorType>(lhs.getType()))
      bits = VectorType::get(v.getShape(), bits);
    return icmp(b, loc, arith::CmpIPredicate::eq, b.create<arith::BitcastOp>(loc, bits, lhs),
                b.create<arith::BitcastOp>(loc, bits, rhs));
  }
  if (isFloat(lhs)) {
    using P = arith::CmpFPredicate;
    auto pred = llvm::StringSwitch<P>(p)
                    .Case("eq", unordered ? P::UEQ : P::OEQ)
                    .Case("ne", P::UNE)
                    .Case("lt", unordered ? P::ULT : P::OLT)
                    .Case("le", unordered ? P::ULE : P::OLE)
                    .Case("gt", unordered ? P::UGT : P::OGT)
                    .Default(unordered ? P::UGE : P::OGE);
    return fcmp(b, loc, pred, lhs, rhs);
  }
  auto pred = llvm::StringSwitch<arith::CmpIPredicate>(p)
                  .Cases("eq", "same", arith::CmpIPredicate::eq)
                  .Case("ne", arith::CmpIPredicate::ne)
                  .Case("lt", arith::CmpIPredicate::slt)
                  .Case("le", arith::CmpIPredicate::sle)
                  .Case("gt", arith::CmpIPredicate::sgt)
                  .Default(arith::CmpIPredicate::sge);
  return icmp(b, loc, pred, lhs, rhs);
}

Value lane::convert(OpBuilder &b, Location loc, Value x, Type to) {
  Type from = getElementTypeOrSelf(x.getType());
  Type toLane = withElement(x.getType(), to);
  if (from == to)
    return x;
  if (to.isInteger(1))
    return isFloat(x) ? fcmp(b, loc, arith::CmpFPredicate::UNE, x, cst(b, loc, x, 0))
                      : icmp(b, loc, arith::CmpIPredicate::ne, x, cst(b, loc, x, 0));
  if (isBool(x))
    return to.isF32() ? b.create<arith::UIToFPOp>(loc, toLane, x).getResult()
                      : b.create<arith::ExtUIOp>(loc, toLane, x).getResult();
  if (to.isF32())
    return b.create<arith::SIToFPOp>(loc, toLane, x);
  // int(x) truncates toward zero. NaN and values past int's range give
  // INT_MIN, as x86's conversion (and so OSL) does: fptosi alone would be
  // poison there, which LLVM folds to anything for a constant.
  // (|x| < 2^31 leaves out -2^31 itself, whose int is INT_MIN anyway.)
  Value truncated = b.create<arith::FPToSIOp>(loc, toLane, x);
  Value inRange = fcmp(b, loc, arith::CmpFPredicate::OLT, b.create<math::AbsFOp>(loc, x),
                       cst(b, loc, x, 2147483648.0));
  return sel(b, loc, inRange, truncated, cst(b, loc, truncated, -2147483648.0));
}
