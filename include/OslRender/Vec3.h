//===- Vec3.h - The renderer's small vector math -----------------*- C++ -*-===//
#ifndef OSLRENDER_VEC3_H
#define OSLRENDER_VEC3_H

#include <array>
#include <cmath>

namespace osl::render {

struct Vec3 {
  float x = 0, y = 0, z = 0;
  Vec3() = default;
  constexpr Vec3(float x, float y, float z) : x(x), y(y), z(z) {}
  explicit Vec3(const std::array<float, 3> &a) : x(a[0]), y(a[1]), z(a[2]) {}
  Vec3 operator+(Vec3 o) const { return {x + o.x, y + o.y, z + o.z}; }
  Vec3 operator-(Vec3 o) const { return {x - o.x, y - o.y, z - o.z}; }
  Vec3 operator*(Vec3 o) const { return {x * o.x, y * o.y, z * o.z}; }
  Vec3 operator*(float s) const { return {x * s, y * s, z * s}; }
  Vec3 operator/(float s) const { return {x / s, y / s, z / s}; }
  Vec3 operator-() const { return {-x, -y, -z}; }
  Vec3 &operator+=(Vec3 o) { return *this = *this + o; }
  Vec3 &operator*=(Vec3 o) { return *this = *this * o; }
  Vec3 &operator*=(float s) { return *this = *this * s; }
  float operator[](int i) const { return i == 0 ? x : i == 1 ? y : z; }
  float max() const { return std::fmax(x, std::fmax(y, z)); }
  float sum() const { return x + y + z; }
  bool isZero() const { return !(x > 0) && !(y > 0) && !(z > 0); }
};

inline Vec3 operator*(float s, Vec3 v) { return v * s; }
inline float dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline Vec3 cross(Vec3 a, Vec3 b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline float length(Vec3 v) { return std::sqrt(dot(v, v)); }
/// v / |v|, or v where its length is 0 (or NaN): divided by 1 there, the
/// same bits, with no select of whole vectors (which lane loops cannot
/// vectorize).
inline Vec3 normalize(Vec3 v) {
  float l = length(v);
  return v / (l > 0 ? l : 1.0f);
}
/// c ? a : b, component by component (vectorizable, as normalize).
inline Vec3 select(bool c, Vec3 a, Vec3 b) {
  return {c ? a.x : b.x, c ? a.y : b.y, c ? a.z : b.z};
}
/// Luminance of a linear Rec.709 color.
inline float luminance(Vec3 c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }

/// An orthonormal frame around unit vector `n` (z = n).
struct Frame {
  Vec3 x, y, z;
  explicit Frame(Vec3 n) : z(n) {
    // Duff et al.'s branchless basis.
    float sign = std::copysign(1.0f, n.z);
    float a = -1.0f / (sign + n.z);
    float b = n.x * n.y * a;
    x = Vec3(1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x);
    y = Vec3(b, sign + n.y * n.y * a, -n.y);
  }
  /// A frame around `n` whose x axis follows `u` (projected) when it can.
  Frame(Vec3 n, Vec3 u) : Frame(n) {
    Vec3 t = u - n * dot(n, u);
    if (dot(t, t) > 1e-12f) {
      x = normalize(t);
      y = cross(n, x);
    }
  }
  Vec3 toWorld(Vec3 v) const { return x * v.x + y * v.y + z * v.z; }
  Vec3 toLocal(Vec3 v) const { return {dot(v, x), dot(v, y), dot(v, z)}; }
};

} // namespace osl::render

#endif // OSLRENDER_VEC3_H
