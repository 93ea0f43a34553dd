//===- UniformDivisor.h - int / and % of lanes by one divisor ---*- C++ -*-===//
//
// x86 has no vector integer division: a vector sdiv becomes one scalar
// idiv per lane. When every lane divides by the same run-time int (a
// uniform base, a loop-invariant count), the divisor's multiplier and
// shifts are computed once in scalar code and each lane then takes a
// multiply-high, an add and two shifts (Granlund & Montgomery, "Division by
// invariant integers using multiplication", 1994, figure 4.1, applied to
// |n| and |d|). Exact for every int, so results equal idiv's at any width.
//
//===----------------------------------------------------------------------===//
#ifndef OSLLANES_UNIFORMDIVISOR_H
#define OSLLANES_UNIFORMDIVISOR_H

#include "mlir/IR/Builders.h"

namespace mlir::osl::lane {

/// The scalar i32 divisor broadcast to every lane of `den`, when `den` is a
/// broadcast of a value not known at compile time (LLVM already divides by
/// constants with multiplications).
Value uniformDivisorOf(Value den);

/// OSL's `num / d` (x/0 = 0, INT_MIN / -1 = INT_MIN) and `num % d`
/// (x%0 = 0, truncating), for a vector of i32 `num` and a scalar i32 `d`.
Value divideByUniform(OpBuilder &b, Location loc, Value num, Value d);
Value remainderByUniform(OpBuilder &b, Location loc, Value num, Value d);

} // namespace mlir::osl::lane

#endif // OSLLANES_UNIFORMDIVISOR_H
