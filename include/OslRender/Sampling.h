//===- Sampling.h - testrender's math: fast functions, frames, warps, MIS -*- C++ -*-===//
//
// osl-run --scene traces the paths OSL's testrender traces, so that its
// renders match testrender's pixel for pixel (OSL's testsuite judges them
// so). The pieces of arithmetic that decide a path are testrender's:
// OpenImageIO's fast_* approximations as testrender is built (x86-64
// baseline: no fused multiply-add; fast_rint rounds half away from zero),
// its tangent frames, its hemisphere warps and its MIS weights. The
// algorithms and constants are published facts (OpenImageIO's fmath.h,
// SLEEF's polynomials, Shirley's concentric map); the code is ours. The
// render library is built with -ffp-contract=off, so a*b + c rounds twice,
// as there.
//
//===----------------------------------------------------------------------===//
#ifndef OSLRENDER_SAMPLING_H
#define OSLRENDER_SAMPLING_H

#include "OslRender/Vec3.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

namespace osl::render {

inline constexpr float kPiF = float(M_PI);

namespace fast {

inline uint32_t bits(float x) {
  uint32_t u;
  std::memcpy(&u, &x, 4);
  return u;
}
inline float fromBits(uint32_t u) {
  float x;
  std::memcpy(&x, &u, 4);
  return x;
}
/// OpenImageIO's clamp: NaN becomes `lo`.
inline float clamp(float x, float lo, float hi) {
  float v = x;
  if (!(lo <= v))
    v = lo;
  if (v > hi)
    v = hi;
  return v;
}
inline Vec3 clamp(Vec3 c, float lo, float hi) {
  return {clamp(c.x, lo, hi), clamp(c.y, lo, hi), clamp(c.z, lo, hi)};
}
/// a*(1-t) + b*t.
inline float lerp(float a, float b, float t) { return a * (1 - t) + b * t; }
inline Vec3 lerp(Vec3 a, Vec3 b, float t) { return a * (1 - t) + b * t; }
/// Round half away from zero (fast_rint without SSE4.1).
inline int rint(float x) { return int(x + std::copysign(0.5f, x)); }

/// The pi/4 parts of the Cody-Waite reduction.
inline constexpr float kPi4[] = {0.78515625f, 0.00024187564849853515625f,
                                 3.7747668102383613586e-08f, 1.2816720341285448015e-12f};

inline void sincos(float x, float &s, float &c) {
  int q = rint(x * float(M_1_PI));
  float qf = float(q);
  for (float part : kPi4)
    x = qf * (-part * 4) + x;
  x = float(M_PI_2) - (float(M_PI_2) - x); // flushes denormals
  float s2 = x * x;
  if (q & 1)
    x = -x;
  float su = 2.6083159809786593541503e-06f;
  su = su * s2 + -0.0001981069071916863322258f;
  su = su * s2 + 0.00833307858556509017944336f;
  su = su * s2 + -0.166666597127914428710938f;
  su = s2 * (su * x) + x;
  float cu = -2.71811842367242206819355e-07f;
  cu = cu * s2 + 2.47990446951007470488548e-05f;
  cu = cu * s2 + -0.00138888787478208541870117f;
  cu = cu * s2 + 0.0416666641831398010253906f;
  cu = cu * s2 + -0.5f;
  cu = cu * s2 + 1.0f;
  if (q & 1)
    cu = -cu;
  s = clamp(su, -1.0f, 1.0f);
  c = clamp(cu, -1.0f, 1.0f);
}

inline float tan(float x) {
  int q = rint(x * float(2 * M_1_PI));
  float qf = float(q);
  for (float part : kPi4)
    x = qf * (-part * 2) + x;
  if ((q & 1) == 0)
    x = float(M_PI_4) - (float(M_PI_4) - x);
  float s = x * x;
  float u = 0.00927245803177356719970703f;
  u = u * s + 0.00331984995864331722259521f;
  u = u * s + 0.0242998078465461730957031f;
  u = u * s + 0.0534495301544666290283203f;
  u = u * s + 0.133383005857467651367188f;
  u = u * s + 0.333331853151321411132812f;
  u = s * (u * x) + x;
  if (q & 1)
    u = -1.0f / u;
  return u;
}

/// OpenImageIO's fast_atan2: a rational atan on [0, 1], then the octant.
inline float atan2(float y, float x) {
  const float a = std::fabs(x), b = std::fabs(y);
  bool bGreater = b > a;
  const float k = (b == 0) ? 0.0f : ((a == b) ? 1.0f : (b > a ? a / b : b / a));
  const float s = 1.0f - (1.0f - k);
  const float t = s * s;
  float r = s * (0.430165678f * t + 1.0f) / ((0.0579354987f * t + 0.763007998f) * t + 1.0f);
  if (bGreater)
    r = 1.570796326794896557998982f - r;
  if (bits(x) & 0x80000000u)
    r = float(M_PI) - r;
  return std::copysign(r, y);
}

inline float acos(float x) {
  float f = std::fabs(x);
  float m = f < 1.0f ? 1.0f - (1.0f - f) : 1.0f;
  float a = std::sqrt(1.0f - m) *
            (1.5707963267f + m * (-0.213300989f + m * (0.077980478f + m * -0.02164095f)));
  return x < 0 ? float(M_PI) - a : a;
}

inline float log2(float xval) {
  float x = clamp(xval, std::numeric_limits<float>::min(), std::numeric_limits<float>::max());
  uint32_t b = bits(x);
  int exponent = int(b >> 23) - 127;
  float f = fromBits((b & 0x007FFFFF) | 0x3f800000) - 1.0f;
  float f2 = f * f, f4 = f2 * f2;
  float hi = f * -0.00931049621349f + 0.05206469089414f;
  float lo = f * 0.47868480909345f + -0.72116591947498f;
  hi = f * hi + -0.13753123777116f;
  hi = f * hi + 0.24187369696082f;
  hi = f * hi + -0.34730547155299f;
  lo = f * lo + 1.442689881667200f;
  return ((f4 * hi) + (f * lo)) + float(exponent);
}
inline float log(float x) { return log2(x) * float(M_LN2); }

inline float exp2(float xval) {
  float x = clamp(xval, -126.0f, 126.0f);
  int m = int(x);
  x -= float(m);
  x = 1.0f - (1.0f - x);
  float r = 1.33336498402e-3f;
  r = x * r + 9.810352697968e-3f;
  r = x * r + 5.551834031939e-2f;
  r = x * r + 0.2401793301105f;
  r = x * r + 0.693144857883f;
  r = x * r + 1.0f;
  return fromBits(bits(r) + (uint32_t(m) << 23));
}
inline float exp(float x) { return exp2(x * float(1 / M_LN2)); }

/// x^y for x > 0.
inline float powPositive(float x, float y) { return exp2(y * log2(x)); }

/// OpenImageIO's fast_safe_pow: exact for y of 0, 1 and 2, 0 for a
/// negative x and a non-integer y.
inline float safePow(float x, float y) {
  if (y == 0)
    return 1.0f;
  if (x == 0)
    return 0.0f;
  if (y == 1.0f)
    return x;
  if (y == 2.0f)
    return std::min(x * x, std::numeric_limits<float>::max());
  float sign = 1.0f;
  if (x < 0.0f) {
    int32_t ybits = int32_t(bits(y) & 0x7fffffff);
    if (ybits >= 0x4b800000) {
      // an even integer
    } else if (ybits >= 0x3f800000) {
      int k = (ybits >> 23) - 127;
      int32_t j = ybits >> (23 - k);
      if ((j << (23 - k)) == ybits)
        sign = fromBits(0x3f800000u | (uint32_t(j) << 31));
      else
        return 0.0f;
    } else {
      return 0.0f;
    }
  }
  return sign * exp2(y * log2(std::fabs(x)));
}

} // namespace fast

/// An orthonormal frame around unit `w` (testrender's TangentFrame).
struct TangentFrame {
  Vec3 u, v, w;
  explicit TangentFrame(Vec3 n) : w(n) {
    u = normalize(select(std::fabs(w.x) > .01f, Vec3(w.z, 0, -w.x), Vec3(0, -w.z, w.y)));
    v = cross(w, u);
  }
  /// Around unit `n`, its first axis following unit tangent `t`.
  TangentFrame(Vec3 n, Vec3 t) : w(n) {
    v = cross(w, t);
    u = cross(v, w);
  }
  Vec3 get(float x, float y, float z) const { return x * u + y * v + z * w; }
  Vec3 toLocal(Vec3 a) const { return {dot(a, u), dot(a, v), dot(a, w)}; }
  Vec3 toWorld(Vec3 a) const { return get(a.x, a.y, a.z); }
};

/// Two unit vectors orthogonal to unit `n` (testrender's ortho()).
inline void orthoBasis(Vec3 n, Vec3 &x, Vec3 &y) {
  x = normalize(select(std::fabs(n.x) > .01f, Vec3(n.z, 0, -n.x), Vec3(0, -n.z, n.y)));
  y = cross(n, x);
}

/// Shirley and Chiu's concentric map of the unit square onto the disk.
inline void toUnitDisk(float &x, float &y) {
  float phi, r;
  float a = 2 * x - 1, b = 2 * y - 1;
  if (a * a > b * b) {
    r = a;
    phi = float(M_PI_4) * (b / a);
  } else if (b != 0) {
    r = b;
    phi = float(M_PI_2) - float(M_PI_4) * (a / b);
  } else {
    r = 0;
    phi = 0;
  }
  fast::sincos(phi, x, y);
  x *= r;
  y *= r;
}

/// A cosine-weighted direction about unit `n` and its pdf (inlined
/// always: lane loops sample with it).
[[gnu::always_inline]] inline Vec3 sampleCosineHemisphere(Vec3 n, float rx, float ry, float &pdf) {
  toUnitDisk(rx, ry);
  float cosTheta = std::sqrt(std::max(1 - rx * rx - ry * ry, 0.0f));
  pdf = cosTheta * float(M_1_PI);
  return TangentFrame(n).get(rx, ry, cosTheta);
}

/// A uniform direction on the hemisphere about unit `n` and its pdf.
inline Vec3 sampleUniformHemisphere(Vec3 n, float rx, float ry, float &pdf) {
  float phi = float(2 * M_PI) * rx;
  float cosTheta = ry;
  float sinTheta = std::sqrt(1 - cosTheta * cosTheta);
  pdf = float(0.5 * M_1_PI);
  return TangentFrame(n).get(sinTheta * std::cos(phi), sinTheta * std::sin(phi), cosTheta);
}

/// The power heuristic of a sampled pdf against another, robust to
/// infinities: what multiplies a contribution whose estimator is a
/// weight (f/pdf) or an evaluation (f), against the other technique's
/// weight or evaluation.
enum class MisMode { WeightWeight, WeightEval, EvalWeight };
template <MisMode mode> inline float powerHeuristic(float sampledPdf, float otherPdf) {
  float r, mis;
  if (sampledPdf > otherPdf) {
    r = otherPdf / sampledPdf;
    mis = 1 / (1 + r * r);
  } else if (sampledPdf < otherPdf) {
    r = sampledPdf / otherPdf;
    mis = 1 - 1 / (1 + r * r);
  } else {
    r = 1.0f;
    mis = 0.5f;
  }
  constexpr float kMax = std::numeric_limits<float>::max();
  switch (mode) {
  case MisMode::WeightWeight: return std::min(otherPdf, kMax) * mis;
  case MisMode::WeightEval: return mis;
  case MisMode::EvalWeight: return mis * (otherPdf > sampledPdf ? std::min(1 / r, kMax) : r);
  }
  return 0;
}

/// Folds a lobe's (weight, pdf) picked with probability `b` into the
/// running (weight, pdf) of a mixture (the balance heuristic), where `on`
/// (the lobe exists) and b is above the smallest normal float. Selects,
/// not branches: lane loops vectorize it, and a lane skipped keeps its
/// bits.
[[gnu::always_inline]] inline void misMix(bool on, Vec3 &w, float &pdf, Vec3 ow, float opdf,
                                          float b) {
  bool use = on && b > std::numeric_limits<float>::min();
  opdf *= b;
  ow *= 1 / b;
  float mis = pdf < opdf ? 1 / (1 + pdf / opdf) : opdf < pdf ? 1 - 1 / (1 + opdf / pdf) : 0.5f;
  w = select(use, w * (1 - mis) + ow * mis, w);
  pdf = use ? pdf + opdf : pdf;
}
inline void misUpdate(Vec3 &w, float &pdf, Vec3 ow, float opdf, float b) {
  misMix(true, w, pdf, ow, opdf, b);
}

} // namespace osl::render

#endif // OSLRENDER_SAMPLING_H
