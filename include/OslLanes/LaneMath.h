//===- LaneMath.h - OSL semantics on lane values ----------------*- C++ -*-===//
//
// A lane value is one scalar per shading point: f32/i32/i1 for a uniform
// value, vector<W x f32/i32/i1> for a varying one. Every function here
// builds the same arith/math ops for both, so uniform and varying code (and
// every width) compute bit-identical results. OSL's edge rules (safe
// division, clamped asin, log of 0...) live here and nowhere else.
//
//===----------------------------------------------------------------------===//
#ifndef OSLLANES_LANEMATH_H
#define OSLLANES_LANEMATH_H

#include "mlir/IR/Builders.h"
#include "mlir/IR/Value.h"

namespace mlir::osl {
/// Marks an operation whose derivative follows OSL's dual-number rule
/// rather than the chain rule through it (read by osl-derivatives):
/// kDualRuleOslAtan2 on math.atan2, kDualRuleValueOnly on a select that
/// overrides a value in a special case without changing its derivative
/// (the derivative is the false operand's), kDualRuleNone on an op whose
/// result has no derivative in OSL (blackbody, wavelength_color),
/// kDualRuleSignFlip on the bitcast that ends bitcast(xor(bitcast(v), s))
/// where s holds only sign bits (its derivative is v's, flipped alike),
/// kDualRuleOslPow on pow's select(cmpf false x y, dual, plain): where its
/// derivative is taken, OSL's dual pow x^(y-1) * x (`dual`) is the value
/// too, and the derivative is OSL's; elsewhere the select folds to `plain`.
inline constexpr const char *kDualRuleAttr = "osl.dual_rule";
inline constexpr const char *kDualRuleOslPow = "osl_pow";
inline constexpr const char *kDualRuleOslAtan2 = "osl_atan2";
inline constexpr const char *kDualRuleValueOnly = "value_only";
inline constexpr const char *kDualRuleNone = "none";
inline constexpr const char *kDualRuleSignFlip = "sign_flip";
/// Marks loads that are not shader globals (constant tables, texture
/// results): osl-derivatives gives them no derivative.
inline constexpr const char *kNoDerivativeAttr = "osl.no_derivative";
/// On the load of a 2D texture lookup's result row (its index in the
/// lookup's block, OslAbi/Texture.h): osl-derivatives makes its
/// derivative from the slopes the texture system wrote beside it.
inline constexpr const char *kTextureResultRowAttr = "osl.texture_result_row";
/// Marks the arithmetic steps of one library function built from several
/// ops (sinh from exp, asin from atan2 and sqrt, log10 as a scaled log...):
/// at --math=precise they are evaluated in double together with the
/// transcendental op they feed or follow, so the function is rounded once
/// (MathLevels.cpp). Other levels ignore it.
inline constexpr const char *kOneRoundingAttr = "osl.one_rounding";

} // namespace mlir::osl

