//===- GridTest.cpp - testshade conventions of the grid driver -------------===//
//
// Hand-written C++ kernels stand in for compiled shaders: one copies every
// global to an output so each value can be checked against testshade's
// setup_shaderglobals, others expose the batching itself.
//
//===----------------------------------------------------------------------===//

#include "OslRuntime/Grid.h"
#include "OslRuntime/ThreadPool.h"

#include "gtest/gtest.h"

#include <algorithm>
#include <cstring>

using namespace osl;

namespace {

constexpr int kWidths[] = {1, 4, 8, 16};

/// Copies all kGlobalRows globals to one output of kGlobalRows channels.
template <int W> void copyGlobals(const float *g, float *out, int32_t nactive) {
  for (int r = 0; r < kGlobalRows; ++r)
    for (int lane = 0; lane < nactive; ++lane)
      out[r * W + lane] = g[r * W + lane];
}

/// Output "lane": (lane index, nactive); lanes past nactive get a marker
/// that must never reach an image.
template <int W> void laneInfo(const float *, float *out, int32_t nactive) {
  for (int lane = 0; lane < W; ++lane) {
    bool on = lane < nactive;
    out[0 * W + lane] = on ? float(lane) : -1000.0f;
    out[1 * W + lane] = on ? float(nactive) : -1000.0f;
  }
}

/// Writes only lanes with u < 0.5 (like a shader writing an output inside
/// a varying if), to check that the other lanes come out as 0.
template <int W> void halfWriter(const float *g, float *out, int32_t nactive) {
  const float *u = g + findGlobal("u")->row * W;
  for (int lane = 0; lane < nactive; ++lane)
    if (u[lane] < 0.5f)
      out[lane] = 1.0f + u[lane];
}

BatchKernel pick(int width, BatchKernel k1, BatchKernel k4, BatchKernel k8,
                 BatchKernel k16) {
  switch (width) {
  case 1: return k1;
  case 4: return k4;
  case 8: return k8;
  default: return k16;
  }
}
#define KERNEL_FOR(NAME, WIDTH)                                                \
  pick(WIDTH, NAME<1>, NAME<4>, NAME<8>, NAME<16>)

/// testshade's setup_shaderglobals for one point, written out directly.
std::vector<float> expectedGlobals(int x, int y, const GridOptions &o) {
  std::vector<float> g(kGlobalRows, 0.0f);
  auto set = [&](const char *name, std::initializer_list<float> values) {
    int row = findGlobal(name)->row;
    for (float v : values)
      g[row++] = v;
  };
  float u, v, dudx = 0, dudy = 0, dvdx = 0, dvdy = 0;
  if (o.center) {
    u = o.uscale * (float)(x + 0.5f) / o.xres + o.uoffset;
    v = o.vscale * (float)(y + 0.5f) / o.yres + o.voffset;
    dudx = o.uscale / o.xres;
    dvdy = o.vscale / o.yres;
  } else {
    u = o.uscale * ((o.xres == 1) ? 0.5f : (float)x / (o.xres - 1)) + o.uoffset;
    v = o.vscale * ((o.yres == 1) ? 0.5f : (float)y / (o.yres - 1)) + o.voffset;
    dudx = o.uscale / std::max(1, o.xres - 1);
    dvdy = o.vscale / std::max(1, o.yres - 1);
  }
  if (o.varyUdxdy) {
    dudx = 1.0f - u;
    dudy = u;
  }
  if (o.varyVdxdy) {
    dvdx = 1.0f - v;
    dvdy = v;
  }
  set("u", {u});
  set("v", {v});
  set("dudx", {dudx});
  set("dudy", {dudy});
  set("dvdx", {dvdx});
  set("dvdy", {dvdy});
  set("P", {u, v, 1.0f});
  if (o.varyPdxdy) {
    set("dPdx", {1.0f - u, 1.0f - v, float(u * 0.5)});
    set("dPdy", {1.0f - v, 1.0f - u, float(v * 0.5)});
  } else {
    set("dPdx", {o.uscale / std::max(1, o.xres - 1), 0, 0});
    set("dPdy", {0, o.vscale / std::max(1, o.yres - 1), 0});
  }
  set("dPdu", {1, 0, 0});
  set("dPdv", {0, 1, 0});
  set("N", {0, 0, 1});
  set("Ng", {0, 0, 1});
  set("surfacearea", {1});
  return g;
}

/// Shades with copyGlobals and compares every global of every pixel,
/// bit for bit.
void checkGlobals(const GridOptions &o, int width) {
  SCOPED_TRACE(testing::Message() << "width " << width << ", grid " << o.xres
                                  << "x" << o.yres);
  ShadeResult r = shadeGrid(KERNEL_FOR(copyGlobals, width), width,
                            {{"globals", kGlobalRows}}, o);
  ASSERT_EQ(r.images.size(), 1u);
  ASSERT_EQ(r.images[0].size(), size_t(o.xres) * o.yres * kGlobalRows);
  int failures = 0;
  for (int y = 0; y < o.yres; ++y)
    for (int x = 0; x < o.xres; ++x) {
      std::vector<float> want = expectedGlobals(x, y, o);
      const float *got = &r.images[0][(size_t(y) * o.xres + x) * kGlobalRows];
      for (const GlobalSlot &s : kGlobalSlots)
        for (int c = 0; c < s.rows; ++c)
          if (std::memcmp(&got[s.row + c], &want[s.row + c], sizeof(float)) &&
              ++failures < 10)
            ADD_FAILURE() << s.name << "[" << c << "] at (" << x << "," << y
                          << "): got " << got[s.row + c] << ", want "
                          << want[s.row + c];
    }
  EXPECT_EQ(failures, 0);
}

GridOptions grid(int xres, int yres) {
  GridOptions o;
  o.xres = xres;
  o.yres = yres;
  o.threads = 1;
  return o;
}

} // namespace

