//===- Integrator.cpp - Wavefront path tracing with batched shading -------===//
#include "BackgroundMap.h"
#include "Dual.h"
#include "LaneKernels.h"
#include "OslAbi/GlobalsLayout.h"
#include "OslFrontend/Frontend.h"
#include "OslRender/Bsdf.h"
#include "OslRender/Geometry.h"
#include "OslRender/Renderer.h"
#include "OslRender/Sampler.h"
#include "OslRender/Sampling.h"
#include "OslRuntime/Closure.h"
#include "OslRuntime/Progress.h"
#include "OslRuntime/ThreadPool.h"

#include "llvm/ADT/STLExtras.h"
#include "llvm/Support/FileSystem.h"
#include "llvm/Support/MemoryBuffer.h"
#include "llvm/Support/Path.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>

namespace osl::render {

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
/// Paths per wave: enough to fill batches per shader, small enough to stay in cache.
constexpr int kWavePaths = 1024;
constexpr int kTileSize = 8;
/// testrender's rr_depth: from this bounce on, lobe choices may end a path.
constexpr int kRouletteDepth = 5;

/// The raytype() bits of camera and bounce rays, looked up once.
int32_t cameraRays() {
  static const int32_t bit = rayTypeBit("camera");
  return bit;
}
int32_t diffuseRays() {
  static const int32_t bit = rayTypeBit("diffuse");
  return bit;
}

struct Path {
  Vec3 weight{1, 1, 1}, radiance;
  float bsdfPdf = kInf; // of the last bounce; infinite for the camera and delta lobes
  /// What raytype() answers for the points the ray reaches (kRayTypes bits).
  int32_t rayType = cameraRays();
  bool alive = true;
  Hit hit;
  Sampler rng;
};

/// Points to shade with one shader: where each is (its geometry computed
/// in lanes; `at.ray` indexes the wave's pathRays for hits and misses, its
/// shadow rays for light queries) and the path it belongs to (for light
/// queries, the shadow ray).
struct ShadeQueue {
  HitPoints at;
  std::vector<int> path;
  /// The ray type every point answers (-1: each its path's own).
  int32_t rayType = -1;
  /// Escaped rays: I is the direction, and there is no surface.
  bool background = false;
  void clear() { resize(0); }
  void resize(size_t n) { at.resize(n), growTo(n, path); }
  void set(size_t i, int prim, int ray, float distance, int p) {
    at.set(i, prim, ray, distance);
    path[i] = p;
  }
  size_t size() const { return at.size(); }
};

/// Sorts n items into queues by index rather than by push: queueOf(k) is
/// item k's queue (-1: none), then add(queue, slot, k) fills its slot.
/// Items keep their order within each queue.
template <typename Queue, typename QueueOf, typename Add>
void sortIntoQueues(size_t n, std::vector<int> &itemQueue, std::vector<size_t> &fill,
                    size_t queueCount, QueueOf queueOf, Queue queue, Add add) {
  itemQueue.resize(n);
  fill.assign(queueCount, 0);
  for (size_t k = 0; k < n; ++k)
    if ((itemQueue[k] = queueOf(k)) >= 0)
      ++fill[size_t(itemQueue[k])];
  for (size_t s = 0; s < queueCount; ++s) {
    queue(s).resize(fill[s]);
    fill[s] = 0;
  }
  for (size_t k = 0; k < n; ++k)
    if (int s = itemQueue[k]; s >= 0)
      add(queue(size_t(s)), fill[size_t(s)]++, k);
}

} // namespace

/// One worker's paths and buffers, reused from wave to wave. Each path
/// is testrender's: one sampler point per bounce, shared by the background
/// sample, every light's sample and the BSDF's.
class PathWave {
public:
  PathWave(const Renderer &r)
      : r(r), scene(r.scene), prims(r.scene), width(r.laneWidth),
        globals(size_t(kGlobalRows) * r.laneWidth), queues(scene.shaders.size()),
        lightQueries(scene.shaders.size()) {
    // testrender numbers spheres before quads, and samples lights in that
    // order.
    for (auto kind : {Primitive::Sphere, Primitive::Quad})
      for (int l = 0; l < int(scene.prims.size()); ++l)
        if (scene.prims[l].kind == kind && scene.prims[l].isLight && scene.prims[l].shader >= 0)
          lights.push_back(l);
    int rows = 1;
    for (const Renderer::Kernel &k : r.kernels)
      rows = std::max(rows, k.outputRows);
    outputs.resize(size_t(rows) * width);
    for (ShadeQueue &q : lightQueries)
      q.rayType = rayTypeBit("shadow"); // lights are seen along shadow rays
    misses.background = true;
    const RenderOptions &opt = r.options;
    const Camera &cam = scene.camera;
    // testrender's camera: the image plane's axes from a fast tangent.
    camera.eye = cam.eye;
    camera.dir = normalize(cam.dir);
    float k = fast::tan(cam.fovDegrees * float(M_PI / 360));
    Vec3 right = normalize(cross(camera.dir, cam.up));
    camera.cx = right * (float(opt.xres) * k / float(opt.yres));
    camera.cy = normalize(cross(camera.cx, camera.dir)) * k;
    camera.invw = 1.0f / float(opt.xres);
    camera.invh = 1.0f / float(opt.yres);
    camera.xres = opt.xres;
    camera.yres = opt.yres;
  }

