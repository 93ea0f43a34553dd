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
    Sampler path(int(i % 17), int(i % 5), i);
    path.reserve(i % 9);
    uint32_t seed = path.reserve(1);
    draws.push(seed, path.sampleIndex());
    alone.push_back(samplerPoint(seed, path.sampleIndex()));
  }
  // The same as get() gives one call at a time.
  Sampler path(3, 9, 5), copy = path;
  EXPECT_TRUE(sameBits(path.get().y, samplerPoint(copy.reserve(1), copy.sampleIndex()).y));
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
    Vec3 o = pointInBox(rng.get()), b = rng.get();
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
  // Normals are unit and face the ray; u and v lie in [0, 1] (on the
  // spheres and inside the quads alike).
  for (size_t i = 0; i < reference.size(); ++i) {
    EXPECT_NEAR(length(reference.n(i)), 1.0f, 1e-5f);
    EXPECT_LE(dot(reference.n(i), reference.d(i)), 0.0f);
    for (float uv : {reference.u[i], reference.v[i]}) {
      EXPECT_GE(uv, -1e-5f);
      EXPECT_LE(uv, 1 + 1e-5f);
    }
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
            &HitPoints::ox,    &HitPoints::oy,    &HitPoints::oz,         &HitPoints::dx,
            &HitPoints::dy,    &HitPoints::dz};
        for (auto column : outputs)
          EXPECT_TRUE(sameBits((h.*column)[i], (reference.*column)[i])) << "hit " << i;
      }
    }
}

