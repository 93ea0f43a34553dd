//===- NoiseReferenceTest.cpp - osl::ref noise vs. OSL 1.13 values --------===//
//
// Checks the scalar noise reference bit for bit against the values OSL
// 1.13.12's scalar testshade printed (noise_values.tsv, see
// ../shared/conformance/README.md). The build defines OSL_NOISE_VALUES_TSV
// as the path of that file.
//
//===----------------------------------------------------------------------===//

#include "OslReference/Noise.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#ifndef OSL_NOISE_VALUES_TSV
#error "OSL_NOISE_VALUES_TSV must name conformance/noise_values.tsv"
#endif

using namespace osl::ref;

namespace {

uint32_t bitsOf(float f) {
  uint32_t u;
  std::memcpy(&u, &f, sizeof u);
  return u;
}

/// One TSV row: OSL noise type (or pnoise_perlin/cellnoise/hashnoise), the
/// domain dimension, whether the result is a color, inputs and outputs.
struct Row {
  std::string type;
  int dims = 0;
  bool color = false;
  float in[4] = {0, 0, 0, 0};
  float period[4] = {0, 0, 0, 0};
  float out[3] = {0, 0, 0};
  std::string text;
};

std::vector<std::string> splitTabs(const std::string &line) {
  std::vector<std::string> fields;
  std::string cur;
  for (char c : line) {
    if (c == '\t') {
      fields.push_back(cur);
      cur.clear();
    } else {
      cur += c;
    }
  }
  fields.push_back(cur);
  return fields;
}

float parseFloat(const std::string &s) { return std::strtof(s.c_str(), nullptr); }

const std::vector<Row> &rows() {
  static const std::vector<Row> table = [] {
    std::vector<Row> result;
    std::ifstream in(OSL_NOISE_VALUES_TSV);
    std::string line;
    if (!in || !std::getline(in, line)) // header
      return result;
    while (std::getline(in, line)) {
      if (line.empty())
        continue;
      std::vector<std::string> f = splitTabs(line);
      if (f.size() < 14)
        continue;
      Row r;
      r.type = f[0];
      r.dims = std::atoi(f[1].c_str());
      r.color = f[2] == "color";
      for (int i = 0; i < r.dims; ++i) {
        r.in[i] = parseFloat(f[3 + i]);
        r.period[i] = f[7 + i].empty() ? 0.0f : parseFloat(f[7 + i]);
      }
      for (int i = 0; i < (r.color ? 3 : 1); ++i)
        r.out[i] = parseFloat(f[11 + i]);
      r.text = line;
      result.push_back(r);
    }
    return result;
  }();
  return table;
}

/// Evaluates the reference for a row; false if the type is unknown.
bool evaluate(const Row &r, float out[3]) {
  bool periodic = r.type.rfind("pnoise_", 0) == 0;
  std::string name = periodic ? r.type.substr(7) : r.type;
  std::optional<NoiseType> type = parseNoiseType(name);
  if (!type)
    return false;
  if (periodic)
    return r.color ? periodicNoiseTriple(*type, r.dims, r.in, r.period, out)
                   : periodicNoise(*type, r.dims, r.in, r.period, out);
  if (r.color)
    noiseTriple(*type, r.dims, r.in, out);
  else
    out[0] = noise(*type, r.dims, r.in);
  return true;
}

/// Compares every row of `type` bit for bit (so -0 vs 0 counts) and expects
/// the 5 variants (1D-4D float, 3D color) x 100 points.
void checkType(const std::string &type) {
  ASSERT_FALSE(rows().empty()) << "cannot read " << OSL_NOISE_VALUES_TSV;
  std::map<std::string, int> perVariant;
  int mismatches = 0;
  for (const Row &r : rows()) {
    if (r.type != type)
      continue;
    ++perVariant[std::to_string(r.dims) + (r.color ? "D color" : "D float")];
    float got[3] = {0, 0, 0};
    ASSERT_TRUE(evaluate(r, got)) << "unknown noise type in: " << r.text;
    for (int c = 0; c < (r.color ? 3 : 1); ++c) {
      if (bitsOf(got[c]) == bitsOf(r.out[c]))
        continue;
      // Report the first few in detail; the count says the rest.
      if (++mismatches <= 10)
        ADD_FAILURE() << "channel " << c << ": expected " << r.out[c]
                      << " (0x" << std::hex << bitsOf(r.out[c])
                      << "), got " << got[c] << " (0x" << bitsOf(got[c])
                      << std::dec << ")\n  row: " << r.text;
    }
  }
  EXPECT_EQ(mismatches, 0) << "values differing from OSL for " << type;
  EXPECT_EQ(perVariant.size(), 5u) << "variants of " << type;
  for (const auto &[variant, n] : perVariant)
    EXPECT_EQ(n, 100) << type << " " << variant;
}

TEST(NoiseReference, Perlin) { checkType("perlin"); }
TEST(NoiseReference, UPerlin) { checkType("uperlin"); }
TEST(NoiseReference, Cell) { checkType("cell"); }
TEST(NoiseReference, Hash) { checkType("hash"); }
TEST(NoiseReference, CellNoise) { checkType("cellnoise"); }
TEST(NoiseReference, HashNoise) { checkType("hashnoise"); }
TEST(NoiseReference, PeriodicPerlin) { checkType("pnoise_perlin"); }
TEST(NoiseReference, Simplex) { checkType("simplex"); }
TEST(NoiseReference, USimplex) { checkType("usimplex"); }

TEST(NoiseReference, TableIsComplete) {
  EXPECT_EQ(rows().size(), 4500u);
}

// Properties the lowering relies on, independent of the table.

TEST(NoiseReference, UnsignedIsHalfOfSignedPlusOne) {
  const float pts[][4] = {{0.3f, -1.7f, 2.2f, 0.9f}, {123.25f, 5.5f, -0.1f, 7.0f}};
  for (const auto &p : pts) {
    for (int d = 1; d <= 4; ++d) {
      float s = noise(NoiseType::Perlin, d, p);
      EXPECT_EQ(bitsOf(noise(NoiseType::UPerlin, d, p)),
                bitsOf(0.5f * (s + 1.0f)));
    }
  }
}

TEST(NoiseReference, TripleChannelZeroMatchesFloat) {
  // Channel 0 uses the low byte of the same hash; gradients read only the
  // low 3-5 bits, so it equals the float result.
  const float pts[][4] = {{0.3f, -1.7f, 2.2f, 0.9f}, {-9.75f, 44.5f, 0.01f, -3.3f}};
  for (const auto &p : pts) {
    for (int d = 1; d <= 4; ++d) {
      float t[3];
      noiseTriple(NoiseType::Perlin, d, p, t);
      EXPECT_EQ(bitsOf(t[0]), bitsOf(noise(NoiseType::Perlin, d, p))) << d;
    }
  }
}

TEST(NoiseReference, CellIsHashOfFloor) {
  const float p[4] = {2.75f, -0.5f, 1e4f + 0.25f, -3.0f};
  for (int d = 1; d <= 4; ++d) {
    float again[4] = {2.0f, -0.25f, 1e4f, -3.0f};
    EXPECT_EQ(bitsOf(noise(NoiseType::Cell, d, p)),
              bitsOf(noise(NoiseType::Cell, d, again)))
        << d;
  }
}

TEST(NoiseReference, HashDistinguishesSignedZero) {
  EXPECT_NE(bitsOf(hash(0.0f)), bitsOf(hash(-0.0f)));
  EXPECT_EQ(bitsOf(cell(0.0f)), bitsOf(cell(-0.0f)));
}

TEST(NoiseReference, PeriodicPerlinRepeats) {
  // Offsets that keep the fractional part exact.
  const float per[4] = {4, 3, 5, 2};
  const float p[4] = {0.25f, 1.5f, -2.75f, 0.125f};
  for (int d = 1; d <= 4; ++d) {
    float q[4];
    for (int i = 0; i < 4; ++i)
      q[i] = p[i] + 2.0f * per[i];
    float a, b;
    ASSERT_TRUE(periodicNoise(NoiseType::Perlin, d, p, per, &a));
    ASSERT_TRUE(periodicNoise(NoiseType::Perlin, d, q, per, &b));
    EXPECT_EQ(bitsOf(a), bitsOf(b)) << d;
  }
}

TEST(NoiseReference, OutOfRangeFloorIsIntMin) {
  // floor() beyond the int32 range converts to INT_MIN, as x86's cvttss2si
  // does, instead of being undefined; the lowering does the same.
  const float expected = bitsTo01(inthash(0x80000000u));
  EXPECT_EQ(bitsOf(cell(3e9f)), bitsOf(expected));
  EXPECT_EQ(bitsOf(cell(-1e38f)), bitsOf(expected));
  EXPECT_EQ(bitsOf(cell(-2147483648.0f)), bitsOf(expected));
  EXPECT_NE(bitsOf(cell(2147483520.0f)), bitsOf(expected));
}

TEST(NoiseReference, ParseNames) {
  EXPECT_EQ(parseNoiseType("noise"), NoiseType::UPerlin);
  EXPECT_EQ(parseNoiseType("snoise"), NoiseType::Perlin);
  EXPECT_EQ(parseNoiseType("cellnoise"), NoiseType::Cell);
  EXPECT_EQ(parseNoiseType("hashnoise"), NoiseType::Hash);
  EXPECT_EQ(parseNoiseType("usimplex"), NoiseType::USimplex);
  EXPECT_FALSE(parseNoiseType("gabor").has_value());
}

} // namespace