  /// Traces samples [s0, s1) of every pixel in `pixels`, mixing their
  /// radiance into `mean` (3 floats per pixel of the window).
  void run(const std::vector<int> &pixels, int s0, int s1, float *mean);
  /// The background's radiance toward each of `dirs` (no ray type, as
  /// testrender shades its background table).
  void shadeBackground(const std::vector<Dual3> &dirs, std::vector<Vec3> &radiance);
  void useBackgroundMap(const BackgroundMap *m) { map = m && !m->empty() ? m : nullptr; }

  long batches = 0, shaded = 0;
  double shadingSeconds = 0;

private:
  void startPaths(const std::vector<int> &pixels, int s0, int s1);
  bool intersectPaths();
  void shadeMisses(int bounce);
  void scatterAll(int bounce);
  void sampleBsdfs();
  void traceShadowRays();
  void accumulate(float *mean);
  /// Shades `q`'s points with `shader`, `width` at a time, and calls
  /// use(index in q, closure handle) for each.
  template <typename Use> void shade(int shader, const ShadeQueue &q, Use use);
  void copyRow(int row, const std::vector<float> &from, size_t start, int n) {
    copyRowLanes(&globals[size_t(row) * width], &from[start], n);
  }
  void copyTriple(int row, const std::vector<float> &x, const std::vector<float> &y,
                  const std::vector<float> &z, size_t start, int n) {
    copyRow(row, x, start, n), copyRow(row + 1, y, start, n), copyRow(row + 2, z, start, n);
  }
  /// Queues a shadow ray from hit `i` of `q` toward `dir`, in the room
  /// scatterAll made.
  void queueShadowRay(const ShadeQueue &q, size_t i, Vec3 dir, int light, Vec3 contrib) {
    shadowRays[shadowCount] = {q.path[i], light, contrib, false, Vec3()};
    rays.set(shadowCount++, q.at.p(i), dir, paths[q.path[i]].hit.prim, q.at.radius[i], 0.0f);
  }

  const Renderer &r;
  const Scene &scene;
  PrimTable prims;
  int width;
  CameraSetup camera;
  const BackgroundMap *map = nullptr;
  std::vector<float> globals, outputs;
  std::vector<Path> paths;
  /// Each path's next ray (origin, direction, the primitive it leaves).
  RayBatch pathRays;
  std::vector<ShadingResult> results;
  std::vector<ShadeQueue> queues, lightQueries;
  /// Escaped paths: primitive -1, never given to hitGeometry (shadeMisses
  /// copies their directions).
  ShadeQueue misses;
  /// The lights next-event estimation samples, in testrender's order.
  std::vector<int> lights;
  /// Sampler points drawn a batch at a time (every path's numbers are its
  /// own, whatever the batch).
  PointDraws draws;
  /// The bounce's scattering paths: queue and index of each.
  std::vector<std::pair<const ShadeQueue *, size_t>> scattering;
  /// Each scattering path's light samples, paths and lights in order.
  LightDraws lightDraws;
  /// The background table's answers: toward each escaped ray
  /// (shadeMisses), then toward each scattering path's sample (scatterAll).
  BackgroundDraws backgroundDraws;
  /// Each scattering path's BSDF sample; the samples of cosine lobes,
  /// drawn in lanes, and whose each is (scattering index, lobe).
  std::vector<BsdfSample> bsdfSamples;
  CosineDraws cosineDraws;
  std::vector<std::pair<size_t, size_t>> cosineOwners;
  /// The scattering paths whose mixtures are cosine lobes alone, prepared,
  /// sampled and evaluated in lanes (at widths above 1; the results are
  /// the same): each scattering path's mixture (-1: its ShadingResult's
  /// own), each light draw's, and the evaluations toward the background's
  /// and the lights' samples (in the order they are added).
  CosineMixtures cosineMixtures;
  std::vector<int> mixtureOf, lightDrawMixtures;
  MixtureEvals mixtureEvals;
  /// The bounce's shadow rays, traced together a batch of `width` lanes at
  /// a time.
  RayBatch rays;
  std::vector<Hit> hits;
  /// The paths whose rays this bounce traces, in order (those alive after
  /// the last bounce; intersectPaths ends some of them).
  std::vector<int> rayPaths;
  /// sortIntoQueues' room: each item's queue, each queue's fill.
  std::vector<int> itemQueue;
  std::vector<size_t> queueFill;
  /// Each path's pixel (for the camera's lanes and the image) and sample
  /// index (its pixel's samples are mixed in in order).
  std::vector<int> pathPixels, pathSamples;
  /// A shadow ray traced with the others: toward `light` (-1: the
  /// background), what reaching it adds (times the light's emission), and
  /// once traced and shaded, what it adds. A path adds them in the order it
  /// sampled them, as testrender does.
  struct ShadowRay {
    int path, light;
    Vec3 contrib;
    bool reached = false;
    Vec3 adds;
  };
  std::vector<ShadowRay> shadowRays;
  size_t shadowCount = 0;
  /// Rows of the globals the renderer sets.
  const int rowP = findGlobal("P")->row, rowI = findGlobal("I")->row, rowN = findGlobal("N")->row,
            rowNg = findGlobal("Ng")->row, rowDPdu = findGlobal("dPdu")->row,
            rowDPdv = findGlobal("dPdv")->row, rowU = findGlobal("u")->row,
            rowV = findGlobal("v")->row, rowBackfacing = findGlobal("backfacing")->row,
            rowRayType = findGlobal("raytype")->row,
            rowSurfaceArea = findGlobal("surfacearea")->row, rowDPdx = findGlobal("dPdx")->row,
            rowDPdy = findGlobal("dPdy")->row, rowDudx = findGlobal("dudx")->row,
            rowDudy = findGlobal("dudy")->row, rowDvdx = findGlobal("dvdx")->row,
            rowDvdy = findGlobal("dvdy")->row, rowDIdx = findGlobal("dIdx")->row,
            rowDIdy = findGlobal("dIdy")->row, rowFlip = findGlobal("flipHandedness")->row;
};

