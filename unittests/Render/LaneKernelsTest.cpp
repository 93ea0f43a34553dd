//===- LaneKernelsTest.cpp - Render loops on every instruction set --------===//
//
// Each instruction set's loops this CPU runs (plain x86-64, AVX2, AVX-512)
// give, at every width, what one ray or path computes alone: the same hits
// and the same sampler points, bit for bit (renders are then the same on
// every machine and at every width).
//
//===----------------------------------------------------------------------===//
#include "LaneKernels.h"
#include "OslRender/Sampler.h"
#include "TestScene.h"

#include <gtest/gtest.h>

using namespace osl::render;
using namespace osl::render::testing;

TEST(LaneKernels, SamplerPointsMatchOnePathsOwn) {
  // 203 draws of a few paths at assorted calls: no width divides it.
  PointDraws draws;
  std::vector<Vec3> alone;
  for (uint32_t i = 0; i < 203; ++i) {
    Sampler path(i % 17, i, 5);
    uint32_t call = path.reserve(1 + i % 9) + i % 9;
    draws.push(path.pathKey(), path.sampleIndex(), call);
    alone.push_back(samplerPoint(path.pathKey(), path.sampleIndex(), call));
  }
  // The same as get() gives one call at a time.
  Sampler path(3, 9, 5);
  EXPECT_TRUE(sameBits(path.get().y, samplerPoint(path.pathKey(), 9, 1).y));
  for (const LaneKernels *kernels : laneKernelsThisCpuRuns())
    for (int width : {1, 4, 8, 16}) {
      SCOPED_TRACE(std::string(kernels->isa) + " width " + std::to_string(width));
      kernels->drawPoints(draws, width);
      for (size_t k = 0; k < alone.size(); ++k) {
        EXPECT_TRUE(sameBits(draws.x[k], alone[k].x)) << "draw " << k;
        EXPECT_TRUE(sameBits(draws.y[k], alone[k].y)) << "draw " << k;
        EXPECT_TRUE(sameBits(draws.z[k], alone[k].z)) << "draw " << k;
      }
    }
}

TEST(LaneKernels, HitsMatchPlainX86AtWidthOne) {
  Scene scene = boxWithSpheres();
  RayBatch rays;
  Sampler rng(7, 3, 11);
  for (int i = 0; i < 203; ++i) {
    Vec3 a = rng.get(), b = rng.get();
    Vec3 o(4 * a.x - 2, 2 * a.y - 1, -6 * a.z);
    rays.push(o, normalize(Vec3(2 * b.x - 1, 2 * b.y - 1, 2 * b.z - 1)), i % 5 ? -1 : i % 3);
  }
  std::vector<Hit> reference;
  genericLaneKernels().intersect(scene, rays, 1, reference);
  int hitsSeen = 0;
  for (const LaneKernels *kernels : laneKernelsThisCpuRuns())
    for (int width : {1, 4, 8, 16}) {
      SCOPED_TRACE(std::string(kernels->isa) + " width " + std::to_string(width));
      std::vector<Hit> hits;
      kernels->intersect(scene, rays, width, hits);
      ASSERT_EQ(hits.size(), reference.size());
      for (size_t k = 0; k < hits.size(); ++k) {
        EXPECT_EQ(hits[k].prim, reference[k].prim) << "ray " << k;
        EXPECT_TRUE(sameBits(hits[k].t, reference[k].t)) << "ray " << k;
        hitsSeen += hits[k].prim >= 0;
      }
    }
  EXPECT_GT(hitsSeen, 100);
}