TEST(Grid, GlobalsFollowTestshadeConventions) {
  for (int width : kWidths)
    checkGlobals(grid(61, 47), width);
}

TEST(Grid, GlobalsWithCenter) {
  GridOptions o = grid(61, 47);
  o.center = true;
  for (int width : kWidths)
    checkGlobals(o, width);
}

TEST(Grid, GlobalsWithVaryingDerivatives) {
  GridOptions o = grid(61, 47);
  o.varyUdxdy = o.varyVdxdy = o.varyPdxdy = true;
  for (int width : kWidths)
    checkGlobals(o, width);
  o.center = true;
  o.varyUdxdy = false;
  checkGlobals(o, 8);
}

TEST(Grid, GlobalsWithScaleAndOffset) {
  GridOptions o = grid(33, 20);
  o.uscale = 2.5f;
  o.vscale = 0.3f;
  o.uoffset = -1.0f;
  o.voffset = 0.125f;
  checkGlobals(o, 16);
}

TEST(Grid, SingleRowOrColumnIsAtHalf) {
  checkGlobals(grid(1, 5), 4);
  checkGlobals(grid(7, 1), 16);
  checkGlobals(grid(1, 1), 8);
}

TEST(Grid, BoundaryValuesAreExact) {
  GridOptions o = grid(61, 47);
  ShadeResult r = shadeGrid(copyGlobals<8>, 8, {{"g", kGlobalRows}}, o);
  auto at = [&](int x, int y, const char *name) {
    return r.images[0][(size_t(y) * o.xres + x) * kGlobalRows +
                       findGlobal(name)->row];
  };
  EXPECT_EQ(at(0, 0, "u"), 0.0f);
  EXPECT_EQ(at(60, 0, "u"), 1.0f);
  EXPECT_EQ(at(0, 46, "v"), 1.0f);
  EXPECT_EQ(at(30, 23, "u"), 0.5f);
  EXPECT_EQ(at(30, 23, "v"), 0.5f);
  EXPECT_EQ(at(5, 5, "dudx"), 1.0f / 60);
  EXPECT_EQ(at(5, 5, "dvdy"), 1.0f / 46);
}

TEST(Grid, DiscardedOutputsTakeNoMemory) {
  GridOptions o = grid(61, 47);
  o.keepImages = {false, true};
  ShadeResult r =
      shadeGrid(copyGlobals<8>, 8, {{"dropped", kGlobalRows}, {"kept", kGlobalRows}}, o);
  ASSERT_EQ(r.images.size(), 2u);
  EXPECT_TRUE(r.images[0].empty());
  EXPECT_EQ(r.images[1].size(), size_t(61) * 47 * kGlobalRows);
}

TEST(Grid, BatchesAreConsecutiveRowMajorPixels) {
  GridOptions o = grid(61, 47);
  long npixels = 61 * 47; // 2867: a partial last batch at widths 4, 8, 16
  for (int width : kWidths) {
    SCOPED_TRACE(width);
    ShadeResult r = shadeGrid(KERNEL_FOR(laneInfo, width), width,
                              {{"lane", 2}}, o);
    const std::vector<float> &img = r.images[0];
    for (long p = 0; p < npixels; ++p) {
      long batchStart = p / width * width;
      ASSERT_EQ(img[2 * p + 0], float(p - batchStart)) << "pixel " << p;
      ASSERT_EQ(img[2 * p + 1], float(std::min<long>(width, npixels - batchStart)))
          << "pixel " << p;
    }
  }
}

TEST(Grid, MultipleOutputsAreSeparateImages) {
  // Channels of consecutive outputs follow each other in the kernel's rows.
  GridOptions o = grid(13, 9);
  ShadeResult r = shadeGrid(copyGlobals<4>, 4,
                            {{"P", 3}, {"I", 3}, {"N", 3}, {"rest", kGlobalRows - 9}}, o);
  ASSERT_EQ(r.images.size(), 4u);
  for (int y = 0; y < o.yres; ++y)
    for (int x = 0; x < o.xres; ++x) {
      std::vector<float> want = expectedGlobals(x, y, o);
      size_t p = size_t(y) * o.xres + x;
      for (int c = 0; c < 3; ++c) {
        EXPECT_EQ(r.images[0][p * 3 + c], want[0 + c]);
        EXPECT_EQ(r.images[1][p * 3 + c], want[3 + c]);
        EXPECT_EQ(r.images[2][p * 3 + c], want[6 + c]);
      }
      EXPECT_EQ(r.images[3][p * (kGlobalRows - 9) + 0], want[9]);
    }
}