template <typename Use> void PathWave::shade(int shader, const ShadeQueue &q, Use use) {
  const Renderer::Kernel &k = r.kernels[shader];
  ClosureArena &arena = threadClosureArena();
  const HitPoints &h = q.at;
  for (size_t start = 0; start < q.size(); start += width) {
    int n = int(std::min<size_t>(width, q.size() - start));
    // Lanes past n, and a background's surface rows, read zeros.
    if (n < width || q.background)
      std::fill(globals.begin(), globals.end(), 0.0f);
    // The globals' rows are the queue's own columns.
    if (!q.background) {
      copyTriple(rowP, h.px, h.py, h.pz, start, n);
      copyTriple(rowN, h.nx, h.ny, h.nz, start, n);
      copyTriple(rowNg, h.nx, h.ny, h.nz, start, n);
      copyTriple(rowDPdu, h.dPdux, h.dPduy, h.dPduz, start, n);
      copyTriple(rowDPdv, h.dPdvx, h.dPdvy, h.dPdvz, start, n);
      copyRow(rowU, h.u, start, n), copyRow(rowV, h.v, start, n);
      copyRow(rowBackfacing, h.backfacing, start, n);
      copyRow(rowSurfaceArea, h.area, start, n);
      copyTriple(rowDPdx, h.dPdxX, h.dPdxY, h.dPdxZ, start, n);
      copyTriple(rowDPdy, h.dPdyX, h.dPdyY, h.dPdyZ, start, n);
      copyRow(rowDudx, h.dudx, start, n), copyRow(rowDudy, h.dudy, start, n);
      copyRow(rowDvdx, h.dvdx, start, n), copyRow(rowDvdy, h.dvdy, start, n);
      copyRow(rowFlip, h.flip, start, n);
    }
    copyTriple(rowI, h.dx, h.dy, h.dz, start, n);
    copyTriple(rowDIdx, h.dIdxX, h.dIdxY, h.dIdxZ, start, n);
    copyTriple(rowDIdy, h.dIdyX, h.dIdyY, h.dIdyZ, start, n);
    float *types = &globals[size_t(rowRayType) * width];
    for (int lane = 0; lane < n; ++lane)
      types[lane] = float(q.rayType >= 0 ? q.rayType : paths[q.path[start + lane]].rayType);
    std::fill(outputs.begin(), outputs.end(), 0.0f);
    arena.reset();
    if (r.options.timeShading) {
      auto t0 = std::chrono::steady_clock::now();
      k.shader->kernel(globals.data(), outputs.data(), n);
      shadingSeconds +=
          std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    } else {
      k.shader->kernel(globals.data(), outputs.data(), n);
    }
    ++batches;
    shaded += n;
    for (int lane = 0; lane < n; ++lane) {
      int32_t handle =
          k.ciRow < 0 ? 0 : closureHandleFromOutput(outputs[size_t(k.ciRow) * width + lane]);
      use(start + lane, handle);
    }
  }
}

