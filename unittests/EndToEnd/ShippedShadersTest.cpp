//===- ShippedShadersTest.cpp - Every shipped shader, every width ---------===//
//
// Each shader in shaders/ is compiled at widths 1, 4, 8 and 16, at every
// --math level, and shaded on a 61x47 grid (not a multiple of 16, so the
// last batch is partial); every output image must be bit-identical to
// width 1's at the same level.
//
//===----------------------------------------------------------------------===//
#include "OslCompiler/ShaderCompiler.h"
#include "OslRuntime/ThreadPool.h"

#include "llvm/Support/MemoryBuffer.h"
#include "llvm/Support/raw_ostream.h"

#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>

using namespace osl;

namespace {

std::vector<std::string> shippedShaders() {
  std::vector<std::string> paths;
  for (auto &entry : std::filesystem::directory_iterator(OSL_SHADERS_DIR))
    if (entry.path().extension() == ".osl")
      paths.push_back(entry.path().string());
  std::sort(paths.begin(), paths.end());
  return paths;
}

using mlir::osl::MathLevel;

ShadeResult shadeAt(const std::string &path, int width, MathLevel math,
                    std::vector<OutputSpec> &outputs) {
  auto buffer = llvm::MemoryBuffer::getFile(path);
  EXPECT_TRUE(bool(buffer)) << path;
  std::string errors;
  llvm::raw_string_ostream errs(errors);
  CompileOptions options;
  options.width = width;
  options.math = math;
  ShaderCompiler compiler(options, errs);
  std::unique_ptr<CompiledShader> shader =
      compiler.compile((*buffer)->getBuffer(), path);
  EXPECT_TRUE(shader) << errors;
  if (!shader)
    return {};
  outputs = shader->outputs;
  GridOptions grid;
  grid.xres = 61;
  grid.yres = 47;
  grid.threads = 2;
  return shadeGrid(shader->kernel, width, shader->outputs, grid);
}

class ShippedShader
    : public testing::TestWithParam<std::tuple<std::string, MathLevel>> {};

TEST_P(ShippedShader, BitIdenticalAcrossWidths) {
  auto [path, math] = GetParam();
  std::vector<OutputSpec> outputs;
  ShadeResult scalar = shadeAt(path, 1, math, outputs);
  ASSERT_FALSE(scalar.images.empty());
  // An image that is one flat value would make the comparison vacuous.
  const std::vector<float> &first = scalar.images.front();
  EXPECT_NE(std::count(first.begin(), first.end(), first.front()),
            std::ptrdiff_t(first.size()))
      << "first output is constant";
  for (int width : {4, 8, 16}) {
    std::vector<OutputSpec> wideOutputs;
    ShadeResult wide = shadeAt(path, width, math, wideOutputs);
    ASSERT_EQ(wide.images.size(), scalar.images.size());
    for (size_t o = 0; o < outputs.size(); ++o) {
      const auto &a = scalar.images[o], &b = wide.images[o];
      ASSERT_EQ(a.size(), b.size());
      size_t differing = 0;
      for (size_t i = 0; i < a.size(); ++i)
        differing += std::memcmp(&a[i], &b[i], sizeof(float)) != 0;
      EXPECT_EQ(differing, 0u) << outputs[o].name << " at width " << width;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(
    Shaders, ShippedShader,
    testing::Combine(testing::ValuesIn(shippedShaders()),
                     testing::Values(MathLevel::Fast, MathLevel::Default, MathLevel::Precise,
                                     MathLevel::Double)),
    [](const auto &info) {
      return std::filesystem::path(std::get<0>(info.param)).stem().string() + "_" +
             mlir::osl::mathLevelName(std::get<1>(info.param));
    });

} // namespace
