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

/// Rewrites each transcendental f32 math op as extf -> the op in f64 ->
/// truncf, and the f64 op as a call to glibc's double function (one call
/// per lane of a vector).
LogicalResult computeInDoubleWithLibm(ModuleOp module);

} // namespace mlir::osl

#endif // OSLTRANSFORMS_MATHLEVELS_H
