//===- UniformDivisor.cpp - int / and % of lanes by one divisor -----------===//
#include "OslLanes/UniformDivisor.h"
#include "OslLanes/LaneMath.h"

#include "mlir/Dialect/Arith/IR/Arith.h"
#include "mlir/Dialect/Math/IR/Math.h"
#include "mlir/Dialect/Vector/IR/VectorOps.h"
#include "mlir/IR/Matchers.h"

using namespace mlir;

namespace {

/// What every lane needs to divide |n| by |d| (figure 4.1 with N = 32):
/// with l = ceil(log2 |d|), m = floor(2^32 (2^l - |d|) / |d|) + 1,
/// t = mulhi(m, |n|), |n| / |d| = (t + ((|n| - t) >> sh1)) >> sh2 where
/// sh1 = min(l, 1), sh2 = l - sh1. A zero divisor divides as 1 (OSL's
/// result is then chosen by `isZero`).
struct Divisor {
  Value multiplier, shift1, shift2; // scalars, i32
  Value isZero;                     // scalar i1
};

Value i32(OpBuilder &b, Location loc, int64_t v) {
  return b.create<arith::ConstantIntOp>(loc, v, 32);
}

Divisor prepare(OpBuilder &b, Location loc, Value d) {
  Value zero = i32(b, loc, 0), one = i32(b, loc, 1);
  Value isZero = b.create<arith::CmpIOp>(loc, arith::CmpIPredicate::eq, d, zero);
  // |d| as an unsigned 32-bit value (|INT_MIN| = 2^31).
  Value absD = b.create<math::AbsIOp>(loc, d);
  absD = b.create<arith::SelectOp>(loc, isZero, one, absD);
  Value lead = b.create<math::CountLeadingZerosOp>(
      loc, b.create<arith::SubIOp>(loc, absD, one));
  Value log2Ceil = b.create<arith::SubIOp>(loc, i32(b, loc, 32), lead);
  Type i64 = b.getI64Type();
  auto wide = [&](Value v) { return b.create<arith::ExtUIOp>(loc, i64, v); };
  Value pow2 = b.create<arith::ShLIOp>(loc, b.create<arith::ConstantIntOp>(loc, 1, 64),
                                       wide(log2Ceil));
  Value scaled = b.create<arith::ShLIOp>(loc, b.create<arith::SubIOp>(loc, pow2, wide(absD)),
                                         b.create<arith::ConstantIntOp>(loc, 32, 64));
  Value multiplier = b.create<arith::TruncIOp>(
      loc, b.getI32Type(),
      b.create<arith::AddIOp>(loc, b.create<arith::DivUIOp>(loc, scaled, wide(absD)),
                              b.create<arith::ConstantIntOp>(loc, 1, 64)));
  Value shift1 = b.create<arith::MinUIOp>(loc, log2Ceil, one);
  Value shift2 = b.create<arith::SubIOp>(loc, log2Ceil, shift1);
  return {multiplier, shift1, shift2, isZero};
}

/// The truncated quotient n / d of every lane, before OSL's x/0 rule.
Value quotient(OpBuilder &b, Location loc, Value num, Value d, const Divisor &div) {
  int64_t width = cast<VectorType>(num.getType()).getNumElements();
  auto splat = [&](Value scalar) { return osl::lane::broadcast(b, loc, scalar, width); };
  // |n| as unsigned: |INT_MIN| = 2^31 keeps its bits.
  Value absN = b.create<math::AbsIOp>(loc, num);
  Value high = b.create<arith::MulUIExtendedOp>(loc, absN, splat(div.multiplier))
                   .getHigh();
  Value rest = b.create<arith::ShRUIOp>(loc, b.create<arith::SubIOp>(loc, absN, high),
                                        splat(div.shift1));
  Value absQ = b.create<arith::ShRUIOp>(loc, b.create<arith::AddIOp>(loc, high, rest),
                                        splat(div.shift2));
  // The sign of n xor d, as 0 or -1 in every bit: (q ^ s) - s negates
  // where the signs differ (INT_MIN / -1 wraps to INT_MIN, OSL's result).
  Value sign = b.create<arith::ShRSIOp>(
      loc, b.create<arith::XOrIOp>(loc, num, splat(d)),
      splat(i32(b, loc, 31)));
  return b.create<arith::SubIOp>(loc, b.create<arith::XOrIOp>(loc, absQ, sign), sign);
}

Value zeroWhere(OpBuilder &b, Location loc, Value isZero, Value v) {
  Value zero = b.create<arith::ConstantOp>(loc, b.getZeroAttr(v.getType()));
  return b.create<arith::SelectOp>(loc, isZero, zero, v);
}

} // namespace

Value mlir::osl::lane::uniformDivisorOf(Value den) {
  auto broadcast = den.getDefiningOp<vector::BroadcastOp>();
  if (!broadcast || isa<VectorType>(broadcast.getSourceType()) ||
      !broadcast.getSourceType().isInteger(32) || matchPattern(broadcast.getSource(), m_Constant()))
    return {};
  return broadcast.getSource();
}

Value mlir::osl::lane::divideByUniform(OpBuilder &b, Location loc, Value num, Value d) {
  Divisor div = prepare(b, loc, d);
  return zeroWhere(b, loc, div.isZero, quotient(b, loc, num, d, div));
}

Value mlir::osl::lane::remainderByUniform(OpBuilder &b, Location loc, Value num, Value d) {
  Divisor div = prepare(b, loc, d);
  Value q = quotient(b, loc, num, d, div);
  // n - q*d wraps to 0 for d = -1 (INT_MIN too), OSL's x % -1.
  Value r = b.create<arith::SubIOp>(
      loc, num,
      b.create<arith::MulIOp>(
          loc, q, osl::lane::broadcast(b, loc, d, cast<VectorType>(num.getType()).getNumElements())));
  return zeroWhere(b, loc, div.isZero, r);
}
