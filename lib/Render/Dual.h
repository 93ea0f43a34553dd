//===- Dual.h - Values with their screen-space derivatives --------*- C++ -*-===//
//
// A float with its derivatives along the image's x and y, for the ray
// differentials testrender gives its shading points (texture filter widths,
// bump mapping). The rules, operand order included, are those of OSL's
// Dual2 (dual.h), so the derivatives come out as testrender's.
//
//===----------------------------------------------------------------------===//
#ifndef OSLRENDER_DUAL_H
#define OSLRENDER_DUAL_H

#include "OslRender/Sampling.h"

#include <cmath>

namespace osl::render {

struct Dual {
  float v = 0, dx = 0, dy = 0;
  Dual() = default;
  constexpr Dual(float v, float dx = 0, float dy = 0) : v(v), dx(dx), dy(dy) {}
  /// f(this) given f's value and slope here.
  Dual chain(float f, float df) const { return {f, df * dx, df * dy}; }
};

inline Dual operator+(Dual a, Dual b) { return {a.v + b.v, a.dx + b.dx, a.dy + b.dy}; }
inline Dual operator-(Dual a, Dual b) { return {a.v - b.v, a.dx - b.dx, a.dy - b.dy}; }
inline Dual operator-(float a, Dual b) { return {a - b.v, -b.dx, -b.dy}; }
inline Dual operator*(Dual a, Dual b) {
  return {a.v * b.v, a.v * b.dx + a.dx * b.v, a.v * b.dy + a.dy * b.v};
}
inline Dual operator*(Dual a, float s) { return {a.v * s, a.dx * s, a.dy * s}; }
inline Dual operator*(float s, Dual a) { return {a.v * s, a.dx * s, a.dy * s}; }
inline Dual operator/(float a, Dual b) {
  float inv = 1 / b.v, q = a / b.v;
  return {q, inv * (-q * b.dx), inv * (-q * b.dy)};
}

/// c ? a : b, part by part (vectorizable, as Vec3's select).
inline Dual select(bool c, Dual a, Dual b) {
  return {c ? a.v : b.v, c ? a.dx : b.dx, c ? a.dy : b.dy};
}

/// sqrt, 0 (no slope) where a is not positive. Selects, not branches:
/// lane loops vectorize it.
inline Dual sqrt(Dual a) {
  bool positive = a.v > 0;
  float f = std::sqrt(a.v);
  return select(positive, a.chain(f, 0.5f / f), Dual());
}

/// atan2's slopes alone, OSL's (its sign convention included), with the
/// value 0: they do not need the value, so lanes compute them while libm's
/// std::atan2 computes the value one lane at a time.
inline Dual atan2Slopes(Dual y, Dual x) {
  float denom = (x.v == 0 && y.v == 0) ? 0.0f : 1 / (x.v * x.v + y.v * y.v);
  float dfdy = -x.v * denom, dfdx = y.v * denom;
  return {0, dfdy * y.dx + dfdx * x.dx, dfdy * y.dy + dfdx * x.dy};
}

/// acos clamped to [0, pi] outside [-1, 1] (no slope there): its value,
/// and its slopes alone (value 0), as atan2's.
inline float safeAcosValue(float a) {
  return a >= 1 ? 0.0f : a <= -1 ? float(M_PI) : std::acos(a);
}
inline Dual safeAcosSlopes(Dual a) {
  bool inside = !(a.v >= 1) && !(a.v <= -1);
  float df = -1 / std::sqrt(1 - a.v * a.v);
  return {0, inside ? df * a.dx : 0.0f, inside ? df * a.dy : 0.0f};
}

inline void fastSinCos(Dual a, Dual &s, Dual &c) {
  float sa, ca;
  fast::sincos(a.v, sa, ca);
  c = a.chain(ca, -sa);
  s = a.chain(sa, ca);
}

/// A vector with its derivatives.
struct Dual3 {
  Vec3 v, dx, dy;
  static Dual3 of(Dual x, Dual y, Dual z) {
    return {{x.v, y.v, z.v}, {x.dx, y.dx, z.dx}, {x.dy, y.dy, z.dy}};
  }
};

/// Vectors with derivatives as their three Duals, not Dual3s: lane loops
/// keep Duals in registers, while a Dual3's parts would go through memory.
/// (x, y, z) made unit (0 for 0), by its inverse length.
inline void normalize(Dual &x, Dual &y, Dual &z) {
  Dual len = sqrt(x * x + y * y + z * z);
  bool positive = len.v > 0;
  Dual inv = 1.0f / len;
  x = select(positive, x * inv, Dual());
  y = select(positive, y * inv, Dual());
  z = select(positive, z * inv, Dual());
}

inline Dual dot(Dual x, Dual y, Dual z, Vec3 b) { return x * b.x + y * b.y + z * b.z; }

} // namespace osl::render

#endif // OSLRENDER_DUAL_H
