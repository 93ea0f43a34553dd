//===- NoiseHelpers.h - Hashing and float helpers of the noise reference --===//
//
// Bob Jenkins' hash mix and final (OSL's inthash), x86's int(floor(x)),
// and the small float steps the reference noises share (Noise.cpp and
// SimplexNoise.cpp). Compiled without FMA contraction, as the reference is.
//
//===----------------------------------------------------------------------===//
#ifndef OSLREFERENCE_NOISEHELPERS_H
#define OSLREFERENCE_NOISEHELPERS_H

#include <cmath>
#include <cstdint>
#include <cstring>

namespace osl::ref::detail {

using u32 = uint32_t;

//===----------------------------------------------------------------------===//
// Hashing
//===----------------------------------------------------------------------===//

inline u32 rotl(u32 x, int k) { return (x << k) | (x >> (32 - k)); }

inline void bjmix(u32 &a, u32 &b, u32 &c) {
  a -= c; a ^= rotl(c, 4);  c += b;
  b -= a; b ^= rotl(a, 6);  a += c;
  c -= b; c ^= rotl(b, 8);  b += a;
  a -= c; a ^= rotl(c, 16); c += b;
  b -= a; b ^= rotl(a, 19); a += c;
  c -= b; c ^= rotl(b, 4);  b += a;
}

inline u32 bjfinal(u32 a, u32 b, u32 c) {
  c ^= b; c -= rotl(b, 14);
  a ^= c; a -= rotl(c, 11);
  b ^= a; b -= rotl(a, 25);
  c ^= b; c -= rotl(b, 16);
  a ^= c; a -= rotl(c, 4);
  b ^= a; b -= rotl(a, 14);
  c ^= b; c -= rotl(b, 24);
  return c;
}

constexpr u32 startValue(u32 nkeys) { return 0xdeadbeefu + (nkeys << 2) + 13u; }

inline u32 floatBits(float f) {
  u32 u;
  std::memcpy(&u, &f, sizeof u);
  return u;
}

//===----------------------------------------------------------------------===//
// Float helpers
//===----------------------------------------------------------------------===//

/// int(floor(x)) with x86 semantics for values that do not fit.
inline u32 ifloor(float x) {
  float f = std::floor(x);
  if (f >= -2147483648.0f && f < 2147483648.0f)
    return static_cast<u32>(static_cast<int32_t>(f));
  return 0x80000000u;
}

inline float floorfrac(float x, u32 &i) {
  i = ifloor(x);
  return x - static_cast<float>(static_cast<int32_t>(i));
}

inline float fade(float t) {
  return t * t * t * (t * (t * 6.0f - 15.0f) + 10.0f);
}

inline float lerp(float a, float b, float t) {
  return a * (1.0f - t) + b * t;
}

inline float negateIf(float v, u32 cond) { return cond ? -v : v; }

inline float unsignedOf(float n) { return 0.5f * (n + 1.0f); }

inline void unsignedTriple(float out[3]) {
  for (int c = 0; c < 3; ++c)
    out[c] = unsignedOf(out[c]);
}

} // namespace osl::ref::detail

#endif // OSLREFERENCE_NOISEHELPERS_H
