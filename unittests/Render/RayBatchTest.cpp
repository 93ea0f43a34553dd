//===- RayBatchTest.cpp - Rays traced a SIMD batch at a time ---------------===//
//
// intersectBatch at 4, 8 and 16 lanes gives each ray the hit it gets alone
// (width 1), bit for bit, however many rays a batch holds; and the hits
// are the right ones where they can be worked out by hand.
//
//===----------------------------------------------------------------------===//
#include "OslRender/Geometry.h"
#include "OslRender/Sampler.h"
#include "TestScene.h"

#include <gtest/gtest.h>

using namespace osl::render;
using namespace osl::render::testing;

TEST(RayBatch, HandWorkedHits) {
  Scene scene = boxWithSpheres();
  Hit h = intersect(scene, Vec3(0, 0, 0), Vec3(0, 0, -1), -1);
  EXPECT_EQ(h.prim, 0);
  EXPECT_EQ(h.t, 4.0f);
  // Refracted into the big sphere where it was hit: its far side, 2 away.
  h = intersect(scene, Vec3(0, 0, -4), Vec3(0, 0, -1), 0);
  EXPECT_EQ(h.prim, 0);
  EXPECT_FLOAT_EQ(h.t, 2.0f);
  // Reflected back toward the camera: nothing there.
  h = intersect(scene, Vec3(0, 0, -4), Vec3(0, 0, 1), 0);
  EXPECT_EQ(h.prim, -1);
  // Straight down to the floor; along it (parallel to the floor) to the wall.
  h = intersect(scene, Vec3(-3, 0, -6), Vec3(0, -1, 0), -1);
  EXPECT_EQ(h.prim, 2);
  EXPECT_FLOAT_EQ(h.t, 1.0f);
  h = intersect(scene, Vec3(-3, -1, -6), Vec3(0, 0, -1), 2);
  EXPECT_EQ(h.prim, 3);
  EXPECT_FLOAT_EQ(h.t, 2.0f);
  // Up and away: nothing.
  h = intersect(scene, Vec3(0, 0, 0), Vec3(0, 1, 0), -1);
  EXPECT_EQ(h.prim, -1);
}

TEST(RayBatch, EveryWidthGivesEachRayItsOwnHit) {
  Scene scene = boxWithSpheres();
  RayBatch rays;
  std::vector<Hit> alone;
  Sampler rng(7, 3, 11);
  // 203 rays: no width divides it, so the last batch is padded.
  for (int i = 0; i < 203; ++i) {
    Vec3 a = rng.get(), b = rng.get();
    Vec3 o(4 * a.x - 2, 2 * a.y - 1, -6 * a.z);
    Vec3 d = normalize(Vec3(2 * b.x - 1, 2 * b.y - 1, 2 * b.z - 1));
    int self = i % 5 == 0 ? i % 4 : -1; // some rays leave a primitive
    if (i % 7 == 0)
      d = Vec3(d.x, 0, d.z); // parallel to the floor
    rays.push(o, d, self);
    alone.push_back(intersect(scene, o, d, self));
  }
  int hitsSeen = 0;
  for (int width : {1, 4, 8, 16}) {
    SCOPED_TRACE(width);
    std::vector<Hit> hits;
    intersectBatch(scene, rays, width, hits);
    ASSERT_EQ(hits.size(), rays.size());
    for (size_t k = 0; k < hits.size(); ++k) {
      EXPECT_EQ(hits[k].prim, alone[k].prim) << "ray " << k;
      EXPECT_TRUE(sameBits(hits[k].t, alone[k].t)) << "ray " << k;
      hitsSeen += hits[k].prim >= 0;
    }
  }
  EXPECT_GT(hitsSeen, 4 * 100); // most rays hit something
}
