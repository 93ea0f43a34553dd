//===- Sampler.h - Per-path quasi-random numbers -----------------*- C++ -*-===//
//
// testrender's sampler, so that osl-run --scene traces the paths testrender
// traces: each call of get() gives a path's next 3D point, the first three
// dimensions of the Sobol sequence at the path's sample index, Owen
// scrambled by hashing (Burley, "Practical Hash-based Owen Scrambling",
// JCGT 2020) with 24 bits per dimension. The sample order is shuffled per
// pixel and call, so a pixel's samples are stratified in every call (pixel
// position, each bounce's choices) while pixels and calls stay
// uncorrelated. A path's numbers depend only on (pixel, sample index,
// seed), never on how paths are batched.
//
//===----------------------------------------------------------------------===//
#ifndef OSLRENDER_SAMPLER_H
#define OSLRENDER_SAMPLER_H

#include "OslRender/Vec3.h"

#include <cstdint>

namespace osl::render {

/// A 32-bit integer hash (two multiply-xorshift rounds; constants from
/// Wellons' hash-prospector, as testrender uses them).
inline uint32_t samplerHash(uint32_t s) {
  s ^= s >> 16;
  s *= 0x21f0aaadU;
  s ^= s >> 15;
  s *= 0xd35a2d97U;
  s ^= s >> 15;
  return s;
}

inline uint32_t reverseBits(uint32_t x) {
  x = ((x & 0x55555555U) << 1) | ((x >> 1) & 0x55555555U);
  x = ((x & 0x33333333U) << 2) | ((x >> 2) & 0x33333333U);
  x = ((x & 0x0f0f0f0fU) << 4) | ((x >> 4) & 0x0f0f0f0fU);
  x = ((x & 0x00ff00ffU) << 8) | ((x >> 8) & 0x00ff00ffU);
  return (x << 16) | (x >> 16);
}

/// Owen scrambling of a bit-reversed value by a hash seeded with `s`
/// (Vegdahl's improved Laine-Karras permutation): a random nested uniform
/// permutation that keeps a sequence's strata. The result is in natural
/// bit order.
inline uint32_t owenScramble(uint32_t p, uint32_t s) {
  p ^= p * 0x3d20adeaU;
  p += s;
  p *= (s >> 16) | 1;
  p ^= p * 0x05526c56U;
  p ^= p * 0x53a22864U;
  return reverseBits(p);
}

/// Sobol dimensions 2 and 3 as 24 columns each, in bit-reversed form
/// (column c is what bit c of a reversed index contributes): dimension 2
/// from x + 1, dimension 3 from x^2 + x + 1 (Joe and Kuo's m = 1, 3).
struct SobolColumns {
  uint32_t y[24], z[24];
  /// The columns folded into byte tables: a point is three lookups per
  /// dimension instead of one XOR per index bit (the sampler is hot).
  uint32_t yBytes[3][256], zBytes[3][256];
  constexpr SobolColumns() : y(), z(), yBytes(), zBytes() {
    uint32_t v1[24] = {}, v2[24] = {};
    v1[0] = v2[0] = 1u << 31;
    v2[1] = 3u << 30;
    for (int k = 1; k < 24; ++k)
      v1[k] = v1[k - 1] ^ (v1[k - 1] >> 1);
    for (int k = 2; k < 24; ++k)
      v2[k] = v2[k - 2] ^ (v2[k - 2] >> 2) ^ v2[k - 1];
    for (int k = 0; k < 24; ++k) {
      y[k] = reverse(v1[k]);
      z[k] = reverse(v2[k]);
    }
    for (int byte = 0; byte < 3; ++byte)
      for (int value = 0; value < 256; ++value) {
        uint32_t a = 0, b = 0;
        for (int bit = 0; bit < 8; ++bit)
          if (value >> bit & 1)
            a ^= y[8 * byte + bit], b ^= z[8 * byte + bit];
        yBytes[byte][value] = a, zBytes[byte][value] = b;
      }
  }

private:
  static constexpr uint32_t reverse(uint32_t x) {
    uint32_t r = 0;
    for (int i = 0; i < 32; ++i)
      r |= (x >> i & 1) << (31 - i);
    return r;
  }
};
inline const SobolColumns &sobolColumns() {
  static constexpr SobolColumns columns{};
  return columns;
}

/// The path's point at depth key `seed` (its pixel's key plus 4 per call
/// before it) of sample `reversedIndex` (bit-reversed sample index).
/// Integer math and table lookups only, so it vectorizes and is the same
/// in every lane (always inlined: a call would keep a lane loop from
/// vectorizing).
[[gnu::always_inline]] inline Vec3 samplerPoint(uint32_t seed, uint32_t reversedIndex) {
  const SobolColumns &c = sobolColumns();
  uint32_t i = owenScramble(reversedIndex, samplerHash(seed)) & 0xffffffU;
  uint32_t y = c.yBytes[0][i & 255] ^ c.yBytes[1][i >> 8 & 255] ^ c.yBytes[2][i >> 16];
  uint32_t z = c.zBytes[0][i & 255] ^ c.zBytes[1][i >> 8 & 255] ^ c.zBytes[2][i >> 16];
  // 24 bits each: equally spaced values in [0, 1).
  auto toFloat = [](uint32_t v) { return float(v >> 8) * 5.96046448e-8f; };
  return {toFloat(owenScramble(i, samplerHash(seed + 1))),
          toFloat(owenScramble(y, samplerHash(seed + 2))),
          toFloat(owenScramble(z, samplerHash(seed + 3)))};
}

/// One path's numbers: pixel (x, y), sample index `si` (below 2^24), and a
/// seed that moves every pixel's key (0: testrender's own numbers).
class Sampler {
public:
  Sampler() = default;
  Sampler(int x, int y, uint32_t si, uint32_t seed = 0)
      : key(((uint32_t(x) & 2047) << 22 | (uint32_t(y) & 2047) << 11) + seed * 0x9e3779b9U),
        index(reverseBits(si)) {}
  /// The next call's point.
  Vec3 get() { return samplerPoint(key + 4 * call++, index); }
  /// The next `n` calls, to draw them elsewhere (a batch of paths at a
  /// time): the first's depth key is returned (each next call's is 4
  /// more), and get() continues after the last.
  uint32_t reserve(uint32_t n) {
    call += n;
    return key + 4 * (call - n);
  }
  uint32_t sampleIndex() const { return index; }

private:
  uint32_t key = 0, index = 0, call = 0;
};

} // namespace osl::render

#endif // OSLRENDER_SAMPLER_H
