//===- MathLevels.h - the fast and precise math levels ----------*- C++ -*-===//
//
// Internal to osl-approximate-math: the `default` level (OSL's algorithms)
// lives in OslMathApproximation.cpp, the other two here.
//
//===----------------------------------------------------------------------===//
#ifndef OSLTRANSFORMS_MATHLEVELS_H
#define OSLTRANSFORMS_MATHLEVELS_H

#include "mlir/IR/BuiltinOps.h"
#include "mlir/IR/PatternMatch.h"

namespace mlir::osl {

/// MLIR's polynomial approximations for every f32 math op they cover, plus
/// the expansions that route the others through them (tan -> sin/cos,
/// exp2 and pow -> exp/log, log10 -> log).
void populateFastMathPatterns(RewritePatternSet &patterns);

/// The ops the fast level computes with OSL's algorithm rather than MLIR's
/// (measured faster, or MLIR's breaks down).
bool isOslFasterAt(Operation *op);

/// OSL's rules where MLIR's approximations break down (sin/cos of huge
/// arguments, atan2 of two infinities); runs before the fast patterns.
/// `oslAlgorithmsWhereFaster`: the fast level, which leaves isOslFasterAt
/// ops to OSL's algorithms.
void guardFastMath(ModuleOp module, bool oslAlgorithmsWhereFaster);

/// Rewrites each transcendental f32 math op as extf -> the op in f64 ->
/// truncf, and the f64 op as a call to glibc's double function (one call
/// per lane of a vector).
LogicalResult computeInDoubleWithLibm(ModuleOp module);

} // namespace mlir::osl

#endif // OSLTRANSFORMS_MATHLEVELS_H