TEST(Grid, UnwrittenLanesAreZero) {
  GridOptions o = grid(61, 47);
  ShadeResult r = shadeGrid(halfWriter<16>, 16, {{"f", 1}}, o);
  for (int y = 0; y < o.yres; ++y)
    for (int x = 0; x < o.xres; ++x) {
      float u = (float)x / 60;
      EXPECT_EQ(r.images[0][size_t(y) * o.xres + x], u < 0.5f ? 1.0f + u : 0.0f);
    }
}

TEST(Grid, ThreadsAndTilesDoNotChangeResults) {
  GridOptions o = grid(61, 47);
  o.varyPdxdy = true;
  for (int width : kWidths) {
    SCOPED_TRACE(width);
    BatchKernel k = KERNEL_FOR(copyGlobals, width);
    std::vector<OutputSpec> outs = {{"g", kGlobalRows}};
    ShadeResult one = shadeGrid(k, width, outs, o);
    for (int threads : {2, 3}) {
      for (int tile : {0, 1, 7}) {
        GridOptions p = o;
        p.threads = threads;
        p.tileBatches = tile;
        ShadeResult many = shadeGrid(k, width, outs, p);
        ASSERT_EQ(one.images[0].size(), many.images[0].size());
        EXPECT_EQ(0, std::memcmp(one.images[0].data(), many.images[0].data(),
                                 one.images[0].size() * sizeof(float)))
            << threads << " threads, tile " << tile;
      }
    }
    // The unwritten-lane zeroing must hold whatever ran before on a thread.
    GridOptions p = o;
    p.threads = 2;
    p.tileBatches = 1;
    ShadeResult a = shadeGrid(KERNEL_FOR(halfWriter, width), width,
                              {{"f", 1}}, grid(61, 47));
    ShadeResult b = shadeGrid(KERNEL_FOR(halfWriter, width), width,
                              {{"f", 1}}, p);
    EXPECT_EQ(a.images[0], b.images[0]);
  }
}

TEST(Grid, WidthsGiveIdenticalImages) {
  GridOptions o = grid(61, 47);
  o.center = true;
  ShadeResult ref = shadeGrid(copyGlobals<1>, 1, {{"g", kGlobalRows}}, o);
  for (int width : {4, 8, 16}) {
    ShadeResult r = shadeGrid(KERNEL_FOR(copyGlobals, width), width,
                              {{"g", kGlobalRows}}, o);
    EXPECT_EQ(0, std::memcmp(ref.images[0].data(), r.images[0].data(),
                             ref.images[0].size() * sizeof(float)))
        << width;
  }
}

TEST(Grid, ReusesAPool) {
  ThreadPool pool(2);
  GridOptions o = grid(61, 47);
  ShadeResult a = shadeGrid(copyGlobals<8>, 8, {{"g", kGlobalRows}}, o, pool);
  ShadeResult b = shadeGrid(copyGlobals<8>, 8, {{"g", kGlobalRows}}, o, pool);
  EXPECT_EQ(a.images[0], b.images[0]);
  EXPECT_GE(a.seconds, 0.0);
}

TEST(Grid, EmptyGridAndNoOutputs) {
  ShadeResult r = shadeGrid(copyGlobals<4>, 4, {{"g", kGlobalRows}}, grid(0, 5));
  ASSERT_EQ(r.images.size(), 1u);
  EXPECT_TRUE(r.images[0].empty());
  ShadeResult none = shadeGrid(laneInfo<4>, 4, {}, grid(5, 5));
  EXPECT_TRUE(none.images.empty());
}

TEST(Grid, FillGlobalsRepeatsLastPixelPastNactive) {
  GridOptions o = grid(61, 47);
  std::vector<float> g(kGlobalRows * 16);
  // Pixels 59, 60 (end of row 0), 61, 62 (start of row 1), then 12 copies.
  fillGlobals(g.data(), 16, 59, 4, o);
  const float *u = &g[findGlobal("u")->row * 16];
  const float *v = &g[findGlobal("v")->row * 16];
  EXPECT_EQ(u[0], 59.0f / 60);
  EXPECT_EQ(u[1], 1.0f);
  EXPECT_EQ(u[2], 0.0f);
  EXPECT_EQ(v[2], 1.0f / 46);
  for (int lane = 3; lane < 16; ++lane) {
    EXPECT_EQ(u[lane], 1.0f / 60);
    EXPECT_EQ(v[lane], 1.0f / 46);
  }
}