namespace mlir::osl::lane {

/// A constant with the shape of `like` (a lane type or a value's type).
Value constant(OpBuilder &b, Location loc, Type like, double value);
Value constantLike(OpBuilder &b, Location loc, Value like, double value);
/// `laneType` with its element replaced by `element`.
Type withElement(Type laneType, Type element);
/// Broadcasts a scalar to `width` lanes (width 0: leave scalar).
Value broadcast(OpBuilder &b, Location loc, Value scalar, int64_t width);
/// Whether any lane of the i1 lane value `mask` is set (a scalar is its own
/// answer): the condition of loops that run while some lane needs them.
Value any(OpBuilder &b, Location loc, Value mask);

Value add(OpBuilder &b, Location loc, ValueRange x);
Value sub(OpBuilder &b, Location loc, ValueRange x);
Value mul(OpBuilder &b, Location loc, ValueRange x);
Value div(OpBuilder &b, Location loc, ValueRange x);
Value mod(OpBuilder &b, Location loc, ValueRange x);
Value neg(OpBuilder &b, Location loc, ValueRange x);
Value min(OpBuilder &b, Location loc, ValueRange x);
Value max(OpBuilder &b, Location loc, ValueRange x);
Value abs(OpBuilder &b, Location loc, ValueRange x);
Value logicalAnd(OpBuilder &b, Location loc, ValueRange x);
Value logicalOr(OpBuilder &b, Location loc, ValueRange x);
Value logicalNot(OpBuilder &b, Location loc, ValueRange x);
Value bitAnd(OpBuilder &b, Location loc, ValueRange x);
Value bitOr(OpBuilder &b, Location loc, ValueRange x);
Value bitXor(OpBuilder &b, Location loc, ValueRange x);
Value bitNot(OpBuilder &b, Location loc, ValueRange x);
Value shl(OpBuilder &b, Location loc, ValueRange x);
Value shr(OpBuilder &b, Location loc, ValueRange x);

Value sin(OpBuilder &b, Location loc, ValueRange x);
Value cos(OpBuilder &b, Location loc, ValueRange x);
Value tan(OpBuilder &b, Location loc, ValueRange x);
Value asin(OpBuilder &b, Location loc, ValueRange x);
Value acos(OpBuilder &b, Location loc, ValueRange x);
Value atan(OpBuilder &b, Location loc, ValueRange x);
Value atan2(OpBuilder &b, Location loc, ValueRange x);
Value exp(OpBuilder &b, Location loc, ValueRange x);
Value exp2(OpBuilder &b, Location loc, ValueRange x);
Value log(OpBuilder &b, Location loc, ValueRange x);
Value log2(OpBuilder &b, Location loc, ValueRange x);
Value log10(OpBuilder &b, Location loc, ValueRange x);
Value sinh(OpBuilder &b, Location loc, ValueRange x);
Value cosh(OpBuilder &b, Location loc, ValueRange x);
/// osl-mlir's own formulas for the fast and polynomial levels: asin and
/// acos of a clamped `c` through atan2 and sqrt, sinh and cosh through one
/// exp (and a polynomial for sinh near 0).
Value asinFromAtan2(OpBuilder &b, Location loc, Value c);
Value acosFromAtan2(OpBuilder &b, Location loc, Value c);
Value sinhFromExp(OpBuilder &b, Location loc, Value x);
Value log10FromLog(OpBuilder &b, Location loc, Value x);
Value coshFromExp(OpBuilder &b, Location loc, Value x);
Value tanh(OpBuilder &b, Location loc, ValueRange x);
Value expm1(OpBuilder &b, Location loc, ValueRange x);
Value cbrt(OpBuilder &b, Location loc, ValueRange x);
Value erf(OpBuilder &b, Location loc, ValueRange x);
Value erfc(OpBuilder &b, Location loc, ValueRange x);
Value logb(OpBuilder &b, Location loc, ValueRange x);
Value linearstep(OpBuilder &b, Location loc, ValueRange x);
Value sqrt(OpBuilder &b, Location loc, ValueRange x);
Value inverseSqrt(OpBuilder &b, Location loc, ValueRange x);
Value floor(OpBuilder &b, Location loc, ValueRange x);
Value ceil(OpBuilder &b, Location loc, ValueRange x);
Value round(OpBuilder &b, Location loc, ValueRange x);
Value trunc(OpBuilder &b, Location loc, ValueRange x);
Value sign(OpBuilder &b, Location loc, ValueRange x);
Value pow(OpBuilder &b, Location loc, ValueRange x);
Value fmod(OpBuilder &b, Location loc, ValueRange x);
Value step(OpBuilder &b, Location loc, ValueRange x);
Value mix(OpBuilder &b, Location loc, ValueRange x);
Value clamp(OpBuilder &b, Location loc, ValueRange x);
Value smoothstep(OpBuilder &b, Location loc, ValueRange x);
Value select(OpBuilder &b, Location loc, ValueRange x);

/// OSL comparison `predicate` (eq, ne, lt, le, gt, ge) on two lane values;
/// `unordered`: floats compare true with a NaN (osl.cmp's attribute).
Value compare(OpBuilder &b, Location loc, StringRef predicate, Value lhs,
              Value rhs, bool unordered = false);
/// `compare` on values split into components (a triple's three lane
/// values): triples are equal when every component is.
Value compareComponents(OpBuilder &b, Location loc, StringRef predicate, ValueRange lhs,
                        ValueRange rhs, bool unordered = false);
/// Converts between f32, i32 and i1 lane values with OSL's rules.
Value convert(OpBuilder &b, Location loc, Value x, Type toElement);

} // namespace mlir::osl::lane

#endif // OSLLANES_LANEMATH_H