void PathWave::shadeBackground(const std::vector<Dual3> &dirs, std::vector<Vec3> &radiance) {
  ShadeQueue q;
  q.background = true;
  q.rayType = 0;
  HitPoints &h = q.at;
  radiance.assign(dirs.size(), Vec3());
  // A wave's worth at a time: the table has a million directions, and a
  // queue's forty columns for all of them would be 160 MB to fault in.
  for (size_t first = 0; first < dirs.size(); first += kWavePaths) {
    size_t n = std::min<size_t>(kWavePaths, dirs.size() - first);
    q.resize(n);
    for (size_t i = 0; i < n; ++i)
      q.set(i, -1, int(i), 0, -1);
    h.sizeOutputs();
    for (size_t i = 0; i < n; ++i)
      h.setDirection(i, dirs[first + i]);
    shade(scene.background, q, [&](size_t i, int32_t handle) {
      radiance[first + i] = backgroundOf(threadClosureArena(), handle);
    });
  }
}

void PathWave::run(const std::vector<int> &pixels, int s0, int s1, float *mean) {
  startPaths(pixels, s0, s1);
  results.resize(paths.size());
  for (int bounce = 0; intersectPaths(); ++bounce) {
    shadeMisses(bounce);
    bool lastBounce = bounce >= r.options.maxBounces;
    for (size_t s = 0; s < queues.size(); ++s) {
      const ShadeQueue &q = queues[s];
      shade(int(s), q, [&](size_t i, int32_t handle) {
        ShadingResult &res = results[q.path[i]];
        res.clear();
        addClosure(threadClosureArena(), handle, {-q.at.d(i), q.at.backfacing[i] != 0}, res,
                   lastBounce);
      });
    }
    scatterAll(bounce);
    traceShadowRays();
    for (size_t s = 0; s < lightQueries.size(); ++s) {
      const ShadeQueue &q = lightQueries[s];
      shade(int(s), q, [&](size_t i, int32_t handle) {
        ShadingResult light;
        addClosure(threadClosureArena(), handle, {-q.at.d(i), q.at.backfacing[i] != 0}, light,
                   true);
        ShadowRay &ray = shadowRays[q.path[i]];
        ray.adds = ray.contrib * light.emission;
      });
    }
    for (size_t k = 0; k < shadowCount; ++k)
      if (shadowRays[k].reached)
        paths[shadowRays[k].path].radiance += shadowRays[k].adds;
  }
  accumulate(mean);
}

/// One path per pixel and sample, from testrender's camera through a
/// tent-filtered point of the pixel (the sampler's first point), its first
/// ray computed in lanes.
void PathWave::startPaths(const std::vector<int> &pixels, int s0, int s1) {
  const RenderOptions &opt = r.options;
  paths.clear();
  draws.resize(pixels.size() * size_t(s1 - s0));
  pathPixels.clear();
  pathSamples.clear();
  rayPaths.clear();
  for (int pixel : pixels)
    for (int s = s0; s < s1; ++s) {
      Path p;
      p.rng = Sampler(pixel % opt.xres, pixel / opt.xres, uint32_t(s), opt.seed);
      draws.set(paths.size(), p.rng.reserve(1), p.rng.sampleIndex());
      rayPaths.push_back(int(paths.size()));
      paths.push_back(p);
      pathPixels.push_back(pixel);
      pathSamples.push_back(s);
    }
  laneKernels().drawPoints(draws, width);
  size_t n = paths.size();
  RayBatch &pr = pathRays;
  pr.resize(n);
  std::fill_n(pr.ox.begin(), n, camera.eye.x), std::fill_n(pr.oy.begin(), n, camera.eye.y);
  std::fill_n(pr.oz.begin(), n, camera.eye.z), std::fill_n(pr.self.begin(), n, -1);
  laneKernels().cameraRays(camera, pathPixels.data(), draws.x.data(), draws.y.data(), n,
                           pr.dx.data(), pr.dy.data(), pr.dz.data(), width);
  // testrender's camera ray differentials: no radius, a spread of about a
  // pixel's angle.
  std::fill_n(pr.radius.begin(), n, 0.0f);
  float pixelArea = camera.invw * camera.invh * length(camera.cx) * length(camera.cy);
  for (size_t i = 0; i < n; ++i) {
    float cosA = dot(camera.dir, Vec3(pr.dx[i], pr.dy[i], pr.dz[i]));
    pr.spread[i] = std::sqrt(pixelArea * cosA) * cosA;
  }
}

