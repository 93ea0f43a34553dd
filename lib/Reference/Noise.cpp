//===- Noise.cpp - Scalar reference of OSL's noise functions --------------===//
//
// Float32 re-implementation of OSL 1.13's noise (liboslnoise), bit-exact with
// scalar testshade. What matters for bit-exactness, and is mirrored by
// lib/Transforms/NoiseBuilder.cpp:
//
//  * Lattice hash: Bob Jenkins' lookup3 (bjmix / bjfinal) over the integer
//    corner coordinates, start value 0xdeadbeef + (nkeys << 2) + 13.
//  * floorfrac: i = int(floor(x)), f = x - float(i). Out-of-range floors
//    (|x| >= 2^31, NaN) give INT_MIN like x86's cvttss2si, so that every
//    implementation agrees instead of relying on undefined conversions.
//  * fade(t) = t*t*t * (t*(t*6 - 15) + 10), evaluated in that order.
//  * lerp(a, b, t) = a*(1-t) + b*t (OpenImageIO's order).
//  * 2D-4D Perlin runs OSL's 4-wide SIMD code path (OIIO_SIMD is always on
//    for x86-64), which interpolates the 3D cube along z first, then x,
//    then y; 4D does two such cubes (w = 0, 1) and lerps them by w last.
//  * Output scales 0.25 (1D), 0.6616 (2D), 0.982 (3D), 0.8344 (4D);
//    unsigned noise is 0.5 * (n + 1).
//  * Triple results use one hash per corner and take channel c's gradient
//    from (h >> 8c) & 0xFF.
//  * Cell/hash noise: lookup3 of floor(coords) / of the float bits, mapped
//    to [0,1] by float(h) * 2^-32; triples hash one extra key 0, 1, 2.
//  * Simplex: OSL's adaptation of Gustavson's sdnoise1234 (hash-scrambled
//    gradients, scales 0.36, 64, 68, 54; triples use seeds 0, 1, 2).
//
//===----------------------------------------------------------------------===//

#include "NoiseHelpers.h"
#include "OslReference/Noise.h"

#include <cmath>
#include <cstring>

// Contraction into FMA would change rounding; OSL's reference values have
// none. GCC ignores this pragma (and contracts by default when the target
// has FMA), so lib/Reference/CMakeLists.txt also passes -ffp-contract=off.
#ifdef __clang__
#pragma STDC FP_CONTRACT OFF
#endif

namespace osl::ref {
using namespace detail;
namespace {

//===----------------------------------------------------------------------===//
// Gradients: dot product of the offset with a pseudo-random direction
//===----------------------------------------------------------------------===//

inline float grad1(u32 hash, float x) {
  u32 h = hash & 15;
  float g = static_cast<float>(1 + (h & 7));
  if (h & 8)
    g = -g;
  return g * x;
}

inline float grad2(u32 hash, float x, float y) {
  u32 h = hash & 7;
  float u = h < 4 ? x : y;
  float v = 2.0f * (h < 4 ? y : x);
  return negateIf(u, h & 1) + negateIf(v, h & 2);
}

inline float grad3(u32 hash, float x, float y, float z) {
  u32 h = hash & 15;
  float u = h < 8 ? x : y;
  float v = h < 4 ? y : ((h == 12 || h == 14) ? x : z);
  return negateIf(u, h & 1) + negateIf(v, h & 2);
}

inline float grad4(u32 hash, float x, float y, float z, float w) {
  u32 h = hash & 31;
  float u = h < 24 ? x : y;
  float v = h < 16 ? y : z;
  float s = h < 8 ? z : w;
  return negateIf(u, h & 1) + negateIf(v, h & 2) + negateIf(s, h & 4);
}

//===----------------------------------------------------------------------===//
// Lattice hashers: integer corner -> 32 hash bits
//===----------------------------------------------------------------------===//

/// Plain lattice hash; `shift` selects the byte used by a triple channel
/// (0, 8, 16); a float result uses the whole hash (shift 0, no mask), which
/// gives the same gradients since they only read the low 5 bits.
struct LatticeHash {
  u32 shift = 0;
  bool slice = false;
  u32 pick(u32 h) const { return slice ? (h >> shift) & 0xFF : h; }
  u32 operator()(u32 x) const { return pick(inthash(x)); }
  u32 operator()(u32 x, u32 y) const { return pick(inthash(x, y)); }
  u32 operator()(u32 x, u32 y, u32 z) const { return pick(inthash(x, y, z)); }
  u32 operator()(u32 x, u32 y, u32 z, u32 w) const {
    return pick(inthash(x, y, z, w));
  }
};

/// Periodic lattice hash: each corner coordinate is taken modulo its period
/// (floored, at least 1) into [0, period) before hashing.
struct PeriodicLatticeHash {
  int32_t p[4] = {1, 1, 1, 1};
  u32 shift = 0;
  bool slice = false;

