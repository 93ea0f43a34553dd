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
  genericLaneKernels().intersect(scene, rays, nullptr, rays.size(), 1, reference);
  int hitsSeen = 0;
  for (const LaneKernels *kernels : laneKernelsThisCpuRuns())
    for (int width : {1, 4, 8, 16}) {
      SCOPED_TRACE(std::string(kernels->isa) + " width " + std::to_string(width));
      std::vector<Hit> hits;
      kernels->intersect(scene, rays, nullptr, rays.size(), width, hits);
      ASSERT_EQ(hits.size(), reference.size());
      for (size_t k = 0; k < hits.size(); ++k) {
        EXPECT_EQ(hits[k].prim, reference[k].prim) << "ray " << k;
        EXPECT_TRUE(sameBits(hits[k].t, reference[k].t)) << "ray " << k;
        hitsSeen += hits[k].prim >= 0;
      }
    }
  EXPECT_GT(hitsSeen, 100);
}

TEST(LaneKernels, HitGeometryMatchesAtEveryWidth) {
  // Hits on every primitive of the scene, 203 of them (no width divides
  // it), through a permuted ray index as the integrator's queues use.
  Scene scene = boxWithSpheres();
  PrimTable prims(scene);
  RayBatch rays;
  Sampler rng(5, 1, 3);
  for (int i = 0; i < 203; ++i) {
    Vec3 a = rng.get(), b = rng.get();
    Vec3 o(4 * a.x - 2, 2 * a.y - 0.5f, -6 * a.z);
    rays.push(o, normalize(Vec3(2 * b.x - 1, 2 * b.y - 1, 2 * b.z - 1)), -1);
  }
  std::vector<Hit> found;
  genericLaneKernels().intersect(scene, rays, nullptr, rays.size(), 1, found);
  HitPoints reference;
  for (int i = int(rays.size()) - 1; i >= 0; --i)
    if (found[i].prim >= 0)
      reference.push(found[i].prim, i, found[i].t);
  ASSERT_GT(reference.size(), 100u);
  genericLaneKernels().hitGeometry(prims, rays, reference, 1);
  // Spheres' normals are unit and face the ray; u and v lie in [0, 1].
  for (size_t i = 0; i < reference.size(); ++i) {
    EXPECT_NEAR(length(reference.n(i)), 1.0f, 1e-5f);
    EXPECT_LE(dot(reference.n(i), reference.d(i)), 0.0f);
    EXPECT_GE(reference.u[i], -1e-5f);
    EXPECT_LE(reference.u[i], 1 + 1e-5f);
  }
  for (const LaneKernels *kernels : laneKernelsThisCpuRuns())
    for (int width : {1, 4, 8, 16}) {
      SCOPED_TRACE(std::string(kernels->isa) + " width " + std::to_string(width));
      HitPoints h;
      for (size_t i = 0; i < reference.size(); ++i)
        h.push(reference.prim[i], reference.ray[i], reference.t[i]);
      kernels->hitGeometry(prims, rays, h, width);
      for (size_t i = 0; i < h.size(); ++i) {
        const std::vector<float> HitPoints::*outputs[] = {
            &HitPoints::px,    &HitPoints::py,    &HitPoints::pz,         &HitPoints::nx,
            &HitPoints::ny,    &HitPoints::nz,    &HitPoints::dPdux,      &HitPoints::dPduy,
            &HitPoints::dPduz, &HitPoints::dPdvx, &HitPoints::dPdvy,      &HitPoints::dPdvz,
            &HitPoints::u,     &HitPoints::v,     &HitPoints::backfacing, &HitPoints::area,
            &HitPoints::dx};
        for (auto column : outputs)
          EXPECT_TRUE(sameBits((h.*column)[i], (reference.*column)[i])) << "hit " << i;
      }
    }
}

TEST(LaneKernels, CameraRaysMatchAtEveryWidth) {
  CameraSetup camera;
  camera.eye = Vec3(0, 1, 5);
  camera.dir = Vec3(0, 0, -1);
  camera.right = Vec3(0.7f, 0, 0);
  camera.up = Vec3(0, 0.5f, 0);
  camera.xres = 37, camera.yres = 23;
  std::vector<int> pixels;
  std::vector<float> jx, jy;
  Sampler rng(2, 2, 2);
  for (int i = 0; i < 37 * 23; i += 4) {
    Vec3 r = rng.get();
    pixels.push_back(i), jx.push_back(r.x), jy.push_back(r.y);
  }
  size_t n = pixels.size();
  std::vector<float> rx(n), ry(n), rz(n);
  genericLaneKernels().cameraRays(camera, pixels.data(), jx.data(), jy.data(), n, rx.data(),
                                  ry.data(), rz.data(), 1);
  for (size_t i = 0; i < n; ++i) {
    EXPECT_NEAR(rx[i] * rx[i] + ry[i] * ry[i] + rz[i] * rz[i], 1.0f, 1e-5f);
    // Left columns look left, top rows up (the tent moves a ray by at most a pixel).
    int col = pixels[i] % 37, row = pixels[i] / 37;
    if (col < 17)
      EXPECT_LT(rx[i], 0.0f) << "pixel " << pixels[i];
    if (row < 10)
      EXPECT_GT(ry[i], 0.0f) << "pixel " << pixels[i];
  }
  for (const LaneKernels *kernels : laneKernelsThisCpuRuns())
    for (int width : {1, 4, 8, 16}) {
      SCOPED_TRACE(std::string(kernels->isa) + " width " + std::to_string(width));
      std::vector<float> x(n), y(n), z(n);
      kernels->cameraRays(camera, pixels.data(), jx.data(), jy.data(), n, x.data(), y.data(),
                          z.data(), width);
      for (size_t i = 0; i < n; ++i)
        EXPECT_TRUE(sameBits(x[i], rx[i]) && sameBits(y[i], ry[i]) && sameBits(z[i], rz[i]))
            << "ray " << i;
    }
}