/// Intersects every live path: hits queue on their shader, escaped paths
/// on the background. False when no path is alive.
bool PathWave::intersectPaths() {
  // The paths still alive: the last bounce's, less those it ended (every
  // path at the first bounce, which startPaths lists).
  rayPaths.erase(std::remove_if(rayPaths.begin(), rayPaths.end(),
                                [&](int i) { return !paths[size_t(i)].alive; }),
                 rayPaths.end());
  intersectBatch(scene, pathRays, rayPaths, width, hits);
  // Hits queue on their shader's queue, escaped paths on the last (misses).
  const int missQueue = int(queues.size());
  sortIntoQueues(
      rayPaths.size(), itemQueue, queueFill, queues.size() + 1,
      [&](size_t k) {
        Path &p = paths[size_t(rayPaths[k])];
        p.hit = hits[k];
        int shader = p.hit.prim < 0 ? (scene.background >= 0 ? missQueue : -1)
                                    : scene.prims[p.hit.prim].shader;
        p.alive = p.hit.prim >= 0 && shader >= 0;
        return shader;
      },
      [&](size_t s) -> ShadeQueue & { return int(s) == missQueue ? misses : queues[s]; },
      [&](ShadeQueue &q, size_t slot, size_t k) {
        const Hit &hit = paths[size_t(rayPaths[k])].hit;
        if (hit.prim < 0)
          q.set(slot, -1, rayPaths[k], 0, rayPaths[k]);
        else
          q.set(slot, hit.prim, rayPaths[k], hit.t, rayPaths[k]);
      });
  for (ShadeQueue &q : queues)
    laneKernels().hitGeometry(prims, pathRays, q.at, width);
  return !rayPaths.empty();
}

/// Escaped paths see the background: after the first bounce, from the
/// importance table (weighted against the table's own sampling), else from
/// the shader (P and I the ray's direction).
void PathWave::shadeMisses(int bounce) {
  if (scene.background < 0)
    return;
  HitPoints &h = misses.at;
  if (bounce > 0 && map) {
    laneKernels().evalBackground(map->table(), pathRays, h.ray.data(), h.size(),
                                 backgroundDraws, width);
    for (size_t i = 0; i < h.size(); ++i) {
      Path &p = paths[misses.path[i]];
      p.radiance += p.weight * backgroundDraws.value(i) *
                    powerHeuristic<MisMode::WeightWeight>(p.bsdfPdf, backgroundDraws.pdf[i]);
    }
    return;
  }
  h.sizeOutputs();
  for (size_t i = 0; i < h.size(); ++i) {
    // The ray's direction, with its differentials (testrender's
    // dual_direction: the footprint's directions by the spread).
    int ray = h.ray[i];
    Vec3 d(pathRays.dx[ray], pathRays.dy[ray], pathRays.dz[ray]), ex, ey;
    orthoBasis(d, ex, ey);
    h.setDirection(i, {d, ex * pathRays.spread[ray], ey * pathRays.spread[ray]});
  }
  misses.rayType = bounce > 0 ? diffuseRays() : cameraRays();
  shade(scene.background, misses, [&](size_t i, int32_t handle) {
    Path &p = paths[misses.path[i]];
    p.radiance += p.weight * backgroundOf(threadClosureArena(), handle);
  });
}