  PeriodicLatticeHash(const float *period, int n) {
    for (int i = 0; i < n; ++i) {
      int32_t pi = static_cast<int32_t>(ifloor(period[i]));
      p[i] = pi < 1 ? 1 : pi;
    }
  }
  static u32 imod(u32 a, int32_t b) {
    int32_t r = static_cast<int32_t>(a) % b;
    if (r < 0)
      r += b;
    return static_cast<u32>(r);
  }
  u32 pick(u32 h) const { return slice ? (h >> shift) & 0xFF : h; }
  u32 operator()(u32 x) const { return pick(inthash(imod(x, p[0]))); }
  u32 operator()(u32 x, u32 y) const {
    return pick(inthash(imod(x, p[0]), imod(y, p[1])));
  }
  u32 operator()(u32 x, u32 y, u32 z) const {
    return pick(inthash(imod(x, p[0]), imod(y, p[1]), imod(z, p[2])));
  }
  u32 operator()(u32 x, u32 y, u32 z, u32 w) const {
    return pick(inthash(imod(x, p[0]), imod(y, p[1]), imod(z, p[2]),
                        imod(w, p[3])));
  }
};

//===----------------------------------------------------------------------===//
// Perlin cores (signed, scaled)
//===----------------------------------------------------------------------===//

template <class H> float perlin1(const H &hash, float x) {
  u32 X;
  float fx = floorfrac(x, X);
  float u = fade(fx);
  float r = lerp(grad1(hash(X), fx), grad1(hash(X + 1), fx - 1.0f), u);
  return 0.25f * r;
}

template <class H> float perlin2(const H &hash, float x, float y) {
  u32 X, Y;
  float fx = floorfrac(x, X);
  float fy = floorfrac(y, Y);
  float u = fade(fx);
  float v = fade(fy);
  float fx1 = fx - 1.0f, fy1 = fy - 1.0f;
  float g00 = grad2(hash(X, Y), fx, fy);
  float g10 = grad2(hash(X + 1, Y), fx1, fy);
  float g01 = grad2(hash(X, Y + 1), fx, fy1);
  float g11 = grad2(hash(X + 1, Y + 1), fx1, fy1);
  float r = lerp(lerp(g00, g10, u), lerp(g01, g11, u), v);
  return 0.6616f * r;
}

/// The eight corner gradients of one unit cube (for 3D, or one w slice of
/// 4D) interpolated along z, then x, then y, as OSL's SIMD trilerp does.
inline float cubeLerp(const float z0[4], const float z1[4], float u, float v,
                      float w) {
  float xy[4];
  for (int c = 0; c < 4; ++c)
    xy[c] = lerp(z0[c], z1[c], w);
  return lerp(lerp(xy[0], xy[1], u), lerp(xy[2], xy[3], u), v);
}

template <class H> float perlin3(const H &hash, float x, float y, float z) {
  u32 X, Y, Z;
  float fx = floorfrac(x, X);
  float fy = floorfrac(y, Y);
  float fz = floorfrac(z, Z);
  float u = fade(fx), v = fade(fy), w = fade(fz);
  float fx1 = fx - 1.0f, fy1 = fy - 1.0f, fz1 = fz - 1.0f;
  // Corner c: x offset c & 1, y offset c >> 1.
  float z0[4], z1[4];
  for (int c = 0; c < 4; ++c) {
    u32 cx = X + (c & 1), cy = Y + (c >> 1);
    float rx = (c & 1) ? fx1 : fx, ry = (c >> 1) ? fy1 : fy;
    z0[c] = grad3(hash(cx, cy, Z), rx, ry, fz);
    z1[c] = grad3(hash(cx, cy, Z + 1), rx, ry, fz1);
  }
  return 0.9820f * cubeLerp(z0, z1, u, v, w);
}

template <class H>
float perlin4(const H &hash, float x, float y, float z, float w) {
  u32 X, Y, Z, W;
  float fx = floorfrac(x, X);
  float fy = floorfrac(y, Y);
  float fz = floorfrac(z, Z);
  float fw = floorfrac(w, W);
  float u = fade(fx), v = fade(fy), t = fade(fz), s = fade(fw);
  float fx1 = fx - 1.0f, fy1 = fy - 1.0f, fz1 = fz - 1.0f, fw1 = fw - 1.0f;
  float g[2][2][4]; // [w offset][z offset][corner]
  for (int dw = 0; dw < 2; ++dw)
    for (int dz = 0; dz < 2; ++dz)
      for (int c = 0; c < 4; ++c) {
        u32 cx = X + (c & 1), cy = Y + (c >> 1);
        float rx = (c & 1) ? fx1 : fx, ry = (c >> 1) ? fy1 : fy;
        g[dw][dz][c] = grad4(hash(cx, cy, Z + dz, W + dw), rx, ry,
                             dz ? fz1 : fz, dw ? fw1 : fw);
      }
  float r = lerp(cubeLerp(g[0][0], g[0][1], u, v, t),
                 cubeLerp(g[1][0], g[1][1], u, v, t), s);
  return 0.8344f * r;
}


/// Runs a signed Perlin core once per triple channel with the hash byte of
/// that channel.
template <class H, class F> void perTriple(H hash, float out[3], F core) {
  hash.slice = true;
  for (int c = 0; c < 3; ++c) {
    hash.shift = 8 * c;
    out[c] = core(hash);
  }
}

//===----------------------------------------------------------------------===//
// Cell / hash noise: 1-4 keys -> [0,1], triples via an extra key
//===----------------------------------------------------------------------===//

inline void tripleOf(u32 k0, float out[3]) {
  for (u32 i = 0; i < 3; ++i)
    out[i] = bitsTo01(inthash(k0, i));
}
inline void tripleOf(u32 k0, u32 k1, float out[3]) {
  for (u32 i = 0; i < 3; ++i)
    out[i] = bitsTo01(inthash(k0, k1, i));
}
/// inthash(k0, k1, k2, i): the bjmix of the first three keys is shared.
inline void tripleOf(u32 k0, u32 k1, u32 k2, float out[3]) {
  u32 s = startValue(4);
  u32 a = s + k0, b = s + k1, c = s + k2;
  bjmix(a, b, c);
  for (u32 i = 0; i < 3; ++i)
    out[i] = bitsTo01(bjfinal(a + i, b, c));
}
/// inthash(k0, k1, k2, k3, i).
inline void tripleOf(u32 k0, u32 k1, u32 k2, u32 k3, float out[3]) {
  u32 s = startValue(5);
  u32 a = s + k0, b = s + k1, c = s + k2;
  bjmix(a, b, c);
  a += k3;
  for (u32 i = 0; i < 3; ++i)
    out[i] = bitsTo01(bjfinal(a, b + i, c));
}

} // namespace

//===----------------------------------------------------------------------===//
// Public building blocks
//===----------------------------------------------------------------------===//

uint32_t inthash(uint32_t k0) {
  u32 s = startValue(1);
  return bjfinal(s + k0, s, s);
}
uint32_t inthash(uint32_t k0, uint32_t k1) {
  u32 s = startValue(2);
  return bjfinal(s + k0, s + k1, s);
}
uint32_t inthash(uint32_t k0, uint32_t k1, uint32_t k2) {
  u32 s = startValue(3);
  return bjfinal(s + k0, s + k1, s + k2);
}
uint32_t inthash(uint32_t k0, uint32_t k1, uint32_t k2, uint32_t k3) {
  u32 s = startValue(4);
  u32 a = s + k0, b = s + k1, c = s + k2;
  bjmix(a, b, c);
  return bjfinal(a + k3, b, c);
}
uint32_t inthash(uint32_t k0, uint32_t k1, uint32_t k2, uint32_t k3,
                 uint32_t k4) {
  u32 s = startValue(5);
  u32 a = s + k0, b = s + k1, c = s + k2;
  bjmix(a, b, c);
  return bjfinal(a + k3, b + k4, c);
}

float bitsTo01(uint32_t bits) {
  constexpr float kScale = static_cast<float>(1.0 / 4294967295.0);
  return static_cast<float>(bits) * kScale;
}

//===----------------------------------------------------------------------===//
// Perlin
//===----------------------------------------------------------------------===//

float perlin(float x) { return perlin1(LatticeHash{}, x); }
float perlin(float x, float y) { return perlin2(LatticeHash{}, x, y); }
float perlin(const float p[3]) {
  return perlin3(LatticeHash{}, p[0], p[1], p[2]);
}
float perlin(const float p[3], float w) {
  return perlin4(LatticeHash{}, p[0], p[1], p[2], w);
}

void perlinTriple(float x, float out[3]) {
  perTriple(LatticeHash{}, out, [&](const auto &h) { return perlin1(h, x); });
}
void perlinTriple(float x, float y, float out[3]) {
  perTriple(LatticeHash{}, out,
            [&](const auto &h) { return perlin2(h, x, y); });
}
void perlinTriple(const float p[3], float out[3]) {
  perTriple(LatticeHash{}, out,
            [&](const auto &h) { return perlin3(h, p[0], p[1], p[2]); });
}
void perlinTriple(const float p[3], float w, float out[3]) {
  perTriple(LatticeHash{}, out,
            [&](const auto &h) { return perlin4(h, p[0], p[1], p[2], w); });
}

float uperlin(float x) { return unsignedOf(perlin(x)); }
float uperlin(float x, float y) { return unsignedOf(perlin(x, y)); }
float uperlin(const float p[3]) { return unsignedOf(perlin(p)); }
float uperlin(const float p[3], float w) { return unsignedOf(perlin(p, w)); }

void uperlinTriple(float x, float out[3]) {
  perlinTriple(x, out);
  unsignedTriple(out);
}
void uperlinTriple(float x, float y, float out[3]) {
  perlinTriple(x, y, out);
  unsignedTriple(out);
}
void uperlinTriple(const float p[3], float out[3]) {
  perlinTriple(p, out);
  unsignedTriple(out);
}
void uperlinTriple(const float p[3], float w, float out[3]) {
  perlinTriple(p, w, out);
  unsignedTriple(out);
}

//===----------------------------------------------------------------------===//
// Periodic Perlin
//===----------------------------------------------------------------------===//

float periodicPerlin(float x, float px) {
  return perlin1(PeriodicLatticeHash(&px, 1), x);
}
float periodicPerlin(float x, float y, float px, float py) {
  float pp[2] = {px, py};
  return perlin2(PeriodicLatticeHash(pp, 2), x, y);
}
float periodicPerlin(const float p[3], const float pp[3]) {
  return perlin3(PeriodicLatticeHash(pp, 3), p[0], p[1], p[2]);
}
float periodicPerlin(const float p[3], float w, const float pp[3], float pw) {
  float per[4] = {pp[0], pp[1], pp[2], pw};
  return perlin4(PeriodicLatticeHash(per, 4), p[0], p[1], p[2], w);
}

void periodicPerlinTriple(float x, float px, float out[3]) {
  perTriple(PeriodicLatticeHash(&px, 1), out,
            [&](const auto &h) { return perlin1(h, x); });
}
void periodicPerlinTriple(float x, float y, float px, float py,
                          float out[3]) {
  float pp[2] = {px, py};
  perTriple(PeriodicLatticeHash(pp, 2), out,
            [&](const auto &h) { return perlin2(h, x, y); });
}
void periodicPerlinTriple(const float p[3], const float pp[3], float out[3]) {
  perTriple(PeriodicLatticeHash(pp, 3), out,
            [&](const auto &h) { return perlin3(h, p[0], p[1], p[2]); });
}
void periodicPerlinTriple(const float p[3], float w, const float pp[3],
                          float pw, float out[3]) {
  float per[4] = {pp[0], pp[1], pp[2], pw};
  perTriple(PeriodicLatticeHash(per, 4), out,
            [&](const auto &h) { return perlin4(h, p[0], p[1], p[2], w); });
}

float periodicUPerlin(float x, float px) {
  return unsignedOf(periodicPerlin(x, px));
}
float periodicUPerlin(float x, float y, float px, float py) {
  return unsignedOf(periodicPerlin(x, y, px, py));
}
float periodicUPerlin(const float p[3], const float pp[3]) {
  return unsignedOf(periodicPerlin(p, pp));
}
float periodicUPerlin(const float p[3], float w, const float pp[3], float pw) {
  return unsignedOf(periodicPerlin(p, w, pp, pw));
}
void periodicUPerlinTriple(float x, float px, float out[3]) {
  periodicPerlinTriple(x, px, out);
  unsignedTriple(out);
}
void periodicUPerlinTriple(float x, float y, float px, float py,
                           float out[3]) {
  periodicPerlinTriple(x, y, px, py, out);
  unsignedTriple(out);
}
void periodicUPerlinTriple(const float p[3], const float pp[3], float out[3]) {
  periodicPerlinTriple(p, pp, out);
  unsignedTriple(out);
}
void periodicUPerlinTriple(const float p[3], float w, const float pp[3],
                           float pw, float out[3]) {
  periodicPerlinTriple(p, w, pp, pw, out);
  unsignedTriple(out);
}

//===----------------------------------------------------------------------===//
// Cell and hash noise
//===----------------------------------------------------------------------===//

float cell(float x) { return bitsTo01(inthash(ifloor(x))); }
float cell(float x, float y) {
  return bitsTo01(inthash(ifloor(x), ifloor(y)));
}
float cell(const float p[3]) {
  return bitsTo01(inthash(ifloor(p[0]), ifloor(p[1]), ifloor(p[2])));
}
float cell(const float p[3], float w) {
  return bitsTo01(
      inthash(ifloor(p[0]), ifloor(p[1]), ifloor(p[2]), ifloor(w)));
}
void cellTriple(float x, float out[3]) { tripleOf(ifloor(x), out); }
void cellTriple(float x, float y, float out[3]) {
  tripleOf(ifloor(x), ifloor(y), out);
}
void cellTriple(const float p[3], float out[3]) {
  tripleOf(ifloor(p[0]), ifloor(p[1]), ifloor(p[2]), out);
}
void cellTriple(const float p[3], float w, float out[3]) {
  tripleOf(ifloor(p[0]), ifloor(p[1]), ifloor(p[2]), ifloor(w), out);
}

float hash(float x) { return bitsTo01(inthash(floatBits(x))); }
float hash(float x, float y) {
  return bitsTo01(inthash(floatBits(x), floatBits(y)));
}
float hash(const float p[3]) {
  return bitsTo01(
      inthash(floatBits(p[0]), floatBits(p[1]), floatBits(p[2])));
}
float hash(const float p[3], float w) {
  return bitsTo01(inthash(floatBits(p[0]), floatBits(p[1]), floatBits(p[2]),
                          floatBits(w)));
}
void hashTriple(float x, float out[3]) { tripleOf(floatBits(x), out); }
void hashTriple(float x, float y, float out[3]) {
  tripleOf(floatBits(x), floatBits(y), out);
}
void hashTriple(const float p[3], float out[3]) {
  tripleOf(floatBits(p[0]), floatBits(p[1]), floatBits(p[2]), out);
}
void hashTriple(const float p[3], float w, float out[3]) {
  tripleOf(floatBits(p[0]), floatBits(p[1]), floatBits(p[2]), floatBits(w),
           out);
}

//===----------------------------------------------------------------------===//
// Dispatch
//===----------------------------------------------------------------------===//

std::optional<NoiseType> parseNoiseType(std::string_view name) {
  if (name == "perlin" || name == "snoise")
    return NoiseType::Perlin;
  if (name == "uperlin" || name == "noise")
    return NoiseType::UPerlin;
  if (name == "cell" || name == "cellnoise")
    return NoiseType::Cell;
  if (name == "hash" || name == "hashnoise")
    return NoiseType::Hash;
  if (name == "simplex")
    return NoiseType::Simplex;
  if (name == "usimplex")
    return NoiseType::USimplex;
  return std::nullopt;
}

float noise(NoiseType type, int dims, const float *in) {
  switch (type) {
#define OSL_REF_DIMS(FN)                                                       \
  switch (dims) {                                                              \
  case 1: return FN(in[0]);                                                    \
  case 2: return FN(in[0], in[1]);                                             \
  case 3: return FN(in);                                                       \
  default: return FN(in, in[3]);                                               \
  }
  case NoiseType::Perlin: OSL_REF_DIMS(perlin)
  case NoiseType::UPerlin: OSL_REF_DIMS(uperlin)
  case NoiseType::Cell: OSL_REF_DIMS(cell)
  case NoiseType::Hash: OSL_REF_DIMS(hash)
  case NoiseType::Simplex: OSL_REF_DIMS(simplex)
  case NoiseType::USimplex: OSL_REF_DIMS(usimplex)
#undef OSL_REF_DIMS
  }
  return 0.0f;
}

void noiseTriple(NoiseType type, int dims, const float *in, float out[3]) {
  switch (type) {
#define OSL_REF_DIMS(FN)                                                       \
  switch (dims) {                                                              \
  case 1: return FN(in[0], out);                                               \
  case 2: return FN(in[0], in[1], out);                                        \
  case 3: return FN(in, out);                                                  \
  default: return FN(in, in[3], out);                                          \
  }
  case NoiseType::Perlin: OSL_REF_DIMS(perlinTriple)
  case NoiseType::UPerlin: OSL_REF_DIMS(uperlinTriple)
  case NoiseType::Cell: OSL_REF_DIMS(cellTriple)
  case NoiseType::Hash: OSL_REF_DIMS(hashTriple)
  case NoiseType::Simplex: OSL_REF_DIMS(simplexTriple)
  case NoiseType::USimplex: OSL_REF_DIMS(usimplexTriple)
#undef OSL_REF_DIMS
  }
}

namespace {
/// OSL's periodic cell/hash noise wraps the coordinates themselves:
/// s - p * floor(s / p) with p = max(floor(period), 1).
float wrapCoord(float s, float period) {
  period = std::floor(period);
  if (period < 1.0f)
    period = 1.0f;
  return s - period * std::floor(s / period);
}
} // namespace

bool periodicNoise(NoiseType type, int dims, const float *in,
                   const float *period, float *out) {
  const float *pp = period;
  switch (type) {
  case NoiseType::Perlin:
  case NoiseType::UPerlin: {
    float n;
    switch (dims) {
    case 1: n = periodicPerlin(in[0], pp[0]); break;
    case 2: n = periodicPerlin(in[0], in[1], pp[0], pp[1]); break;
    case 3: n = periodicPerlin(in, pp); break;
    default: n = periodicPerlin(in, in[3], pp, pp[3]); break;
    }
    *out = type == NoiseType::UPerlin ? unsignedOf(n) : n;
    return true;
  }
  case NoiseType::Cell:
  case NoiseType::Hash: {
    float w[4];
    for (int i = 0; i < dims; ++i)
      w[i] = wrapCoord(in[i], pp[i]);
    *out = noise(type, dims, w);
    return true;
  }
  default:
    return false;
  }
}

bool periodicNoiseTriple(NoiseType type, int dims, const float *in,
                         const float *period, float out[3]) {
  const float *pp = period;
  switch (type) {
  case NoiseType::Perlin:
  case NoiseType::UPerlin:
    switch (dims) {
    case 1: periodicPerlinTriple(in[0], pp[0], out); break;
    case 2: periodicPerlinTriple(in[0], in[1], pp[0], pp[1], out); break;
    case 3: periodicPerlinTriple(in, pp, out); break;
    default: periodicPerlinTriple(in, in[3], pp, pp[3], out); break;
    }
    if (type == NoiseType::UPerlin)
      unsignedTriple(out);
    return true;
  case NoiseType::Cell:
  case NoiseType::Hash: {
    float w[4];
    for (int i = 0; i < dims; ++i)
      w[i] = wrapCoord(in[i], pp[i]);
    noiseTriple(type, dims, w, out);
    return true;
  }
  default:
    return false;
  }
}

} // namespace osl::ref
