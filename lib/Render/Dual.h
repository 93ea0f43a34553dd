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

inline Dual sqrt(Dual a) {
  if (!(a.v > 0))
    return {};
  float f = std::sqrt(a.v);
  return a.chain(f, 0.5f / f);
}

/// atan2 with OSL's slopes (its sign convention included).
inline Dual atan2(Dual y, Dual x) {
  float f = std::atan2(y.v, x.v);
  float denom = (x.v == 0 && y.v == 0) ? 0.0f : 1 / (x.v * x.v + y.v * y.v);
  float dfdy = -x.v * denom, dfdx = y.v * denom;
  return {f, dfdy * y.dx + dfdx * x.dx, dfdy * y.dy + dfdx * x.dy};
}

/// acos clamped to [0, pi] outside [-1, 1] (no slope there).
inline Dual safeAcos(Dual a) {
  if (a.v >= 1)
    return {0};
  if (a.v <= -1)
    return {float(M_PI)};
  return a.chain(std::acos(a.v), -1 / std::sqrt(1 - a.v * a.v));
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
  Dual x() const { return {v.x, dx.x, dy.x}; }
  Dual y() const { return {v.y, dx.y, dy.y}; }
  Dual z() const { return {v.z, dx.z, dy.z}; }
  static Dual3 of(Dual x, Dual y, Dual z) {
    return {{x.v, y.v, z.v}, {x.dx, y.dx, z.dx}, {x.dy, y.dy, z.dy}};
  }
};

/// The unit vector along `a` (0 for 0), by its inverse length.
inline Dual3 normalize(const Dual3 &a) {
  Dual ax = a.x(), ay = a.y(), az = a.z();
  Dual len = sqrt(ax * ax + ay * ay + az * az);
  if (!(len.v > 0))
    return {};
  Dual inv = 1.0f / len;
  return Dual3::of(ax * inv, ay * inv, az * inv);
}

inline Dual dot(const Dual3 &a, Vec3 b) { return a.x() * b.x + a.y() * b.y + a.z() * b.z; }

} // namespace osl::render

#endif // OSLRENDER_DUAL_H
