//===- ShaderGroupTest.cpp - Shader groups through the embedding API -----===//
//
// A renderer builds a group with ShaderGroup's statements and compiles it
// with ShaderCompiler::compileGroup: the kernel equals the same network
// written as one shader at widths 1 and 16; bad groups are errors.
//
//===----------------------------------------------------------------------===//
#include "OslCompiler/ShaderCompiler.h"
#include "TempDir.h"

#include "llvm/Support/raw_ostream.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <vector>

using namespace osl;

namespace {

const char *kUpstream = R"(
shader wave(float freq = 1, output float out = 0, output color unused = 0)
{
    out = sin(u * freq) * v;
    unused = color(noise("perlin", P * 9), 0, 0);
}
)";

const char *kDownstream = R"(
shader tint(float x = 0, color c = color(1, 0, 0), output color Cout = 0)
{
    if (x > 0.2)
        Cout = c * x;
    else
        Cout = color(0, 0, x);
}
)";

const char *kNetwork = R"(
shader network(output color Cout = 0)
{
    float x = sin(u * 5) * v;
    if (x > 0.2)
        Cout = color(0, 1, 0) * x;
    else
        Cout = color(0, 0, x);
}
)";

std::string writeTemp(const std::string &name, const char *text) {
  static test::TempDir dir("osl-group");
  std::string path = dir.path + "/" + name;
  std::ofstream(path) << text;
  return path;
}

ShaderGroup twoLayers() {
  ShaderGroup group;
  std::string error;
  group.param("freq", "5");
  EXPECT_TRUE(group.shader(writeTemp("wave.osl", kUpstream), "w", error)) << error;
  group.param("c", "0,1,0");
  EXPECT_TRUE(group.shader(writeTemp("tint.osl", kDownstream), "t", error)) << error;
  group.connect({"w", "out", "t", "x"});
  return group;
}

std::vector<float> shade(const CompiledShader &shader) {
  GridOptions grid;
  grid.xres = 19;
  grid.yres = 7; // a partial last batch at width 16
  grid.threads = 1;
  return shadeGrid(shader.kernel, shader.width, shader.outputs, grid).images.at(0);
}

TEST(ShaderGroupTest, GroupEqualsOneShaderAtEveryWidth) {
  for (int width : {1, 16}) {
    CompileOptions options;
    options.width = width;
    std::string errors;
    llvm::raw_string_ostream errs(errors);
    ShaderCompiler groupCompiler(options, errs);
    auto group = groupCompiler.compileGroup(twoLayers());
    ASSERT_TRUE(group) << errors;
    ShaderCompiler oneCompiler(options, errs);
    auto one = oneCompiler.compile(kNetwork, "network.osl");
    ASSERT_TRUE(one) << errors;
    ASSERT_EQ(group->outputs.size(), 1u); // only the root's Cout is left
    std::vector<float> a = shade(*group), b = shade(*one);
    ASSERT_EQ(a.size(), b.size());
    EXPECT_EQ(0, std::memcmp(a.data(), b.data(), a.size() * sizeof(float)))
        << "width " << width;
    // Both arms of the root's if are taken somewhere.
    EXPECT_TRUE(std::any_of(a.begin(), a.end(), [](float f) { return f > 0.2f; }));
    const GroupStats &stats = groupCompiler.groupStats();
    EXPECT_EQ(stats.layersBefore, 2);
    EXPECT_LT(stats.opsAfter, stats.opsBefore);
  }
}

TEST(ShaderGroupTest, ReparamRespecialises) {
  CompileOptions options;
  options.width = 4;
  std::string errors;
  llvm::raw_string_ostream errs(errors);
  ShaderGroup group = twoLayers();
  ShaderCompiler first(options, errs);
  auto before = first.compileGroup(group);
  ASSERT_TRUE(before) << errors;
  std::string error;
  ASSERT_TRUE(group.reparam("w", "freq", "2", error)) << error;
  ShaderCompiler second(options, errs);
  auto after = second.compileGroup(group);
  ASSERT_TRUE(after) << errors;
  EXPECT_NE(shade(*before), shade(*after));
  EXPECT_FALSE(group.reparam("nosuch", "freq", "2", error));
  EXPECT_EQ(error, "reparam: unknown layer 'nosuch'");
}

TEST(ShaderGroupTest, BadGroupsAreErrors) {
  std::string error;
  ShaderGroup group = twoLayers();
  group.connect({"w", "out", "nosuch", "x"});
  EXPECT_FALSE(group.validate(error));
  EXPECT_EQ(error, "connect: unknown layer 'nosuch'");

  ShaderGroup backwards = twoLayers();
  backwards.connect({"t", "Cout", "w", "freq"});
  EXPECT_FALSE(backwards.validate(error));
  EXPECT_NE(error.find("would make a cycle"), std::string::npos) << error;

  ShaderGroup mismatched = twoLayers();
  mismatched.connections.back() = {"w", "unused", "t", "x"};
  CompileOptions options;
  options.width = 1;
  std::string errors;
  llvm::raw_string_ostream errs(errors);
  ShaderCompiler compiler(options, errs);
  EXPECT_FALSE(compiler.compileGroup(mismatched));
  EXPECT_NE(errors.find("cannot connect output 'w.unused' (color/point/vector/normal) to "
                        "input 't.x' (float)"),
            std::string::npos)
      << errors;
}

TEST(ShaderGroupTest, GroupSyntax) {
  ShaderGroup group;
  std::string error;
  ASSERT_TRUE(group.parseStatements(
      "# comment\nparam float freq 5 ; param color c 0 1 0 [[int lockgeom=0]] ;\n"
      "shader wave w ; shader tint t ; connect w.out t.x ;",
      "/shaders", error))
      << error;
  ASSERT_EQ(group.layers.size(), 2u);
  EXPECT_EQ(group.layers[0].shaderPath, "/shaders/wave.osl");
  ASSERT_EQ(group.layers[0].params.size(), 2u);
  EXPECT_EQ(group.layers[0].params[1].value, "0,1,0");
  EXPECT_EQ(group.layers[0].userdata, std::vector<std::string>{"c"});
  ASSERT_EQ(group.connections.size(), 1u);
  EXPECT_EQ(group.connections[0].toInput, "x");
  EXPECT_FALSE(group.parseStatements("connect w.out ;", "", error));
  EXPECT_EQ(error, "group statement 'connect w.out': expected 'connect FROMLAYER.OUTPUT "
                   "TOLAYER.INPUT ;'");
}

} // namespace
