//===- SimplexNoise.cpp - Scalar reference of OSL's simplex noise ---------===//
#include "NoiseHelpers.h"
#include "OslReference/Noise.h"

// No FMA contraction, as in Noise.cpp (CMakeLists.txt passes
// -ffp-contract=off for GCC too).
#ifdef __clang__
#pragma STDC FP_CONTRACT OFF
#endif

namespace osl::ref {
using namespace detail;

//===----------------------------------------------------------------------===//
// Simplex noise (Gustavson's sdnoise1234 with a hash instead of a
// permutation table, as adapted by OSL)
//===----------------------------------------------------------------------===//

namespace {

/// OSL's `scramble`: bjfinal(v0, v1, v2 ^ 0xdeadbeef).
inline u32 scramble(u32 v0, u32 v1 = 0, u32 v2 = 0) {
  return bjfinal(v0, v1, v2 ^ 0xdeadbeefu);
}

// Gradient tables, indexed by the low hash bits.
constexpr float kGrad2[8][2] = {{-1, -1}, {1, 0},  {-1, 0}, {1, 1},
                                {-1, 1},  {0, -1}, {0, 1},  {1, -1}};
constexpr float kGrad3[16][3] = {
    {1, 0, 1},  {0, 1, 1},  {-1, 0, 1},  {0, -1, 1},
    {1, 0, -1}, {0, 1, -1}, {-1, 0, -1}, {0, -1, -1},
    {1, -1, 0}, {1, 1, 0},  {-1, 1, 0},  {-1, -1, 0},
    {1, 0, 1},  {-1, 0, 1}, {0, 1, -1},  {0, -1, -1}};
/// 4D gradients: the 32 edges of the tesseract. Entry h has a zero in
/// component h >> 3 and signs from bits 2, 1, 0 (set = negative) on the
/// other three components in order.
float grad4Component(u32 h, int comp) {
  int zeroAt = static_cast<int>(h >> 3);
  if (comp == zeroAt)
    return 0.0f;
  int slot = comp < zeroAt ? comp : comp - 1; // 0..2 among the nonzero ones
  return (h >> (2 - slot)) & 1 ? -1.0f : 1.0f;
}

/// Simplex traversal order for 4D, indexed by the six pairwise comparison
/// bits; entry = rank (0..3) of each coordinate.
constexpr unsigned char kSimplex4[64][4] = {
    {0, 1, 2, 3}, {0, 1, 3, 2}, {0, 0, 0, 0}, {0, 2, 3, 1}, {0, 0, 0, 0},
    {0, 0, 0, 0}, {0, 0, 0, 0}, {1, 2, 3, 0}, {0, 2, 1, 3}, {0, 0, 0, 0},
    {0, 3, 1, 2}, {0, 3, 2, 1}, {0, 0, 0, 0}, {0, 0, 0, 0}, {0, 0, 0, 0},
    {1, 3, 2, 0}, {0, 0, 0, 0}, {0, 0, 0, 0}, {0, 0, 0, 0}, {0, 0, 0, 0},
    {0, 0, 0, 0}, {0, 0, 0, 0}, {0, 0, 0, 0}, {0, 0, 0, 0}, {1, 2, 0, 3},
    {0, 0, 0, 0}, {1, 3, 0, 2}, {0, 0, 0, 0}, {0, 0, 0, 0}, {0, 0, 0, 0},
    {2, 3, 0, 1}, {2, 3, 1, 0}, {1, 0, 2, 3}, {1, 0, 3, 2}, {0, 0, 0, 0},
    {0, 0, 0, 0}, {0, 0, 0, 0}, {2, 0, 3, 1}, {0, 0, 0, 0}, {2, 1, 3, 0},
    {0, 0, 0, 0}, {0, 0, 0, 0}, {0, 0, 0, 0}, {0, 0, 0, 0}, {0, 0, 0, 0},
    {0, 0, 0, 0}, {0, 0, 0, 0}, {0, 0, 0, 0}, {2, 0, 1, 3}, {0, 0, 0, 0},
    {0, 0, 0, 0}, {0, 0, 0, 0}, {3, 0, 1, 2}, {3, 0, 2, 1}, {0, 0, 0, 0},
    {3, 1, 2, 0}, {2, 1, 0, 3}, {0, 0, 0, 0}, {0, 0, 0, 0}, {0, 0, 0, 0},
    {3, 1, 0, 2}, {0, 0, 0, 0}, {3, 2, 0, 1}, {3, 2, 1, 0}};

inline float i2f(u32 i) { return static_cast<float>(static_cast<int32_t>(i)); }

float simplex1(float x, u32 seed) {
  u32 i0 = ifloor(x);
  u32 i1 = i0 + 1;
  float x0 = x - i2f(i0);
  float x1 = x0 - 1.0f;

  auto corner = [&](u32 i, float d) {
    float t = 1.0f - d * d; // never negative in 1D
    float t2 = t * t;
    float t4 = t2 * t2;
    u32 h = scramble(i, seed);
    float g = 1.0f + static_cast<float>(h & 7);
    if (h & 8)
      g = -g;
    return t4 * g * d;
  };
  float n0 = corner(i0, x0);
  float n1 = corner(i1, x1);
  return 0.36f * (n0 + n1);
}

float simplex2(float x, float y, u32 seed) {
  const float F2 = static_cast<float>(0.366025403); // double literal in OSL
  const float G2 = static_cast<float>(0.211324865); // double literal in OSL
  float s = (x + y) * F2;
  float xs = x + s, ys = y + s;
  u32 i = ifloor(xs), j = ifloor(ys);
  float t = i2f(i + j) * G2;
  float X0 = i2f(i) - t, Y0 = i2f(j) - t;
  float x0 = x - X0, y0 = y - Y0;
  u32 i1 = x0 > y0 ? 1 : 0, j1 = 1 - i1;
  float x1 = x0 - i2f(i1) + G2, y1 = y0 - i2f(j1) + G2;
  float x2 = x0 - 1.0f + 2.0f * G2, y2 = y0 - 1.0f + 2.0f * G2;

  auto corner = [&](u32 ci, u32 cj, float dx, float dy) {
    float t0 = 0.5f - dx * dx - dy * dy;
    if (!(t0 >= 0.0f))
      return 0.0f;
    const float *g = kGrad2[scramble(ci, cj, seed) & 7];
    float t2 = t0 * t0;
    float t4 = t2 * t2;
    return t4 * (g[0] * dx + g[1] * dy);
  };
  float n0 = corner(i, j, x0, y0);
  float n1 = corner(i + i1, j + j1, x1, y1);
  float n2 = corner(i + 1, j + 1, x2, y2);
  return 64.0f * (n0 + n1 + n2);
}

float simplex3(float x, float y, float z, u32 seed) {
  const float F3 = static_cast<float>(0.333333333); // double literal in OSL
  const float G3 = static_cast<float>(0.166666667); // double literal in OSL
  float s = (x + y + z) * F3;
  float xs = x + s, ys = y + s, zs = z + s;
  u32 i = ifloor(xs), j = ifloor(ys), k = ifloor(zs);
  float t = i2f(i + j + k) * G3;
  float X0 = i2f(i) - t, Y0 = i2f(j) - t, Z0 = i2f(k) - t;
  float x0 = x - X0, y0 = y - Y0, z0 = z - Z0;

  u32 i1, j1, k1, i2, j2, k2;
  if (x0 >= y0) {
    if (y0 >= z0) {
      i1 = 1; j1 = 0; k1 = 0; i2 = 1; j2 = 1; k2 = 0;
    } else if (x0 >= z0) {
      i1 = 1; j1 = 0; k1 = 0; i2 = 1; j2 = 0; k2 = 1;
    } else {
      i1 = 0; j1 = 0; k1 = 1; i2 = 1; j2 = 0; k2 = 1;
    }
  } else {
    if (y0 < z0) {
      i1 = 0; j1 = 0; k1 = 1; i2 = 0; j2 = 1; k2 = 1;
    } else if (x0 < z0) {
      i1 = 0; j1 = 1; k1 = 0; i2 = 0; j2 = 1; k2 = 1;
    } else {
      i1 = 0; j1 = 1; k1 = 0; i2 = 1; j2 = 1; k2 = 0;
    }
  }
  float x1 = x0 - i2f(i1) + G3, y1 = y0 - i2f(j1) + G3,
        z1 = z0 - i2f(k1) + G3;
  float x2 = x0 - i2f(i2) + 2.0f * G3, y2 = y0 - i2f(j2) + 2.0f * G3,
        z2 = z0 - i2f(k2) + 2.0f * G3;
  float x3 = x0 - 1.0f + 3.0f * G3, y3 = y0 - 1.0f + 3.0f * G3,
        z3 = z0 - 1.0f + 3.0f * G3;

  auto corner = [&](u32 ci, u32 cj, u32 ck, float dx, float dy, float dz) {
    float t0 = 0.5f - dx * dx - dy * dy - dz * dz;
    if (!(t0 >= 0.0f))
      return 0.0f;
    const float *g = kGrad3[scramble(ci, cj, scramble(ck, seed)) & 15];
    float t2 = t0 * t0;
    float t4 = t2 * t2;
    return t4 * (g[0] * dx + g[1] * dy + g[2] * dz);
  };
  float n0 = corner(i, j, k, x0, y0, z0);
  float n1 = corner(i + i1, j + j1, k + k1, x1, y1, z1);
  float n2 = corner(i + i2, j + j2, k + k2, x2, y2, z2);
  float n3 = corner(i + 1, j + 1, k + 1, x3, y3, z3);
  return 68.0f * (n0 + n1 + n2 + n3);
}

float simplex4(float x, float y, float z, float w, u32 seed) {
  const float F4 = static_cast<float>(0.309016994); // double literal in OSL
  const float G4 = static_cast<float>(0.138196601); // double literal in OSL
  float s = (x + y + z + w) * F4;
  float xs = x + s, ys = y + s, zs = z + s, ws = w + s;
  u32 i = ifloor(xs), j = ifloor(ys), k = ifloor(zs), l = ifloor(ws);
  float t = i2f(i + j + k + l) * G4;
  float X0 = i2f(i) - t, Y0 = i2f(j) - t, Z0 = i2f(k) - t, W0 = i2f(l) - t;
  float x0 = x - X0, y0 = y - Y0, z0 = z - Z0, w0 = w - W0;

  int c = (x0 > y0 ? 32 : 0) | (x0 > z0 ? 16 : 0) | (y0 > z0 ? 8 : 0) |
          (x0 > w0 ? 4 : 0) | (y0 > w0 ? 2 : 0) | (z0 > w0 ? 1 : 0);
  const unsigned char *sc = kSimplex4[c];
  u32 o[4][4]; // o[corner-1][axis], corners 1..3
  for (int n = 0; n < 3; ++n)
    for (int a = 0; a < 4; ++a)
      o[n][a] = sc[a] >= 3 - n ? 1 : 0;

  float d[5][4];
  const float base[4] = {x0, y0, z0, w0};
  const float offs[4] = {G4, 2.0f * G4, 3.0f * G4, 4.0f * G4};
  for (int a = 0; a < 4; ++a) {
    d[0][a] = base[a];
    for (int n = 0; n < 3; ++n)
      d[n + 1][a] = base[a] - i2f(o[n][a]) + offs[n];
    d[4][a] = base[a] - 1.0f + offs[3];
  }
  u32 ci[5][4];
  const u32 lat[4] = {i, j, k, l};
  for (int a = 0; a < 4; ++a) {
    ci[0][a] = lat[a];
    for (int n = 0; n < 3; ++n)
      ci[n + 1][a] = lat[a] + o[n][a];
    ci[4][a] = lat[a] + 1;
  }

  float nsum[5];
  for (int n = 0; n < 5; ++n) {
    const float *p = d[n];
    float t0 = 0.5f - p[0] * p[0] - p[1] * p[1] - p[2] * p[2] - p[3] * p[3];
    if (!(t0 >= 0.0f)) {
      nsum[n] = 0.0f;
      continue;
    }
    float t2 = t0 * t0;
    float t4 = t2 * t2;
    u32 h = scramble(ci[n][0], ci[n][1], scramble(ci[n][2], ci[n][3], seed));
    h &= 31;
    nsum[n] = t4 * (grad4Component(h, 0) * p[0] + grad4Component(h, 1) * p[1] +
                    grad4Component(h, 2) * p[2] + grad4Component(h, 3) * p[3]);
  }
  return 54.0f * (nsum[0] + nsum[1] + nsum[2] + nsum[3] + nsum[4]);
}

} // namespace

float simplex(float x) { return simplex1(x, 0); }
float simplex(float x, float y) { return simplex2(x, y, 0); }
float simplex(const float p[3]) { return simplex3(p[0], p[1], p[2], 0); }
float simplex(const float p[3], float w) {
  return simplex4(p[0], p[1], p[2], w, 0);
}
void simplexTriple(float x, float out[3]) {
  for (u32 c = 0; c < 3; ++c)
    out[c] = simplex1(x, c);
}
void simplexTriple(float x, float y, float out[3]) {
  for (u32 c = 0; c < 3; ++c)
    out[c] = simplex2(x, y, c);
}
void simplexTriple(const float p[3], float out[3]) {
  for (u32 c = 0; c < 3; ++c)
    out[c] = simplex3(p[0], p[1], p[2], c);
}
void simplexTriple(const float p[3], float w, float out[3]) {
  for (u32 c = 0; c < 3; ++c)
    out[c] = simplex4(p[0], p[1], p[2], w, c);
}

float usimplex(float x) { return unsignedOf(simplex(x)); }
float usimplex(float x, float y) { return unsignedOf(simplex(x, y)); }
float usimplex(const float p[3]) { return unsignedOf(simplex(p)); }
float usimplex(const float p[3], float w) { return unsignedOf(simplex(p, w)); }
void usimplexTriple(float x, float out[3]) {
  simplexTriple(x, out);
  unsignedTriple(out);
}
void usimplexTriple(float x, float y, float out[3]) {
  simplexTriple(x, y, out);
  unsignedTriple(out);
}
void usimplexTriple(const float p[3], float out[3]) {
  simplexTriple(p, out);
  unsignedTriple(out);
}
void usimplexTriple(const float p[3], float w, float out[3]) {
  simplexTriple(p, w, out);
  unsignedTriple(out);
}

} // namespace osl::ref