/// Every shaded hit scatters: its emission (weighted against the light
/// sampling that could have found it), one sampler point, then with it a
/// background sample, a sample of every other light, and the BSDF's sample
/// that continues the path.
void PathWave::scatterAll(int bounce) {
  scattering.clear();
  mixtureOf.clear();
  bool lastBounce = bounce >= r.options.maxBounces;
  bool mayEnd = bounce >= kRouletteDepth;
  int mixtures = 0, mostLobes = 0;
  // The SoA batches below are sized for the most they may hold, filled by
  // index, then cut to what they hold.
  size_t hitCount = 0;
  for (const ShadeQueue &q : queues)
    hitCount += q.size();
  draws.resize(hitCount);
  for (const ShadeQueue &q : queues)
    for (size_t i = 0; i < q.size(); ++i) {
      Path &p = paths[q.path[i]];
      ShadingResult &res = results[q.path[i]];
      float k = 1;
      if (scene.prims[p.hit.prim].isLight)
        k = powerHeuristic<MisMode::WeightEval>(
            p.bsdfPdf, lightPdf(prims, p.hit.prim, q.at.o(i), q.at.p(i)));
      p.radiance += p.weight * k * res.emission;
      if (lastBounce) {
        p.alive = false;
        continue;
      }
      // Lanes pay for a mixture's columns: one lane shares them with none.
      if (width > 1 &&
          llvm::all_of(res.lobes, [](const Lobe &l) { return isCosineLobe(l.model); })) {
        mixtureOf.push_back(mixtures++);
        mostLobes = std::max(mostLobes, int(res.lobes.size()));
      } else {
        res.prepare(-q.at.d(i), p.weight, mayEnd);
        mixtureOf.push_back(-1);
      }
      draws.set(scattering.size(), p.rng.reserve(1), p.rng.sampleIndex());
      scattering.push_back({&q, i});
    }
  draws.resize(scattering.size());
  laneKernels().drawPoints(draws, width);
  cosineMixtures.reset(size_t(mixtures), mostLobes);
  for (size_t s = 0; s < scattering.size(); ++s)
    if (int m = mixtureOf[s]; m >= 0) {
      auto [q, i] = scattering[s];
      cosineMixtures.set(size_t(m), results[q->path[i]].lobes, -q->at.d(i),
                         paths[q->path[i]].weight, mayEnd);
      cosineMixtures.rx[size_t(m)] = draws.x[s], cosineMixtures.ry[size_t(m)] = draws.y[s];
    }
  laneKernels().sampleCosineMixtures(cosineMixtures, width);
  // The background's samples, and the lights' (every path's together).
  if (map)
    laneKernels().sampleBackground(map->table(), draws.x.data(), draws.y.data(),
                                   scattering.size(), backgroundDraws, width);
  lightDraws.resize(scattering.size() * lights.size());
  lightDrawMixtures.resize(lightDraws.size());
  size_t lightCount = 0;
  for (size_t s = 0; s < scattering.size(); ++s) {
    auto [q, i] = scattering[s];
    int self = paths[q->path[i]].hit.prim;
    for (int l : lights)
      if (l != self) {
        lightDrawMixtures[lightCount] = mixtureOf[s];
        lightDraws.set(lightCount++, l, q->at.p(i), draws.x[s], draws.y[s]);
      }
  }
  lightDraws.resize(lightCount);
  laneKernels().sampleLights(prims, lightDraws, width);
  // The lanes' evaluations: toward the background's samples, then the
  // lights', as the loops below take them.
  size_t towardCount = (map ? scattering.size() : 0) + lightCount;
  mixtureEvals.resize(towardCount);
  size_t evalCount = 0;
  if (map)
    for (size_t s = 0; s < scattering.size(); ++s)
      if (mixtureOf[s] >= 0)
        mixtureEvals.set(evalCount++, mixtureOf[s], backgroundDraws.dir(s));
  for (size_t k = 0; k < lightCount; ++k)
    if (lightDrawMixtures[k] >= 0)
      mixtureEvals.set(evalCount++, lightDrawMixtures[k], lightDraws.dir(k));
  mixtureEvals.resize(evalCount);
  laneKernels().evalCosineMixtures(cosineMixtures, mixtureEvals, width);
  // At most one shadow ray toward each sample.
  growTo(towardCount, shadowRays);
  rays.resize(towardCount);
  shadowCount = 0;
  // A path's mixture toward a direction: the lanes' next evaluation (they
  // are taken in the order added), or its ShadingResult's.
  size_t evaluated = 0;
  auto evalMixture = [&](size_t s, Vec3 wo, Vec3 wi) {
    if (mixtureOf[s] < 0) {
      auto [q, i] = scattering[s];
      return results[q->path[i]].eval(wo, wi);
    }
    BsdfSample e;
    e.weight = mixtureEvals.weight(evaluated);
    e.pdf = mixtureEvals.pdf[evaluated++];
    return e;
  };
  if (map)
    for (size_t s = 0; s < scattering.size(); ++s) {
      auto [q, i] = scattering[s];
      Path &p = paths[q->path[i]];
      Vec3 dir = backgroundDraws.dir(s);
      BsdfSample e = evalMixture(s, -q->at.d(i), dir);
      Vec3 contrib = p.weight * e.weight * backgroundDraws.value(s) *
                     powerHeuristic<MisMode::WeightWeight>(backgroundDraws.pdf[s], e.pdf);
      if (contrib.sum() > 0)
        queueShadowRay(*q, i, dir, -1, contrib);
    }
  sampleBsdfs();
  size_t light = 0;
  for (size_t s = 0; s < scattering.size(); ++s) {
    auto [q, i] = scattering[s];
    Path &p = paths[q->path[i]];
    Vec3 wo = -q->at.d(i);
    for (int l : lights) {
      if (l == p.hit.prim)
        continue;
      Vec3 dir = lightDraws.dir(light);
      float pdf = lightDraws.pdf[light++];
      BsdfSample e = evalMixture(s, wo, dir);
      Vec3 contrib = p.weight * e.weight * powerHeuristic<MisMode::EvalWeight>(pdf, e.pdf);
      if (contrib.sum() > 0)
        queueShadowRay(*q, i, dir, l, contrib);
    }
    // The BSDF's sample continues the path (testrender calls every
    // bounce's rays diffuse).
    const BsdfSample &smp = bsdfSamples[s];
    p.weight *= smp.weight;
    p.bsdfPdf = smp.pdf;
    p.rayType = diffuseRays();
    if (!(p.weight.x > 0) && !(p.weight.y > 0) && !(p.weight.z > 0)) {
      p.alive = false; // all zero, or NaN
      continue;
    }
    int pathIndex = q->path[i];
    Vec3 at = q->at.p(i);
    pathRays.ox[pathIndex] = at.x, pathRays.oy[pathIndex] = at.y, pathRays.oz[pathIndex] = at.z;
    pathRays.dx[pathIndex] = smp.wi.x, pathRays.dy[pathIndex] = smp.wi.y;
    pathRays.dz[pathIndex] = smp.wi.z;
    pathRays.self[pathIndex] = p.hit.prim;
    // The footprint grows with the distance, and spreads at least as much
    // as the lobe is rough (testrender's rule).
    pathRays.radius[pathIndex] = q->at.radius[i];
    pathRays.spread[pathIndex] = std::max(pathRays.spread[pathIndex], smp.roughness);
  }
  assert(evaluated == mixtureEvals.size() && "every lane evaluation taken, in order");
  rays.resize(shadowCount);
}

