//===- NoiseValuesTest.cpp - Compiled noise against OSL's own values ------===//
//
// A probe shader reads its coordinates from the globals (P and u), so the
// noise runs in the JIT-compiled kernel, not in a constant folder. The
// kernel is called directly with globals holding the 100 points of
// conformance/noise_values.tsv, at every width, and each result must equal
// OSL 1.13's value bit for bit.
//
//===----------------------------------------------------------------------===//
#include "OslCompiler/ShaderCompiler.h"

#include "llvm/Support/raw_ostream.h"

#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <map>
#include <sstream>

using namespace osl;

namespace {

struct NoiseRow {
  float in[4];
  float out[3];
};

/// Rows of one (type, dims, result) group.
std::vector<NoiseRow> loadRows(const std::string &type, int dims,
                               const std::string &result) {
  std::ifstream file(OSL_NOISE_VALUES_TSV);
  std::string line;
  std::getline(file, line);
  std::vector<NoiseRow> rows;
  while (std::getline(file, line)) {
    std::vector<std::string> cells;
    std::stringstream ss(line);
    std::string cell;
    while (std::getline(ss, cell, '\t'))
      cells.push_back(cell);
    cells.resize(14);
    if (cells[0] != type || std::stoi(cells[1]) != dims || cells[2] != result)
      continue;
    NoiseRow row{};
    for (int i = 0; i < dims; ++i)
      row.in[i] = std::stof(cells[3 + i]);
    for (int i = 0; i < (result == "color" ? 3 : 1); ++i)
      row.out[i] = std::stof(cells[11 + i]);
    rows.push_back(row);
  }
  return rows;
}

/// The probe's noise call for each dimension: P holds x, y, z and u holds w.
const char *domain(int dims) {
  switch (dims) {
  case 1: return "P[0]";
  case 2: return "P[0], P[1]";
  case 3: return "P";
  default: return "P, u";
  }
}

struct NoiseCase {
  std::string type;
  int dims;
  std::string result;
};

void PrintTo(const NoiseCase &c, std::ostream *os) {
  *os << c.type << " " << c.dims << "D " << c.result;
}

class NoiseValues : public testing::TestWithParam<std::tuple<NoiseCase, int>> {};

TEST_P(NoiseValues, MatchOsl) {
  auto [c, width] = GetParam();
  std::vector<NoiseRow> rows = loadRows(c.type, c.dims, c.result);
  ASSERT_EQ(rows.size(), 100u);
  std::string resultType = c.result == "color" ? "color" : "float";
  // pnoise_perlin rows use periods 4, 3, 5, 2 (the corpus README).
  static const char *const periods[] = {"", "4.0", "4.0, 3.0", "point(4, 3, 5)",
                                        "point(4, 3, 5), 2.0"};
  bool periodic = c.type == "pnoise_perlin";
  std::string call = periodic ? std::string("pnoise(\"perlin\", ") + domain(c.dims) +
                                    ", " + periods[c.dims] + ")"
                              : "noise(\"" + c.type + "\", " + domain(c.dims) + ")";
  std::string source = "shader probe(output " + resultType + " r = 0) { r = " + call + "; }";
  std::string errors;
  llvm::raw_string_ostream errs(errors);
  CompileOptions options;
  options.width = width;
  ShaderCompiler compiler(options, errs);
  auto shader = compiler.compile(source, "probe.osl");
  ASSERT_TRUE(shader) << errors;
  int channels = c.result == "color" ? 3 : 1;
  std::vector<float> globals(kGlobalRows * width), outputs(channels * width);
  const GlobalSlot *p = findGlobal("P"), *u = findGlobal("u");
  size_t mismatches = 0;
  for (size_t first = 0; first < rows.size(); first += width) {
    int n = std::min<size_t>(width, rows.size() - first);
    for (int lane = 0; lane < n; ++lane) {
      const NoiseRow &row = rows[first + lane];
      for (int i = 0; i < 3; ++i)
        globals[(p->row + i) * width + lane] = row.in[i];
      globals[u->row * width + lane] = row.in[3];
    }
    shader->kernel(globals.data(), outputs.data(), n);
    for (int lane = 0; lane < n; ++lane)
      for (int ch = 0; ch < channels; ++ch) {
        float got = outputs[ch * width + lane];
        float want = rows[first + lane].out[ch];
        if (std::memcmp(&got, &want, sizeof(float)) != 0 && ++mismatches <= 5)
          ADD_FAILURE() << c.type << " " << c.dims << "D point " << first + lane
                        << " channel " << ch << ": got " << got << ", OSL " << want;
      }
  }
  EXPECT_EQ(mismatches, 0u);
}

std::vector<NoiseCase> cases() {
  std::vector<NoiseCase> all;
  for (const char *type :
       {"perlin", "uperlin", "cell", "hash", "simplex", "usimplex", "pnoise_perlin"}) {
    for (int dims = 1; dims <= 4; ++dims)
      all.push_back({type, dims, "float"});
    all.push_back({type, 3, "color"});
  }
  return all;
}

INSTANTIATE_TEST_SUITE_P(
    Noise, NoiseValues,
    testing::Combine(testing::ValuesIn(cases()), testing::Values(1, 4, 8, 16)),
    [](const testing::TestParamInfo<std::tuple<NoiseCase, int>> &info) {
      const NoiseCase &c = std::get<0>(info.param);
      return c.type + "_" + std::to_string(c.dims) + "D_" + c.result + "_w" +
             std::to_string(std::get<1>(info.param));
    });

} // namespace
