//===- KernelCacheTest.cpp - Compiled kernels kept between runs -----------===//
//
// The cache's file format refuses every damaged entry (flipped bytes
// anywhere, truncation at any length, another key's file), and a compile
// through the cache gives the same images as one without it, loading the
// kernel the second time instead of compiling it.
//
//===----------------------------------------------------------------------===//
#include "OslCompiler/KernelCache.h"
#include "OslCompiler/ShaderCompiler.h"
#include "OslRuntime/ThreadPool.h"
#include "TempDir.h"

#include "llvm/Support/raw_ostream.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>

using namespace osl;

namespace {

std::string readFile(const std::string &path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

void writeFile(const std::string &path, const std::string &data) {
  std::ofstream(path, std::ios::binary | std::ios::trunc) << data;
}

CachedKernel sampleEntry() {
  return {"sample",
          {{"Cout", 3}, {"f", 1}},
          std::string("\x7f" "ELF object bytes", 17),
          {"library object one", std::string("two\0bytes", 9)},
          /*warnings=*/"",
          /*reports=*/""};
}

TEST(KernelCacheTest, StoredEntryReadsBack) {
  test::TempDir dir{"osl-kernel-cache"};
  KernelCache cache(dir.path + "/nested/dir");
  CachedKernel entry;
  EXPECT_EQ(cache.lookup("key", entry), CacheLookup::Miss);
  std::string error;
  ASSERT_TRUE(cache.store("key", sampleEntry(), error)) << error;
  ASSERT_EQ(cache.lookup("key", entry), CacheLookup::Hit);
  EXPECT_EQ(entry.shaderName, "sample");
  ASSERT_EQ(entry.outputs.size(), 2u);
  EXPECT_EQ(entry.outputs[0].name, "Cout");
  EXPECT_EQ(entry.outputs[0].channels, 3);
  EXPECT_EQ(entry.outputs[1].name, "f");
  EXPECT_EQ(entry.object, sampleEntry().object);
  EXPECT_EQ(entry.libraries, sampleEntry().libraries);
  EXPECT_EQ(cache.lookup("other key", entry), CacheLookup::Miss);
}

/// A cache in a fresh directory with the sample entry stored under "key":
/// `good` is its file's content, to damage in every way.
class StoredSampleTest : public ::testing::Test {
protected:
  void SetUp() override {
    std::string error;
    ASSERT_TRUE(cache.store("key", sampleEntry(), error)) << error;
    path = cache.pathFor("key");
    good = readFile(path);
  }
  test::TempDir dir{"osl-kernel-cache"};
  KernelCache cache{dir.path};
  std::string path, good;
};

TEST_F(StoredSampleTest, EveryFlippedByteIsCorrupt) {
  for (size_t i = 0; i < good.size(); ++i) {
    std::string bad = good;
    bad[i] ^= 0x20;
    writeFile(path, bad);
    CachedKernel entry;
    EXPECT_EQ(cache.lookup("key", entry), CacheLookup::Corrupt) << "byte " << i;
  }
}

TEST_F(StoredSampleTest, EveryTruncationIsCorrupt) {
  for (size_t n = 0; n < good.size(); ++n) {
    writeFile(path, good.substr(0, n));
    CachedKernel entry;
    EXPECT_EQ(cache.lookup("key", entry), CacheLookup::Corrupt) << n << " bytes";
  }
}

TEST(KernelCacheTest, AnotherKeysEntryIsCorrupt) {
  test::TempDir dir{"osl-kernel-cache"};
  KernelCache cache(dir.path);
  std::string error;
  ASSERT_TRUE(cache.store("key A", sampleEntry(), error)) << error;
  // As if "key B" hashed to the file "key A" wrote.
  std::filesystem::copy_file(cache.pathFor("key A"), cache.pathFor("key B"));
  CachedKernel entry;
  EXPECT_EQ(cache.lookup("key B", entry), CacheLookup::Corrupt);
}

TEST(KernelCacheTest, UnwritableDirectoryIsAnError) {
  test::TempDir dir{"osl-kernel-cache"};
  writeFile(dir.path + "/file", "x");
  KernelCache cache(dir.path + "/file/sub");
  std::string error;
  EXPECT_FALSE(cache.store("key", sampleEntry(), error));
  EXPECT_FALSE(error.empty());
}

constexpr const char *kShader = R"(
shader cached(float scale = 3, output color Cout = 0, output float f = 0)
{
    f = noise("perlin", P * scale);
    if (u > 0.5)
        Cout = color(f, u, v);
}
)";

struct Compiled {
  std::unique_ptr<CompiledShader> shader;
  CacheUse use;
};

Compiled compileWith(const std::string &cacheDir, int width,
                     std::vector<ParamOverride> params = {}) {
  CompileOptions options;
  options.width = width;
  options.cacheDir = cacheDir;
  options.params = std::move(params);
  std::string errors;
  llvm::raw_string_ostream errs(errors);
  ShaderCompiler compiler(options, errs);
  Compiled c{compiler.compile(kShader, "cached.osl"), compiler.cacheUse()};
  EXPECT_TRUE(c.shader) << errors;
  return c;
}

std::vector<std::vector<float>> shade(const CompiledShader &shader) {
  GridOptions grid;
  grid.xres = 37;
  grid.yres = 5;
  ThreadPool pool(1);
  return shadeGrid(shader.kernel, shader.width, shader.outputs, grid, pool).images;
}

TEST(KernelCacheTest, SecondCompileLoadsTheSameKernel) {
  test::TempDir dir{"osl-kernel-cache"};
  Compiled plain = compileWith("", 8);
  ASSERT_TRUE(plain.shader);
  EXPECT_EQ(plain.use, CacheUse::Off);

  Compiled first = compileWith(dir.path, 8);
  ASSERT_TRUE(first.shader);
  EXPECT_EQ(first.use, CacheUse::Miss);
  Compiled second = compileWith(dir.path, 8);
  ASSERT_TRUE(second.shader);
  EXPECT_EQ(second.use, CacheUse::Hit);
  EXPECT_EQ(second.shader->name, "cached");
  ASSERT_EQ(second.shader->outputs.size(), 2u);
  EXPECT_EQ(second.shader->outputs[0].channels, 3);
  EXPECT_EQ(shade(*second.shader), shade(*plain.shader));

  // Another width or parameter value is another kernel.
  EXPECT_EQ(compileWith(dir.path, 4).use, CacheUse::Miss);
  EXPECT_EQ(compileWith(dir.path, 8, {{"scale", "5"}}).use, CacheUse::Miss);
  EXPECT_EQ(compileWith(dir.path, 8, {{"scale", "5"}}).use, CacheUse::Hit);
}

TEST(KernelCacheTest, DamagedEntryIsRebuiltNotRun) {
  test::TempDir dir{"osl-kernel-cache"};
  Compiled first = compileWith(dir.path, 8);
  ASSERT_TRUE(first.shader);
  // One kernel entry (library/ holds the noise function's object).
  std::vector<std::string> entries;
  for (const auto &e : std::filesystem::directory_iterator(dir.path))
    if (e.is_regular_file())
      entries.push_back(e.path().string());
  ASSERT_EQ(entries.size(), 1u);
  std::string path = entries.front();
  std::string data = readFile(path);
  data[data.size() / 2] ^= 0x55; // inside the object code
  writeFile(path, data);

  Compiled rebuilt = compileWith(dir.path, 8);
  ASSERT_TRUE(rebuilt.shader);
  EXPECT_EQ(rebuilt.use, CacheUse::Rebuilt);
  EXPECT_EQ(shade(*rebuilt.shader), shade(*first.shader));
  EXPECT_EQ(compileWith(dir.path, 8).use, CacheUse::Hit);
}

} // namespace