/// Each scattering path's BSDF sample (with the bounce's sampler point):
/// mixtures of cosine lobes alone were sampled in lanes (scatterAll); in
/// the others the mixture picks a lobe, cosine lobes are sampled in lanes,
/// the others one at a time.
void PathWave::sampleBsdfs() {
  cosineDraws.clear();
  cosineOwners.clear();
  bsdfSamples.assign(scattering.size(), BsdfSample());
  for (size_t s = 0; s < scattering.size(); ++s) {
    if (mixtureOf[s] >= 0) {
      bsdfSamples[s] = cosineMixtures.result(size_t(mixtureOf[s]));
      continue;
    }
    auto [q, i] = scattering[s];
    const ShadingResult &res = results[q->path[i]];
    Vec3 wo = -q->at.d(i);
    float rx = draws.x[s];
    int lobe = res.pick(rx);
    if (lobe < 0)
      continue;
    const Lobe &l = res.lobes[size_t(lobe)];
    if (isCosineLobe(l.model)) {
      cosineDraws.push(l, wo, rx, draws.y[s]);
      cosineOwners.push_back({s, size_t(lobe)});
    } else {
      bsdfSamples[s] =
          res.mixSample(size_t(lobe), sampleLobe(l, wo, rx, draws.y[s], draws.z[s]), wo);
    }
  }
  laneKernels().sampleCosineLobes(cosineDraws, width);
  for (size_t k = 0; k < cosineOwners.size(); ++k) {
    auto [s, lobe] = cosineOwners[k];
    auto [q, i] = scattering[s];
    bsdfSamples[s] = results[q->path[i]].mixSample(lobe, cosineDraws.result(k), -q->at.d(i));
  }
}

/// The bounce's shadow rays, traced together: one toward the background
/// that escapes adds its contribution; one that reaches its light queues a
/// query for the light's shader (the query's `path` is the shadow ray).
void PathWave::traceShadowRays() {
  intersectBatch(scene, rays, width, hits);
  sortIntoQueues(
      shadowCount, itemQueue, queueFill, lightQueries.size(),
      [&](size_t k) {
        ShadowRay &s = shadowRays[k];
        if (s.light < 0) {
          s.reached = hits[k].prim < 0;
          s.adds = s.contrib;
          return -1;
        }
        s.reached = hits[k].prim == s.light;
        return s.reached ? scene.prims[s.light].shader : -1;
      },
      [&](size_t s) -> ShadeQueue & { return lightQueries[s]; },
      [&](ShadeQueue &q, size_t slot, size_t k) {
        q.set(slot, shadowRays[k].light, int(k), hits[k].t, int(k));
      });
  for (ShadeQueue &q : lightQueries)
    laneKernels().hitGeometry(prims, rays, q.at, width);
}

/// Mixes each path's radiance into its pixel, a sample at a time in order
/// (testrender's running mean: mean += (c - mean) / (s + 1) as a lerp).
void PathWave::accumulate(float *mean) {
  const RenderOptions &opt = r.options;
  for (size_t i = 0; i < paths.size(); ++i) {
    Vec3 c = paths[i].radiance;
    if (!(std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z)))
      c = Vec3(); // one bad sample must not turn a pixel into NaN
    float t = 1.0f / float(pathSamples[i] + 1);
    float *m = &mean[3 * opt.windowIndex(pathPixels[i])];
    m[0] = fast::lerp(m[0], c.x, t);
    m[1] = fast::lerp(m[1], c.y, t);
    m[2] = fast::lerp(m[2], c.z, t);
  }
}

//===----------------------------------------------------------------------===//
// Renderer
//===----------------------------------------------------------------------===//

