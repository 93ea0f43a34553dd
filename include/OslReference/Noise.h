//===- Noise.h - Scalar reference of OSL's noise functions ------*- C++ -*-===//
//
// Bit-exact float32 re-implementation of the noise functions of OSL 1.13
// (liboslnoise, scalar `testshade`), written from OSL's documented behaviour
// and checked against ../shared/conformance/noise_values.tsv.
//
// This is the ground truth that the MLIR lowering (OslTransforms/NoiseBuilder)
// mirrors operation by operation, so both must change together. Compile it
// without floating-point contraction (-ffp-contract=off): an FMA changes the
// rounding and breaks the bit-exact match with OSL.
//
// Domains follow OSL: 1D noise(x), 2D noise(x, y), 3D noise(point p),
// 4D noise(point p, float w). "Triple" variants are the color/point/vector
// valued overloads (three decorrelated channels).
//
//===----------------------------------------------------------------------===//
#ifndef OSLREFERENCE_NOISE_H
#define OSLREFERENCE_NOISE_H

#include <cstdint>
#include <optional>
#include <string_view>

namespace osl::ref {

//===----------------------------------------------------------------------===//
// Building blocks (exposed so that tests can pin down each step)
//===----------------------------------------------------------------------===//

/// Bob Jenkins' lookup3 hash of 1 to 5 32-bit keys, seeded with
/// 0xdeadbeef + (nkeys << 2) + 13 (OSL's `inthash`).
uint32_t inthash(uint32_t k0);
uint32_t inthash(uint32_t k0, uint32_t k1);
uint32_t inthash(uint32_t k0, uint32_t k1, uint32_t k2);
uint32_t inthash(uint32_t k0, uint32_t k1, uint32_t k2, uint32_t k3);
uint32_t inthash(uint32_t k0, uint32_t k1, uint32_t k2, uint32_t k3,
                 uint32_t k4);

/// Maps 32 hash bits to [0, 1]: float(bits) * 2^-32 (OSL's bits_to_01; the
/// constant 1/(2^32-1) rounds to exactly 2^-32 in float).
float bitsTo01(uint32_t bits);

//===----------------------------------------------------------------------===//
// Perlin gradient noise
//===----------------------------------------------------------------------===//

/// Signed Perlin noise, OSL "perlin" / snoise(). Range about [-1, 1].
float perlin(float x);
float perlin(float x, float y);
float perlin(const float p[3]);
float perlin(const float p[3], float w);
void perlinTriple(float x, float out[3]);
void perlinTriple(float x, float y, float out[3]);
void perlinTriple(const float p[3], float out[3]);
void perlinTriple(const float p[3], float w, float out[3]);

/// Unsigned Perlin noise, OSL "uperlin" / noise(): 0.5 * (perlin + 1).
float uperlin(float x);
float uperlin(float x, float y);
float uperlin(const float p[3]);
float uperlin(const float p[3], float w);
void uperlinTriple(float x, float out[3]);
void uperlinTriple(float x, float y, float out[3]);
void uperlinTriple(const float p[3], float out[3]);
void uperlinTriple(const float p[3], float w, float out[3]);

/// Periodic signed Perlin noise, OSL pnoise("perlin", ...) / psnoise().
/// Periods are floored and clamped to at least 1; the lattice wraps.
float periodicPerlin(float x, float px);
float periodicPerlin(float x, float y, float px, float py);
float periodicPerlin(const float p[3], const float pp[3]);
float periodicPerlin(const float p[3], float w, const float pp[3], float pw);
void periodicPerlinTriple(float x, float px, float out[3]);
void periodicPerlinTriple(float x, float y, float px, float py, float out[3]);
void periodicPerlinTriple(const float p[3], const float pp[3], float out[3]);
void periodicPerlinTriple(const float p[3], float w, const float pp[3],
                          float pw, float out[3]);

/// Periodic unsigned Perlin noise, OSL pnoise("uperlin", ...) / pnoise().
float periodicUPerlin(float x, float px);
float periodicUPerlin(float x, float y, float px, float py);
float periodicUPerlin(const float p[3], const float pp[3]);
float periodicUPerlin(const float p[3], float w, const float pp[3], float pw);
void periodicUPerlinTriple(float x, float px, float out[3]);
void periodicUPerlinTriple(float x, float y, float px, float py,
                           float out[3]);
void periodicUPerlinTriple(const float p[3], const float pp[3], float out[3]);
void periodicUPerlinTriple(const float p[3], float w, const float pp[3],
                           float pw, float out[3]);

//===----------------------------------------------------------------------===//
// Cell and hash noise
//===----------------------------------------------------------------------===//

/// Cell noise, OSL "cell" / cellnoise(): a hash of floor(coords), in [0, 1].
float cell(float x);
float cell(float x, float y);
float cell(const float p[3]);
float cell(const float p[3], float w);
void cellTriple(float x, float out[3]);
void cellTriple(float x, float y, float out[3]);
void cellTriple(const float p[3], float out[3]);
void cellTriple(const float p[3], float w, float out[3]);

/// Hash noise, OSL "hash" / hashnoise(): a hash of the coordinates' bit
/// patterns (so 0.0 and -0.0 differ), in [0, 1].
float hash(float x);
float hash(float x, float y);
float hash(const float p[3]);
float hash(const float p[3], float w);
void hashTriple(float x, float out[3]);
void hashTriple(float x, float y, float out[3]);
void hashTriple(const float p[3], float out[3]);
void hashTriple(const float p[3], float w, float out[3]);

//===----------------------------------------------------------------------===//
// Simplex noise
//===----------------------------------------------------------------------===//

/// Signed simplex noise, OSL "simplex". Range about [-1, 1].
float simplex(float x);
float simplex(float x, float y);
float simplex(const float p[3]);
float simplex(const float p[3], float w);
void simplexTriple(float x, float out[3]);
void simplexTriple(float x, float y, float out[3]);
void simplexTriple(const float p[3], float out[3]);
void simplexTriple(const float p[3], float w, float out[3]);

/// Unsigned simplex noise, OSL "usimplex": 0.5 * (simplex + 1).
float usimplex(float x);
float usimplex(float x, float y);
float usimplex(const float p[3]);
float usimplex(const float p[3], float w);
void usimplexTriple(float x, float out[3]);
void usimplexTriple(float x, float y, float out[3]);
void usimplexTriple(const float p[3], float out[3]);
void usimplexTriple(const float p[3], float w, float out[3]);

//===----------------------------------------------------------------------===//
// Dispatch by name and dimension (for tests and tools)
//===----------------------------------------------------------------------===//

enum class NoiseType { Perlin, UPerlin, Cell, Hash, Simplex, USimplex };

/// OSL noise type names: "perlin"/"snoise", "uperlin"/"noise", "cell"/
/// "cellnoise", "hash"/"hashnoise", "simplex", "usimplex".
std::optional<NoiseType> parseNoiseType(std::string_view name);

/// `in` holds `dims` (1-4) coordinates in OSL's domain order (x, y, z, w).
float noise(NoiseType type, int dims, const float *in);
void noiseTriple(NoiseType type, int dims, const float *in, float out[3]);

/// Periodic variants (OSL's pnoise): Perlin/UPerlin wrap the integer
/// lattice; Cell/Hash wrap the coordinates, s - p * floor(s / p) with
/// p = max(floor(period), 1). Returns false for Simplex/USimplex, which have
/// no periodic form.
bool periodicNoise(NoiseType type, int dims, const float *in,
                   const float *period, float *out);
bool periodicNoiseTriple(NoiseType type, int dims, const float *in,
                         const float *period, float out[3]);

} // namespace osl::ref

#endif // OSLREFERENCE_NOISE_H
