//===- VolumeTextureTest.cpp - texture3d on a volume the project writes ---===//
//
// osl-make-volume writes an OpenVDB volume whose voxels hold their own
// world position (and a ramp x + 2y + 4z), so trilinear lookups have a known
// answer inside the volume: the lookup point itself. Outside, "clamp" repeats
// the face and "black" gives 0. Every width must give the same bits.
//
//===----------------------------------------------------------------------===//
#include "OslCompiler/ShaderCompiler.h"
#include "OslRuntime/ThreadPool.h"
#include "TempDir.h"

#include "llvm/Support/raw_ostream.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <cstdlib>

using namespace osl;

namespace {

constexpr int kVoxels = 16;

/// The volume, written once per test process into its own directory.
const std::string &volumePath() {
  static test::TempDir dir("osl-volume");
  static std::string path = [] {
    std::string p = dir.path + "/volume.vdb";
    std::string command = std::string(OSL_MAKE_VOLUME) + " " + p + " " +
                          std::to_string(kVoxels);
    EXPECT_EQ(std::system(command.c_str()), 0) << command;
    return p;
  }();
  return path;
}

/// Shades a 13x11 grid (partial last batch) with `body` and returns its
/// float outputs, one image per output.
ShadeResult shade(const std::string &body, int width) {
  std::string source = "shader volume(string file = \"" + volumePath() +
                       "\", output color C = 0, output float f = 0)\n{\n" + body + "\n}\n";
  std::string errors;
  llvm::raw_string_ostream errs(errors);
  CompileOptions options;
  options.width = width;
  ShaderCompiler compiler(options, errs);
  std::unique_ptr<CompiledShader> shader = compiler.compile(source, "volume.osl");
  EXPECT_TRUE(shader) << errors;
  if (!shader)
    return {};
  GridOptions grid;
  grid.xres = 13;
  grid.yres = 11;
  grid.threads = 1;
  return shadeGrid(shader->kernel, width, shader->outputs, grid);
}

/// Point (x, y) of the grid: u = x / 12, v = y / 10.
float gridU(int x) { return float(x) / 12.0f; }
float gridV(int y) { return float(y) / 10.0f; }

TEST(VolumeTexture, InteriorLookupsReproduceTheLinearField) {
  const char *body =
      "point p = point(0.2 + 0.5 * u, 0.25 + 0.5 * v, 0.3 + 0.2 * u * v);\n"
      "C = texture3d(file, p, \"interp\", \"linear\");\n"
      "f = texture3d(file, p, \"subimage\", \"ramp\", \"interp\", \"linear\");";
  ShadeResult r = shade(body, 16);
  ASSERT_EQ(r.images.size(), 2u);
  double worst = 0;
  for (int y = 0; y < 11; ++y)
    for (int x = 0; x < 13; ++x) {
      float u = gridU(x), v = gridV(y);
      float p[3] = {0.2f + 0.5f * u, 0.25f + 0.5f * v, 0.3f + 0.2f * u * v};
      size_t i = size_t(y) * 13 + x;
      for (int c = 0; c < 3; ++c)
        worst = std::max(worst, std::fabs(double(r.images[0][i * 3 + c]) - p[c]));
      worst = std::max(worst, std::fabs(double(r.images[1][i]) - (p[0] + 2 * p[1] + 4 * p[2])));
    }
  EXPECT_LT(worst, 1e-5);
}

TEST(VolumeTexture, WrapModesOutsideTheVolume) {
  // x runs from -0.5 to 1.5: under clamp every point past a face reads what
  // the face holds, so points beyond the volume agree; under black they are 0.
  const char *body = "point p = point(2 * u - 0.5, 0.5, 0.5);\n"
                     "C = texture3d(file, p, \"wrap\", \"clamp\", \"interp\", \"linear\");\n"
                     "f = texture3d(file, p, \"wrap\", \"black\", \"subimage\", \"ramp\");";
  ShadeResult r = shade(body, 8);
  ASSERT_EQ(r.images.size(), 2u);
  // u = 0, 1/12 (p.x = -0.5, -0.33) and u = 11/12, 1 (p.x = 1.33, 1.5).
  for (auto [a, b] : {std::pair{0, 1}, std::pair{11, 12}})
    for (int c = 0; c < 3; ++c)
      EXPECT_EQ(r.images[0][size_t(a) * 3 + c], r.images[0][size_t(b) * 3 + c])
          << "clamp, channel " << c << ", points " << a << " and " << b;
  for (int x : {0, 1, 11, 12})
    EXPECT_EQ(r.images[1][size_t(x)], 0.0f) << "black at point " << x;
  // Inside, black changes nothing: the ramp at the centre point.
  EXPECT_NEAR(r.images[1][6], 0.5 + 2 * 0.5 + 4 * 0.5, 1e-5);
}

TEST(VolumeTexture, BitIdenticalAcrossWidths) {
  const char *body =
      "point p = point(u * 1.4 - 0.2, v * 1.4 - 0.2, 0.5);\n"
      "string modes[3] = { \"black\", \"clamp\", \"periodic\" };\n"
      "C = texture3d(file, p, \"wrap\", modes[(int) floor(u * 2.999)]);\n"
      "f = texture3d(file, p, \"subimage\", 1, \"blur\", 0.1 * v);";
  ShadeResult base = shade(body, 1);
  ASSERT_EQ(base.images.size(), 2u);
  for (int width : {4, 8, 16}) {
    ShadeResult r = shade(body, width);
    ASSERT_EQ(r.images.size(), 2u);
    for (size_t k = 0; k < 2; ++k)
      EXPECT_EQ(0, std::memcmp(base.images[k].data(), r.images[k].data(),
                               base.images[k].size() * sizeof(float)))
          << "output " << k << " at width " << width;
  }
}

} // namespace