bool Renderer::compileShaders(const std::vector<std::string> &searchPaths,
                              const CompileOptions &sceneOptions, llvm::raw_ostream &errs,
                              Stats *stats) {
  // raytype() reads each point's ray types, which the paths set.
  CompileOptions compile = sceneOptions;
  compile.rayType = "";
  kernels.clear();
  for (const SceneGroup &group : scene.shaders) {
    // Each layer's shader is found on the search paths: NAME.osl, or a
    // source declaring shader NAME.
    std::vector<std::string> found;
    for (const ShaderInstance &inst : group.layers) {
      std::string path = findShaderSource(inst.shader, searchPaths);
      if (path.empty()) {
        errs << "error: shader '" << inst.shader << "' (scene line " << group.line << "): no "
             << inst.shader << ".osl, nor a source declaring it, in";
        for (const std::string &dir : searchPaths)
          errs << " " << dir;
        errs << " (use --path DIR)\n";
        return false;
      }
      found.push_back(path);
    }
    Kernel k;
    if (group.layers.size() == 1 && group.connections.empty()) {
      auto buffer = llvm::MemoryBuffer::getFile(found[0]);
      if (!buffer) {
        errs << "error: cannot read " << found[0] << "\n";
        return false;
      }
      CompileOptions opts = compile;
      opts.params = group.layers[0].params;
      ShaderCompiler compiler(opts, errs, stats);
      k.shader = compiler.compile((*buffer)->getBuffer(), found[0]);
    } else {
      // Several layers: one kernel for the group, the last layer its root.
      ShaderGroup shaderGroup;
      std::string error;
      for (size_t i = 0; i < group.layers.size() && error.empty(); ++i) {
        for (const ParamOverride &p : group.layers[i].params)
          shaderGroup.param(p.name, p.value);
        shaderGroup.shader(found[i], group.layers[i].layer, error);
      }
      for (const GroupConnection &c : group.connections)
        shaderGroup.connect(c);
      if (!error.empty() || !shaderGroup.validate(error)) {
        errs << "error: shader group (scene line " << group.line << "): " << error << "\n";
        return false;
      }
      ShaderCompiler compiler(compile, errs, stats);
      k.shader = compiler.compileGroup(shaderGroup);
    }
    if (!k.shader)
      return false;
    int row = 0;
    for (const OutputSpec &o : k.shader->outputs) {
      if (o.closure && o.name == "Ci")
        k.ciRow = row;
      row += o.channels;
    }
    k.outputRows = row;
    laneWidth = k.shader->width;
    kernels.push_back(std::move(k));
  }
  return true;
}

void Renderer::render(std::vector<float> &rgb, RenderStats &stats) {
  const RenderOptions &opt = options;
  int spp = opt.aa * opt.aa;
  int x0 = opt.cropX0, y0 = opt.cropY0;
  int x1 = x0 + opt.windowWidth(), y1 = y0 + opt.windowHeight();
  rgb.assign(size_t(opt.windowWidth()) * opt.windowHeight() * 3, 0.0f);
  int tilesX = (opt.xres + kTileSize - 1) / kTileSize;
  int tilesY = (opt.yres + kTileSize - 1) / kTileSize;
  int tiles = tilesX * tilesY;
  // Samples per wave: a fixed split of each pixel's samples (the same at
  // every width and thread count, so sums add up in the same order).
  int samplesPerWave = std::max(1, std::min(spp, kWavePaths / (kTileSize * kTileSize)));

  ThreadPool pool(opt.threads);
  std::vector<std::unique_ptr<PathWave>> waves;
  for (int i = 0; i < pool.size(); ++i)
    waves.push_back(std::make_unique<PathWave>(*this));
  // The background's importance table, shaded before the paths start.
  BackgroundMap map;
  if (scene.background >= 0 && scene.backgroundResolution > 0)
    map.prepare(scene.backgroundResolution,
                [&](const std::vector<Dual3> &dirs, std::vector<Vec3> &radiance) {
                  waves[0]->shadeBackground(dirs, radiance);
                });
  for (auto &w : waves)
    w->useBackgroundMap(&map);
  Progress progress(opt.progress, long(tiles), "rendering");
  auto start = std::chrono::steady_clock::now();
  pool.parallelForWithWorker(tiles, [&](int tile, int worker) {
    int tx = tile % tilesX, ty = tile / tilesX;
    std::vector<int> pixels;
    // The whole image's tiles, each cut to the window.
    for (int y = std::max(y0, ty * kTileSize); y < std::min(y1, (ty + 1) * kTileSize); ++y)
      for (int x = std::max(x0, tx * kTileSize); x < std::min(x1, (tx + 1) * kTileSize); ++x)
        pixels.push_back(y * opt.xres + x);
    for (int s = 0; s < spp && !pixels.empty(); s += samplesPerWave)
      waves[worker]->run(pixels, s, std::min(spp, s + samplesPerWave), rgb.data());
    progress.add(1);
  });
  progress.finish();
  stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  stats.paths = long(opt.windowWidth()) * opt.windowHeight() * spp;
  for (auto &w : waves) {
    stats.batches += w->batches;
    stats.shadedPoints += w->shaded;
    stats.shadingSeconds += w->shadingSeconds;
  }
  stats.activeLaneFraction =
      stats.batches ? double(stats.shadedPoints) / (double(stats.batches) * laneWidth) : 0;
}

} // namespace osl::render
