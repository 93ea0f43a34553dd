//===- Sampler.h - Per-path quasi-random numbers -----------------*- C++ -*-===//
//
// Each call of get() gives the next 3D point of a path: the first three
// dimensions of the Sobol sequence at the path's sample index, Owen
// scrambled with a shuffled sample order per pixel and call. A
// pixel's samples are then stratified in every call (pixel position, each
// bounce's BSDF and light choices) while pixels and calls stay
// uncorrelated. A path's numbers depend only on (pixel, sample index,
// seed), never on how paths are batched.
//
//===----------------------------------------------------------------------===//
#ifndef OSLRENDER_SAMPLER_H
#define OSLRENDER_SAMPLER_H

#include "OslRender/Vec3.h"

#include <cstdint>

namespace osl::render {

inline uint32_t hash32(uint32_t x) {
  x ^= x >> 16;
  x *= 0x7feb352dU;
  x ^= x >> 15;
  x *= 0x846ca68bU;
  x ^= x >> 16;
  return x;
}

/// Direction numbers of Sobol dimensions 1-3 (Joe and Kuo's first three).
struct SobolMatrices {
  uint32_t v[3][32];
  constexpr SobolMatrices() : v() {
    for (int k = 0; k < 32; ++k)
      v[0][k] = 1u << (31 - k);
    // x + 1 (s = 1, a = 0, m = 1)
    v[1][0] = 1u << 31;
    for (int k = 1; k < 32; ++k)
      v[1][k] = v[1][k - 1] ^ (v[1][k - 1] >> 1);
    // x^2 + x + 1 (s = 2, a = 1, m = 1, 3)
    v[2][0] = 1u << 31;
    v[2][1] = 3u << 30;
    for (int k = 2; k < 32; ++k)
      v[2][k] = v[2][k - 2] ^ (v[2][k - 2] >> 2) ^ v[2][k - 1];
  }
};
inline constexpr SobolMatrices kSobol{};

/// The matrices folded into byte tables: a point is four lookups per
/// dimension instead of one XOR per index bit (the sampler is hot).
struct SobolByteTables {
  uint32_t t[3][4][256];
  constexpr SobolByteTables() : t() {
    for (int d = 0; d < 3; ++d)
      for (int byte = 0; byte < 4; ++byte)
        for (int value = 0; value < 256; ++value) {
          uint32_t x = 0;
          for (int bit = 0; bit < 8; ++bit)
            if (value >> bit & 1)
              x ^= kSobol.v[d][8 * byte + bit];
          t[d][byte][value] = x;
        }
  }
};
inline const SobolByteTables &sobolTables() {
  static constexpr SobolByteTables tables{};
  return tables;
}

inline uint32_t sobol(int dim, uint32_t index) {
  const auto &t = sobolTables().t[dim];
  return t[0][index & 255] ^ t[1][index >> 8 & 255] ^ t[2][index >> 16 & 255] ^
         t[3][index >> 24];
}

inline uint32_t reverseBits(uint32_t x) {
  x = ((x & 0x55555555U) << 1) | ((x >> 1) & 0x55555555U);
  x = ((x & 0x33333333U) << 2) | ((x >> 2) & 0x33333333U);
  x = ((x & 0x0f0f0f0fU) << 4) | ((x >> 4) & 0x0f0f0f0fU);
  x = ((x & 0x00ff00ffU) << 8) | ((x >> 8) & 0x00ff00ffU);
  return (x << 16) | (x >> 16);
}

/// Owen scrambling by hashing (Burley, "Practical Hash-based Owen
/// Scrambling", 2020): a random nested uniform permutation of the bits
/// from the most significant down, which keeps a sequence's strata.
inline uint32_t owenScramble(uint32_t x, uint32_t seed) {
  x = reverseBits(x);
  x += seed;
  x ^= x * 0x6c50b47cU;
  x ^= x * 0xb82f1e52U;
  x ^= x * 0xc7afe638U;
  x ^= x * 0x8d22f6e6U;
  return reverseBits(x);
}

/// Point `call` (1, 2, ...) of the path seeded (`key`, `index`): its own
/// shuffle of the sample order (so calls are uncorrelated) and its own
/// scramble of each dimension. Integer math only, so it vectorizes and is
/// the same in every lane (always inlined: a call would keep a lane loop
/// from vectorizing).
[[gnu::always_inline]] inline Vec3 samplerPoint(uint32_t key, uint32_t index, uint32_t call) {
  auto toFloat = [](uint32_t x) { return float(x >> 8) * 0x1p-24f; };
  uint32_t h = hash32(key ^ hash32(call * 0x85ebca6bU));
  uint32_t i = owenScramble(index, h);
  return {toFloat(owenScramble(sobol(0, i), hash32(h + 1))),
          toFloat(owenScramble(sobol(1, i), hash32(h + 2))),
          toFloat(owenScramble(sobol(2, i), hash32(h + 3)))};
}

class Sampler {
public:
  Sampler() = default;
  Sampler(uint32_t pixel, uint32_t index, uint32_t seed)
      : key(hash32(pixel * 0x9e3779b9U ^ hash32(seed + 0x632be5abU))), index(index) {}
  /// The next call's point.
  Vec3 get() { return samplerPoint(key, index, ++call); }
  /// The next `n` calls, to draw them elsewhere (a batch of paths at a
  /// time): the first is returned, and get() continues after the last.
  uint32_t reserve(uint32_t n) {
    call += n;
    return call - n + 1;
  }
  uint32_t pathKey() const { return key; }
  uint32_t sampleIndex() const { return index; }

private:
  uint32_t key = 0, index = 0, call = 0;
};

} // namespace osl::render

#endif // OSLRENDER_SAMPLER_H
