//===- RenderMath.h - Trigonometry the renderer's lane loops can run -*- C++ -*-===//
//
// libm's sinf, cosf, atan2f and acosf are calls, and a call keeps a lane
// loop from vectorizing. These are polynomials of plain float operations
// and selects (no branches, no tables), so the same code runs one lane at a
// time or sixteen, with the same bits at every width. Error against double
// precision is measured in unittests/Render/RenderMathTest.cpp: at most
// 3.1 ulps of 1 for sin and cos, 2.8 ulps for atan2 and 1.2 ulps of pi for
// acos (libm's are within 0.5-1); the renderer's own noise is far above.
//
//===----------------------------------------------------------------------===//
#ifndef OSLRENDER_RENDERMATH_H
#define OSLRENDER_RENDERMATH_H

#include <cmath>

namespace osl::render {

inline constexpr float kRenderPi = 3.14159265358979f;

/// sin and cos of `x`: x is reduced by the nearest multiple k of pi/2 in
/// three parts (Cody and Waite; the first two have few enough bits that
/// k times them is exact for |k| < 2^15), then Taylor polynomials on
/// [-pi/4, pi/4] (truncation below 2e-9). Accurate as measured for |x| up
/// to 8 pi (the renderer's angles are in [-2 pi, 2 pi]); arguments beyond
/// 1e7 are reduced as 1e7 (their result is meaningless either way, but
/// the conversion to int stays defined).
[[gnu::always_inline]] inline void polySinCos(float x, float &s, float &c) {
  // k = x / (pi/2) rounded half away from zero (a conversion, which every
  // instruction set vectorizes; nearbyint is a call without SSE4.1).
  float kx = std::fmin(1e7f, std::fmax(-1e7f, x * 0.636619772f));
  int qk = int(kx + (kx >= 0 ? 0.5f : -0.5f));
  float k = float(qk);
  float r = x - k * 1.5703125f;
  r = r - k * 4.837512969970703125e-4f;
  r = r - k * 7.54978995489188216e-8f;
  float r2 = r * r;
  float sr = r + r * r2 *
                     (-1.66666667e-1f +
                      r2 * (8.33333333e-3f + r2 * (-1.98412698e-4f + r2 * 2.75573192e-6f)));
  float cr =
      1 +
      r2 * (-0.5f + r2 * (4.16666667e-2f +
                          r2 * (-1.38888889e-3f + r2 * (2.48015873e-5f + r2 * -2.75573192e-7f))));
  int q = qk & 3;
  float sq = (q & 1) ? cr : sr, cq = (q & 1) ? sr : cr;
  s = (q & 2) ? -sq : sq;
  c = ((q + 1) & 2) ? -cq : cq;
}

/// atan of `a` in [0, 1]: above tan(pi/8) as pi/4 + atan((a-1)/(a+1)),
/// so the Taylor series runs on |t| <= 0.4143 (truncation below 3e-9).
[[gnu::always_inline]] inline float polyAtanUnit(float a) {
  bool upper = a > 0.414213562f;
  float t = upper ? (a - 1) / (a + 1) : a;
  float t2 = t * t;
  float p =
      t + t * t2 *
              (-3.33333333e-1f +
               t2 * (2.0e-1f +
                     t2 * (-1.42857143e-1f +
                           t2 * (1.11111111e-1f +
                                 t2 * (-9.09090909e-2f +
                                       t2 * (7.69230769e-2f +
                                             t2 * (-6.66666667e-2f + t2 * 5.88235294e-2f)))))));
  return upper ? 0.785398163f + p : p;
}

/// atan2(y, x) in [-pi, pi]; 0 for (0, 0). Unlike libm's, a NaN argument
/// gives a number (fmax and fmin drop it) and -0 is not kept.
[[gnu::always_inline]] inline float polyAtan2(float y, float x) {
  float ax = std::fabs(x), ay = std::fabs(y);
  float big = std::fmax(ax, ay), small = std::fmin(ax, ay);
  float a = big > 0 ? small / big : 0.0f;
  float r = polyAtanUnit(a);
  r = ay > ax ? 1.57079633f - r : r;
  r = x < 0 ? kRenderPi - r : r;
  return y < 0 ? -r : r;
}

/// acos of `x` in [-1, 1] (clamped; NaN gives a number, as polyAtan2),
/// as atan2(sqrt(1 - x^2), x).
[[gnu::always_inline]] inline float polyAcos(float x) {
  x = std::fmin(1.0f, std::fmax(-1.0f, x));
  return polyAtan2(std::sqrt((1 - x) * (1 + x)), x);
}

} // namespace osl::render

#endif // OSLRENDER_RENDERMATH_H