TEST(LaneKernels, CameraRaysMatchAtEveryWidth) {
  CameraSetup camera;
  camera.eye = Vec3(0, 1, 5);
  camera.dir = Vec3(0, 0, -1);
  camera.cx = Vec3(0.7f, 0, 0);
  camera.cy = Vec3(0, 0.5f, 0);
  camera.xres = 37, camera.yres = 23;
  camera.invw = 1.0f / 37, camera.invh = 1.0f / 23;
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

TEST(LaneKernels, CameraRaysFindTheirPixelPastTwoToThe24) {
  // A 4097-wide image's pixels past 2^24: each pixel of a row looks
  // further right than the one before it (a float index would merge them).
  CameraSetup camera;
  camera.dir = Vec3(0, 0, -1);
  camera.cx = Vec3(1, 0, 0);
  camera.cy = Vec3(0, 1, 0);
  camera.xres = 4097, camera.yres = 4500;
  camera.invw = 1.0f / 4097, camera.invh = 1.0f / 4500;
  std::vector<int> pixels;
  for (int k = 0; k < 40; ++k)
    pixels.push_back((1 << 24) + k);
  std::vector<float> centre(pixels.size(), 0.5f), x(pixels.size()), y(x), z(x);
  for (const LaneKernels *kernels : laneKernelsThisCpuRuns())
    for (int width : {1, 16}) {
      SCOPED_TRACE(std::string(kernels->isa) + " width " + std::to_string(width));
      kernels->cameraRays(camera, pixels.data(), centre.data(), centre.data(), pixels.size(),
                          x.data(), y.data(), z.data(), width);
      for (size_t i = 1; i < pixels.size(); ++i)
        if (pixels[i] % camera.xres != 0) // the same row as the one before
          EXPECT_GT(x[i] / -z[i], x[i - 1] / -z[i - 1]) << "pixel " << pixels[i];
    }
}

TEST(LaneKernels, LightSamplesMatchAtEveryWidth) {
  // Sphere and quad lights seen from 203 points (no width divides it),
  // some inside the first sphere (testrender then samples the whole
  // sphere of directions about its centre).
  Scene scene = boxWithSpheres();
  PrimTable prims(scene);
  LightDraws reference;
  Sampler rng(9, 4, 1);
  for (int i = 0; i < 203; ++i) {
    Vec3 a = rng.get(), r = rng.get();
    Vec3 from = i % 7 == 0 ? Vec3(0.3f * a.x, 0.3f * a.y, -5) // inside sphere 0
                           : pointInBox(a);
    reference.push(i % 4, from, r.x, r.y);
  }
  genericLaneKernels().sampleLights(prims, reference, 1);
  for (size_t i = 0; i < reference.size(); ++i) {
    EXPECT_GT(reference.pdf[i], 0.0f) << "sample " << i;
    if (i % 7 == 0)
      continue;
    EXPECT_NEAR(length(reference.dir(i)), 1.0f, 1e-5f) << "sample " << i;
    // The direction reaches the light it sampled (nothing is in the way
    // of a light as its own only primitive).
    Scene alone;
    alone.prims.push_back(scene.prims[reference.light[i]]);
    Vec3 from(reference.ox[i], reference.oy[i], reference.oz[i]);
    EXPECT_EQ(intersect(alone, from, reference.dir(i), -1).prim, 0) << "sample " << i;
  }
  for (const LaneKernels *kernels : laneKernelsThisCpuRuns())
    for (int width : {1, 4, 8, 16}) {
      SCOPED_TRACE(std::string(kernels->isa) + " width " + std::to_string(width));
      LightDraws draws;
      for (size_t i = 0; i < reference.size(); ++i)
        draws.push(reference.light[i], Vec3(reference.ox[i], reference.oy[i], reference.oz[i]),
                   reference.rx[i], reference.ry[i]);
      kernels->sampleLights(prims, draws, width);
      for (size_t i = 0; i < draws.size(); ++i) {
        EXPECT_TRUE(sameBits(draws.pdf[i], reference.pdf[i])) << "sample " << i;
        EXPECT_TRUE(sameBits(draws.dx[i], reference.dx[i]) &&
                      sameBits(draws.dy[i], reference.dy[i]) &&
                      sameBits(draws.dz[i], reference.dz[i]))
              << "sample " << i;
      }
    }
}

namespace {

/// A 32 x 32 background table whose cells all differ (each cell's
/// radiance names it), with a band of black rows and black columns in
/// every row (equal entries in the cumulative tables).
BackgroundMap namedCellsMap() {
  BackgroundMap map;
  map.prepare(32, [](const std::vector<Dual3> &dirs, std::vector<Vec3> &radiance) {
    radiance.resize(dirs.size());
    for (size_t i = 0; i < dirs.size(); ++i) {
      int x = int(i % 32), y = int(i / 32);
      bool black = (y >= 10 && y < 13) || x % 5 == 2;
      radiance[i] = black ? Vec3() : Vec3(float(1 + x), float(1 + y), 0.5f + float(i));
    }
  });
  return map;
}

/// The cell testrender's sampler picks for (rx, ry): std::upper_bound
/// through the rows, then through the row (the reference for the lanes'
/// branchless search).
size_t expectedCell(const BackgroundMap::Table &t, float rx, float ry) {
  auto entry = [&](const float *cdf, float x) {
    int i = int(std::upper_bound(cdf, cdf + t.res, x) - cdf);
    return std::min(i, t.res - 1);
  };
  int y = entry(t.rows, ry);
  int x = entry(t.cols + size_t(y) * t.res, rx);
  return size_t(y) * t.res + x;
}

} // namespace

TEST(LaneKernels, BackgroundSamplesPickUpperBoundsCellAtEveryWidth) {
  BackgroundMap map = namedCellsMap();
  BackgroundMap::Table t = map.table();
  // 203 random draws, then the edges: 0, each row's and column's exact
  // cumulative values (equal runs where cells are black), the largest
  // float below 1.
  std::vector<float> rx, ry;
  Sampler rng(2, 7, 5);
  for (int i = 0; i < 203; ++i) {
    Vec3 r = rng.get();
    rx.push_back(r.x), ry.push_back(r.y);
  }
  for (int i = 0; i < t.res; ++i) {
    rx.push_back(t.cols[size_t(3) * t.res + i]), ry.push_back(t.rows[i]);
  }
  rx.push_back(0), ry.push_back(0);
  rx.push_back(0.99999994f), ry.push_back(0.99999994f);
  BackgroundDraws reference;
  genericLaneKernels().sampleBackground(t, rx.data(), ry.data(), rx.size(), reference, 1);
  for (size_t i = 0; i < rx.size(); ++i) {
    SCOPED_TRACE("draw " + std::to_string(i));
    Vec3 value = t.values[expectedCell(t, rx[i], ry[i])];
    EXPECT_TRUE(sameBits(reference.r[i], value.x) && sameBits(reference.g[i], value.y) &&
                sameBits(reference.b[i], value.z));
    EXPECT_GT(reference.value(i).x, 0.0f); // never a black cell
    EXPECT_NEAR(length(reference.dir(i)), 1.0f, 1e-5f);
    // eval() of the direction finds the same cell (its pdf) but at a
    // cell's edge, where the direction's rounding may cross it.
    float pdf = 0;
    Vec3 back = map.eval(reference.dir(i), pdf);
    if (back.x == value.x && back.y == value.y)
      EXPECT_EQ(pdf, reference.pdf[i]);
  }
  for (const LaneKernels *kernels : laneKernelsThisCpuRuns())
    for (int width : {1, 4, 8, 16}) {
      SCOPED_TRACE(std::string(kernels->isa) + " width " + std::to_string(width));
      BackgroundDraws draws;
      kernels->sampleBackground(t, rx.data(), ry.data(), rx.size(), draws, width);
      for (size_t i = 0; i < rx.size(); ++i)
        EXPECT_TRUE(sameBits(draws.pdf[i], reference.pdf[i]) &&
                    sameBits(draws.dx[i], reference.dx[i]) &&
                    sameBits(draws.dy[i], reference.dy[i]) &&
                    sameBits(draws.dz[i], reference.dz[i]) &&
                    sameBits(draws.r[i], reference.r[i]))
            << "draw " << i;
    }
}

TEST(LaneKernels, CosineLobeSamplesMatchOneLobesOwnAtEveryWidth) {
  // Diffuse, translucent and Oren-Nayar lobes about random normals, seen
  // from both sides (Oren-Nayar gives nothing below the surface): 203 of
  // them, which no width divides.
  std::vector<Lobe> lobes;
  std::vector<Vec3> wo, r;
  Sampler rng(4, 4, 8);
  auto unit = [](Vec3 a) { return normalize(Vec3(2 * a.x - 1, 2 * a.y - 1, 2 * a.z - 1)); };
  for (int i = 0; i < 203; ++i) {
    Lobe l;
    l.model = i % 3 == 0 ? Lobe::Diffuse : i % 3 == 1 ? Lobe::Translucent : Lobe::OrenNayar;
    l.n = unit(rng.get());
    l.a = rng.get().x;
    lobes.push_back(l);
    wo.push_back(unit(rng.get()));
    r.push_back(rng.get());
  }
  int zero = 0;
  for (size_t i = 0; i < lobes.size(); ++i)
    zero += sampleLobe(lobes[i], wo[i], r[i].x, r[i].y, r[i].z).pdf == 0;
  EXPECT_GT(zero, 10);  // Oren-Nayar seen from below
  EXPECT_LT(zero, 100);
  for (const LaneKernels *kernels : laneKernelsThisCpuRuns())
    for (int width : {1, 4, 8, 16}) {
      SCOPED_TRACE(std::string(kernels->isa) + " width " + std::to_string(width));
      CosineDraws draws;
      for (size_t i = 0; i < lobes.size(); ++i)
        draws.push(lobes[i], wo[i], r[i].x, r[i].y);
      kernels->sampleCosineLobes(draws, width);
      for (size_t i = 0; i < lobes.size(); ++i) {
        BsdfSample one = sampleLobe(lobes[i], wo[i], r[i].x, r[i].y, r[i].z);
        BsdfSample lane = draws.result(i);
        EXPECT_TRUE(sameBits(lane.pdf, one.pdf) && sameBits(lane.roughness, one.roughness) &&
                    sameBits(lane.weight.x, one.weight.x) &&
                    sameBits(lane.weight.z, one.weight.z) && sameBits(lane.wi.x, one.wi.x) &&
                    sameBits(lane.wi.y, one.wi.y) && sameBits(lane.wi.z, one.wi.z))
            << "lobe " << i;
      }
    }
}

TEST(LaneKernels, BackgroundLookupsMatchEvalAtEveryWidth) {
  // 203 escaped rays (no width divides it), some straight up and down and
  // along the seam where atan2 turns, read through a permuted ray index.
  BackgroundMap map = namedCellsMap();
  RayBatch rays;
  Sampler rng(6, 1, 2);
  auto unit = [](Vec3 a) { return normalize(Vec3(2 * a.x - 1, 2 * a.y - 1, 2 * a.z - 1)); };
  for (int i = 0; i < 203; ++i) {
    Vec3 d = i % 50 == 0   ? Vec3(0, 0, i % 100 == 0 ? 1.0f : -1.0f)
             : i % 50 == 1 ? normalize(Vec3(-1, i % 100 == 1 ? 0.0f : -0.0f, 0.3f))
                           : unit(rng.get());
    rays.push(Vec3(), d, -1);
  }
  std::vector<int> which;
  for (int i = 202; i >= 0; --i)
    which.push_back(i);
  for (const LaneKernels *kernels : laneKernelsThisCpuRuns())
    for (int width : {1, 4, 8, 16}) {
      SCOPED_TRACE(std::string(kernels->isa) + " width " + std::to_string(width));
      BackgroundDraws out;
      kernels->evalBackground(map.table(), rays, which.data(), which.size(), out, width);
      for (size_t i = 0; i < which.size(); ++i) {
        int k = which[i];
        float pdf = 0;
        Vec3 value = map.eval(Vec3(rays.dx[k], rays.dy[k], rays.dz[k]), pdf);
        EXPECT_TRUE(sameBits(out.pdf[i], pdf) && sameBits(out.r[i], value.x) &&
                    sameBits(out.g[i], value.y) && sameBits(out.b[i], value.z))
            << "ray " << k;
      }
    }
}

TEST(LaneKernels, CosineMixturesMatchShadingResultAtEveryWidth) {
  // 203 mixtures of 0 to 4 diffuse, translucent and Oren-Nayar lobes
  // (some of weight 0), seen from both sides, on paths that may end there
  // or not: each prepared, sampled and evaluated toward two directions in
  // lanes must give ShadingResult's bits.
  Sampler rng(7, 2, 11);
  auto unit = [](Vec3 a) { return normalize(Vec3(2 * a.x - 1, 2 * a.y - 1, 2 * a.z - 1)); };
  struct Case {
    ShadingResult result;
    Vec3 wo, pathWeight, r, toward[2];
    bool mayEnd;
  };
  std::vector<Case> cases(203);
  for (size_t i = 0; i < cases.size(); ++i) {
    Case &c = cases[i];
    for (int j = 0; j < int(i % 5); ++j) {
      Lobe l;
      l.model = (i + size_t(j)) % 3 == 0   ? Lobe::Diffuse
                : (i + size_t(j)) % 3 == 1 ? Lobe::Translucent
                                           : Lobe::OrenNayar;
      l.n = unit(rng.get());
      l.a = rng.get().x;
      l.weight = (i + size_t(j)) % 7 == 3 ? Vec3() : rng.get();
      c.result.lobes.push_back(l);
    }
    c.wo = unit(rng.get());
    c.pathWeight = rng.get();
    c.mayEnd = i % 2 == 1;
    c.r = rng.get();
    c.toward[0] = unit(rng.get()), c.toward[1] = unit(rng.get());
  }
  // What ShadingResult gives one mixture at a time.
  std::vector<BsdfSample> samples, evals;
  int ended = 0, zeroPdf = 0;
  for (Case &c : cases) {
    c.result.prepare(c.wo, c.pathWeight, c.mayEnd);
    float rx = c.r.x;
    int lobe = c.result.pick(rx);
    BsdfSample s;
    if (lobe >= 0)
      s = c.result.mixSample(size_t(lobe),
                             sampleLobe(c.result.lobes[size_t(lobe)], c.wo, rx, c.r.y, c.r.z),
                             c.wo);
    ended += lobe < 0 && !c.result.lobes.empty();
    zeroPdf += lobe >= 0 && s.pdf == 0;
    samples.push_back(s);
    for (Vec3 wi : c.toward)
      evals.push_back(c.result.eval(c.wo, wi));
  }
  EXPECT_GT(ended, 5);   // paths ended by the roulette (and 41 empty mixtures)
  EXPECT_GT(zeroPdf, 5); // Oren-Nayar seen from below
  auto same = [](const BsdfSample &a, const BsdfSample &b) {
    return sameBits(a.pdf, b.pdf) && sameBits(a.roughness, b.roughness) &&
           sameBits(a.weight.x, b.weight.x) && sameBits(a.weight.y, b.weight.y) &&
           sameBits(a.weight.z, b.weight.z) && sameBits(a.wi.x, b.wi.x) &&
           sameBits(a.wi.y, b.wi.y) && sameBits(a.wi.z, b.wi.z);
  };
  // One set of columns for every run, as a render reuses them: each run
  // first fills them for twice as many mixtures (another stride, rows a
  // run of fewer mixtures must not read as its own). The evaluations come
  // in a shuffled order, some mixtures twice.
  CosineMixtures mixtures;
  const size_t n = cases.size();
  std::vector<size_t> evalOrder;
  for (size_t k = 0; k < 2 * n + 20; ++k)
    evalOrder.push_back((k * 37) % (2 * n));
  for (const LaneKernels *kernels : laneKernelsThisCpuRuns())
    for (int width : {1, 4, 8, 16}) {
      SCOPED_TRACE(std::string(kernels->isa) + " width " + std::to_string(width));
      mixtures.reset(2 * n, 4);
      for (size_t m = 0; m < 2 * n; ++m) {
        const Case &c = cases[(m * 5) % n];
        mixtures.set(m, c.result.lobes, c.toward[0], c.pathWeight, !c.mayEnd);
        mixtures.rx[m] = c.r.y, mixtures.ry[m] = c.r.x;
      }
      kernels->sampleCosineMixtures(mixtures, width);
      mixtures.reset(n, 4);
      MixtureEvals toward;
      for (size_t m = 0; m < n; ++m) {
        const Case &c = cases[m];
        mixtures.set(m, c.result.lobes, c.wo, c.pathWeight, c.mayEnd);
        mixtures.rx[m] = c.r.x, mixtures.ry[m] = c.r.y;
      }
      for (size_t k : evalOrder)
        toward.push(int(k / 2), cases[k / 2].toward[k % 2]);
      kernels->sampleCosineMixtures(mixtures, width);
      kernels->evalCosineMixtures(mixtures, toward, width);
      for (size_t m = 0; m < n; ++m)
        EXPECT_TRUE(same(mixtures.result(m), samples[m])) << "mixture " << m;
      for (size_t e = 0; e < evalOrder.size(); ++e) {
        const BsdfSample &one = evals[evalOrder[e]];
        EXPECT_TRUE(sameBits(toward.pdf[e], one.pdf) && sameBits(toward.fx[e], one.weight.x) &&
                    sameBits(toward.fy[e], one.weight.y) && sameBits(toward.fz[e], one.weight.z))
            << "evaluation " << e << " (mixture " << evalOrder[e] / 2 << ")";
      }
      // Mixtures without lobes, none of them with any: no sample, and
      // nothing toward any direction.
      ShadingResult empty;
      mixtures.reset(5, 0);
      MixtureEvals nothing;
      for (size_t m = 0; m < 5; ++m) {
        mixtures.set(m, empty.lobes, cases[m].wo, cases[m].pathWeight, false);
        mixtures.rx[m] = cases[m].r.x, mixtures.ry[m] = cases[m].r.y;
        nothing.push(int(m), cases[m].toward[0]);
      }
      kernels->sampleCosineMixtures(mixtures, width);
      kernels->evalCosineMixtures(mixtures, nothing, width);
      for (size_t m = 0; m < 5; ++m) {
        EXPECT_TRUE(same(mixtures.result(m), BsdfSample())) << "empty mixture " << m;
        EXPECT_TRUE(sameBits(nothing.pdf[m], 0.0f) && sameBits(nothing.fx[m], 0.0f))
            << "empty mixture " << m;
      }
    }
}
