//===- Integrator.cpp - Wavefront path tracing with batched shading -------===//
#include "LaneKernels.h"
#include "OslAbi/GlobalsLayout.h"
#include "OslFrontend/Frontend.h"
#include "OslRender/Bsdf.h"
#include "OslRender/Geometry.h"
#include "OslRender/Renderer.h"
#include "OslRender/Sampler.h"
#include "OslRuntime/Closure.h"
#include "OslRuntime/Progress.h"
#include "OslRuntime/ThreadPool.h"

#include "llvm/ADT/STLExtras.h"
#include "llvm/Support/FileSystem.h"
#include "llvm/Support/MemoryBuffer.h"
#include "llvm/Support/Path.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>

namespace osl::render {

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kPi = 3.14159265358979f;
/// Paths per wave: enough to fill batches per shader, small enough to stay in cache.
constexpr int kWavePaths = 1024;
constexpr int kTileSize = 8;
constexpr int kRouletteBounce = 5;

float powerHeuristic(float a, float b) {
  if (std::isinf(a))
    return 1;
  float a2 = a * a, b2 = b * b;
  return a2 + b2 > 0 ? a2 / (a2 + b2) : 0;
}

struct Path {
  Vec3 throughput{1, 1, 1}, radiance;
  float bsdfPdf = kInf; // of the last bounce; infinite for the camera and specular lobes
  /// What raytype() answers for the points the ray reaches (kRayTypes bits).
  int32_t rayType = rayTypeBit("camera");
  bool alive = true;
  Hit hit;
  Sampler rng;
};

/// Points to shade with one shader: where each is (its geometry computed
/// in lanes; `at.ray` indexes the wave's pathRays for hits and misses, its
/// shadow rays for light queries), the path it belongs to, and for light
/// queries what the light's emission is multiplied by.
struct ShadeQueue {
  HitPoints at;
  std::vector<int> path;
  std::vector<Vec3> contrib;
  /// The ray type every point answers (-1: each its path's own).
  int32_t rayType = -1;
  /// Escaped rays: P and I are the direction, and there is no surface.
  bool background = false;
  void clear() {
    at.clear();
    path.clear();
    contrib.clear();
  }
  size_t size() const { return path.size(); }
};

} // namespace

/// One worker's paths and buffers, reused from wave to wave.
class PathWave {
public:
  PathWave(const Renderer &r)
      : r(r), scene(r.scene), prims(r.scene), width(r.laneWidth),
        globals(size_t(kGlobalRows) * r.laneWidth), queues(scene.shaders.size()),
        lightQueries(scene.shaders.size()) {
    for (int l = 0; l < int(scene.prims.size()); ++l)
      if (scene.prims[l].isLight && scene.prims[l].shader >= 0)
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
    camera.eye = cam.eye;
    camera.dir = normalize(cam.lookAt - cam.eye);
    float k = std::tan(cam.fovDegrees * kPi / 360);
    camera.right = normalize(cross(camera.dir, cam.up)) * (float(opt.xres) * k / float(opt.yres));
    camera.up = normalize(cross(camera.right, camera.dir)) * k;
    camera.xres = opt.xres;
    camera.yres = opt.yres;
  }

  /// Traces samples [s0, s1) of every pixel in `pixels`, adding their
  /// radiance to `sum` (3 floats per pixel of the image).
  void run(const std::vector<int> &pixels, int s0, int s1, float *sum);

  long batches = 0, shaded = 0;
  double shadingSeconds = 0;

private:
  void startPaths(const std::vector<int> &pixels, int s0, int s1);
  bool intersectPaths();
  void shadeMisses();
  void scatterAll(int bounce);
  bool startScatter(const ShadeQueue &q, size_t i);
  void scatter(const ShadeQueue &q, size_t i, int bounce, size_t firstDraw, size_t firstLight);
  void continueScatter(const ShadeQueue &q, size_t i, int bounce, const BsdfSample &smp);
  void sampleLights(const ShadeQueue &q, size_t i, Vec3 wo, size_t firstLight);
  /// The lights a path at primitive `prim` samples (every light but itself).
  int lightsSampledFrom(int prim) const {
    return int(lights.size()) - int(llvm::is_contained(lights, prim));
  }
  void traceShadowRays();
  void accumulate(float *sum);
  /// Shades `q`'s points with `shader`, `width` at a time, and calls
  /// use(index in q, closure handle) for each.
  template <typename Use> void shade(int shader, const ShadeQueue &q, Use use);
  void copyRow(int row, const std::vector<float> &from, size_t start, int n) {
    float *to = &globals[size_t(row) * width];
    if (n == 1) // width 1: a store, not a call of memmove per row and point
      *to = from[start];
    else
      std::copy_n(from.begin() + start, n, to);
  }
  void copyTriple(int row, const std::vector<float> &x, const std::vector<float> &y,
                  const std::vector<float> &z, size_t start, int n) {
    copyRow(row, x, start, n), copyRow(row + 1, y, start, n), copyRow(row + 2, z, start, n);
  }
  /// The shading normal and side a closure is interpreted with.
  static ShadingPoint pointOf(const ShadeQueue &q, size_t i) {
    return {-q.at.d(i), q.at.n(i), q.at.backfacing[i] != 0};
  }

  const Renderer &r;
  const Scene &scene;
  PrimTable prims;
  int width;
  CameraSetup camera;
  std::vector<float> globals, outputs;
  std::vector<Path> paths;
  /// Each path's next ray (origin, direction, the primitive it leaves).
  RayBatch pathRays;
  std::vector<ShadingResult> results;
  std::vector<ShadeQueue> queues, lightQueries;
  /// Escaped paths: primitive -1, never given to hitGeometry (shadeMisses
  /// copies their directions).
  ShadeQueue misses;
  /// The lights next-event estimation samples, in the scene's order.
  std::vector<int> lights;
  /// Random points drawn a batch at a time (every path's numbers are its
  /// own, whatever the batch): a bounce's scattering paths with the first
  /// of their points, and the paths whose roulette draws.
  PointDraws draws;
  struct Scattering {
    const ShadeQueue *queue;
    size_t index, firstDraw, firstLight;
  };
  /// Each scattering path's light samples, in its lights' order.
  LightDraws lightDraws;
  std::vector<Scattering> scattering;
  /// The bounce's BSDF samples of cosine lobes, per model: the lanes' input
  /// and output, and which path's point and lobe each is.
  static constexpr size_t kCosineModels = size_t(CosineModel::EnergyOrenNayar) + 1;
  struct CosinePick {
    const ShadeQueue *queue;
    size_t index;
    ShadingResult::Pick picked;
    bool alone; // the only lobe the mixture evaluates: the lanes finish it
  };
  std::array<CosineDraws, kCosineModels> cosineDraws;
  std::array<std::vector<CosinePick>, kCosineModels> cosinePicks;
  std::vector<std::pair<int, float>> roulette;
  /// The bounce's shadow rays, traced together a batch of `width` lanes at
  /// a time.
  RayBatch rays;
  std::vector<Hit> hits;
  std::vector<int> rayPaths;
  /// Each path's pixel (for the camera's lanes and the image).
  std::vector<int> pathPixels;
  /// A light sample whose shadow ray is traced with the others: what its
  /// light query gets if the ray reaches the light.
  struct ShadowRay {
    int path, light;
    Vec3 contrib;
  };
  std::vector<ShadowRay> shadowRays;
  /// Rows of the globals the renderer sets.
  const int rowP = findGlobal("P")->row, rowI = findGlobal("I")->row, rowN = findGlobal("N")->row,
            rowNg = findGlobal("Ng")->row, rowDPdu = findGlobal("dPdu")->row,
            rowDPdv = findGlobal("dPdv")->row, rowU = findGlobal("u")->row,
            rowV = findGlobal("v")->row, rowBackfacing = findGlobal("backfacing")->row,
            rowRayType = findGlobal("raytype")->row,
            rowSurfaceArea = findGlobal("surfacearea")->row;
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
    if (q.background) {
      copyTriple(rowP, h.dx, h.dy, h.dz, start, n);
    } else {
      copyTriple(rowP, h.px, h.py, h.pz, start, n);
      copyTriple(rowN, h.nx, h.ny, h.nz, start, n);
      copyTriple(rowNg, h.nx, h.ny, h.nz, start, n);
      copyTriple(rowDPdu, h.dPdux, h.dPduy, h.dPduz, start, n);
      copyTriple(rowDPdv, h.dPdvx, h.dPdvy, h.dPdvz, start, n);
      copyRow(rowU, h.u, start, n), copyRow(rowV, h.v, start, n);
      copyRow(rowBackfacing, h.backfacing, start, n);
      copyRow(rowSurfaceArea, h.area, start, n);
    }
    copyTriple(rowI, h.dx, h.dy, h.dz, start, n);
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

void PathWave::run(const std::vector<int> &pixels, int s0, int s1, float *sum) {
  startPaths(pixels, s0, s1);
  results.resize(paths.size());
  for (int bounce = 0; intersectPaths(); ++bounce) {
    shadeMisses();
    for (size_t s = 0; s < queues.size(); ++s) {
      const ShadeQueue &q = queues[s];
      shade(int(s), q, [&](size_t i, int32_t handle) {
        ShadingResult &res = results[q.path[i]];
        res.clear();
        addClosure(threadClosureArena(), handle, pointOf(q, i), res);
      });
    }
    scatterAll(bounce);
    traceShadowRays();
    for (size_t s = 0; s < lightQueries.size(); ++s) {
      const ShadeQueue &q = lightQueries[s];
      shade(int(s), q, [&](size_t i, int32_t handle) {
        ShadingResult light;
        addClosure(threadClosureArena(), handle, pointOf(q, i), light);
        paths[q.path[i]].radiance += q.contrib[i] * light.emission;
      });
    }
  }
  accumulate(sum);
}

/// One path per pixel and sample, from testrender's camera, its first ray
/// computed in lanes.
void PathWave::startPaths(const std::vector<int> &pixels, int s0, int s1) {
  const RenderOptions &opt = r.options;
  paths.clear();
  draws.clear();
  pathPixels.clear();
  for (int pixel : pixels)
    for (int s = s0; s < s1; ++s) {
      Path p;
      p.rng = Sampler(uint32_t(pixel), uint32_t(s), opt.seed);
      draws.push(p.rng.pathKey(), p.rng.sampleIndex(), p.rng.reserve(1));
      paths.push_back(p);
      pathPixels.push_back(pixel);
    }
  laneKernels().drawPoints(draws, width);
  size_t n = paths.size();
  RayBatch &pr = pathRays;
  pr.ox.assign(n, camera.eye.x), pr.oy.assign(n, camera.eye.y), pr.oz.assign(n, camera.eye.z);
  pr.dx.resize(n), pr.dy.resize(n), pr.dz.resize(n);
  pr.self.assign(n, -1);
  laneKernels().cameraRays(camera, pathPixels.data(), draws.x.data(), draws.y.data(), n,
                           pr.dx.data(), pr.dy.data(), pr.dz.data(), width);
}

/// Intersects every live path: hits queue on their shader, escaped paths
/// on the background. False when no path is alive.
bool PathWave::intersectPaths() {
  for (ShadeQueue &q : queues)
    q.clear();
  misses.clear();
  rayPaths.clear();
  for (int i = 0; i < int(paths.size()); ++i)
    if (paths[i].alive)
      rayPaths.push_back(i);
  intersectBatch(scene, pathRays, rayPaths, width, hits);
  for (size_t k = 0; k < rayPaths.size(); ++k) {
    int i = rayPaths[k];
    Path &p = paths[i];
    p.hit = hits[k];
    if (p.hit.prim < 0) {
      p.alive = false;
      if (scene.background >= 0) {
        misses.at.push(-1, i, 0);
        misses.path.push_back(i);
      }
      continue;
    }
    int shader = scene.prims[p.hit.prim].shader;
    if (shader < 0) {
      p.alive = false;
      continue;
    }
    queues[shader].at.push(p.hit.prim, i, p.hit.t);
    queues[shader].path.push_back(i);
  }
  for (ShadeQueue &q : queues)
    laneKernels().hitGeometry(prims, pathRays, q.at, width);
  return !rayPaths.empty();
}

/// Escaped paths see the background (not importance sampled, so the
/// BSDF's sample takes it whole): its P and I are the ray's direction.
void PathWave::shadeMisses() {
  if (scene.background < 0)
    return;
  HitPoints &h = misses.at;
  for (std::vector<float> *v : {&h.dx, &h.dy, &h.dz})
    v->resize(h.size());
  for (size_t i = 0; i < h.size(); ++i) {
    int ray = h.ray[i];
    h.dx[i] = pathRays.dx[ray], h.dy[i] = pathRays.dy[ray], h.dz[i] = pathRays.dz[ray];
  }
  shade(scene.background, misses, [&](size_t i, int32_t handle) {
    ShadingResult bg;
    addClosure(threadClosureArena(), handle, {-h.d(i), Vec3(), false}, bg);
    Path &p = paths[misses.path[i]];
    p.radiance += p.throughput * bg.background;
  });
}

/// Every shaded hit scatters: its emission, a light sample per light
/// (queued for the light's shader), then the BSDF's sample continues the
/// path. Each path draws its random numbers in this order, a batch of
/// paths at a time.
void PathWave::scatterAll(int bounce) {
  for (ShadeQueue &q : lightQueries)
    q.clear();
  shadowRays.clear();
  rays.clear();
  scattering.clear();
  draws.clear();
  for (const ShadeQueue &q : queues)
    for (size_t i = 0; i < q.size(); ++i)
      if (startScatter(q, i)) {
        // The BSDF's point, then one per light.
        Path &p = paths[q.path[i]];
        uint32_t n = 1 + lightsSampledFrom(p.hit.prim);
        scattering.push_back({&q, i, draws.size(), 0});
        for (uint32_t call = p.rng.reserve(n), k = 0; k < n; ++k)
          draws.push(p.rng.pathKey(), p.rng.sampleIndex(), call + k);
      }
  laneKernels().drawPoints(draws, width);
  // The lights' samples, every path's together: each light with a point of
  // its own (after the BSDF's).
  lightDraws.clear();
  for (Scattering &s : scattering) {
    s.firstLight = lightDraws.size();
    Vec3 at = s.queue->at.p(s.index);
    int self = paths[s.queue->path[s.index]].hit.prim;
    size_t draw = s.firstDraw + 1;
    for (int l : lights)
      if (l != self) {
        lightDraws.push(l, at, draws.x[draw], draws.y[draw]);
        ++draw;
      }
  }
  laneKernels().sampleLights(prims, lightDraws, width);
  roulette.clear();
  for (CosineDraws &d : cosineDraws)
    d.clear();
  for (auto &picks : cosinePicks)
    picks.clear();
  for (const Scattering &s : scattering)
    scatter(*s.queue, s.index, bounce, s.firstDraw, s.firstLight);
  // The cosine lobes' samples, a model at a time.
  for (size_t m = 0; m < kCosineModels; ++m) {
    if (cosinePicks[m].empty())
      continue;
    laneKernels().sampleCosineLobes(CosineModel(m), cosineDraws[m], width);
    for (size_t k = 0; k < cosinePicks[m].size(); ++k) {
      const CosinePick &c = cosinePicks[m][k];
      if (c.alone) {
        continueScatter(*c.queue, c.index, bounce, cosineDraws[m].alone(k));
        continue;
      }
      // Other lobes are evaluated toward the sample too.
      CosineSample lanes = cosineDraws[m].sample(k);
      BsdfSample smp = sampledDirection(lanes.wi, {lanes.eval.value, lanes.eval.pdf});
      const ShadingResult &res = results[c.queue->path[c.index]];
      continueScatter(*c.queue, c.index, bounce,
                      res.finish(-c.queue->at.d(c.index), c.picked, smp));
    }
  }
  // Russian roulette, past kRouletteBounce: the survivors are scaled up.
  PointDraws &survival = draws;
  survival.clear();
  for (auto [path, survive] : roulette) {
    Path &p = paths[path];
    survival.push(p.rng.pathKey(), p.rng.sampleIndex(), p.rng.reserve(1));
  }
  laneKernels().drawPoints(survival, width);
  for (size_t k = 0; k < roulette.size(); ++k) {
    auto [path, survive] = roulette[k];
    Path &p = paths[path];
    if (survival.x[k] >= survive)
      p.alive = false;
    else
      p.throughput = p.throughput / survive;
  }
}

/// A hit's emission (weighted against the light sampling that could have
/// found it) and its lobes' pick probabilities: false when nothing
/// scatters, and the path ends.
bool PathWave::startScatter(const ShadeQueue &q, size_t i) {
  int pathIndex = q.path[i];
  Path &p = paths[pathIndex];
  ShadingResult &res = results[pathIndex];
  float k = 1;
  if (scene.prims[p.hit.prim].isLight && !std::isinf(p.bsdfPdf))
    k = powerHeuristic(p.bsdfPdf, lightPdf(prims, p.hit.prim, q.at.o(i), q.at.p(i)));
  p.radiance += p.throughput * res.emission * k;
  if (!res.prepare(-q.at.d(i))) {
    p.alive = false;
    return false;
  }
  return true;
}

/// The lights' samples (from `firstLight` in lightDraws) and the BSDF's
/// (with the path's point `firstDraw`).
void PathWave::scatter(const ShadeQueue &q, size_t i, int bounce, size_t firstDraw,
                       size_t firstLight) {
  int pathIndex = q.path[i];
  Path &p = paths[pathIndex];
  ShadingResult &res = results[pathIndex];
  Vec3 wo = -q.at.d(i);
  Vec3 bsdfRandom(draws.x[firstDraw], draws.y[firstDraw], draws.z[firstDraw]);
  sampleLights(q, i, wo, firstLight);
  // The last bounce still samples the lights (as testrender's max_bounces
  // does) but traces no further.
  if (bounce >= r.options.maxBounces) {
    p.alive = false;
    return;
  }
  // A cosine lobe is sampled with the bounce's others of its model, in
  // lanes (continueScatter follows); any other now.
  ShadingResult::Pick picked = res.pick(bsdfRandom.z);
  if (picked.lobe)
    if (std::optional<CosineModel> m = cosineModelOf(*picked.lobe)) {
      cosineDraws[size_t(*m)].push(cosineLobeOf(*picked.lobe), picked.lobe->weight,
                                   picked.lobe->pick, wo, bsdfRandom.x, bsdfRandom.y);
      cosinePicks[size_t(*m)].push_back({&q, i, picked, res.evaluatedLobes() == 1});
      return;
    }
  BsdfSample smp = picked.lobe ? res.finish(wo, picked,
                                            sampleLobe(*picked.lobe, wo, bsdfRandom.x,
                                                       bsdfRandom.y, picked.rz))
                               : BsdfSample();
  continueScatter(q, i, bounce, smp);
}

/// A scattering path's BSDF sample `smp`: its throughput, next ray and ray
/// type; the path ends where nothing goes on.
void PathWave::continueScatter(const ShadeQueue &q, size_t i, int bounce, const BsdfSample &smp) {
  int pathIndex = q.path[i];
  Path &p = paths[pathIndex];
  Vec3 wo = -q.at.d(i), at = q.at.p(i), ng = q.at.n(i);
  p.throughput *= smp.weight;
  p.bsdfPdf = smp.pdf;
  pathRays.ox[pathIndex] = at.x, pathRays.oy[pathIndex] = at.y, pathRays.oz[pathIndex] = at.z;
  pathRays.dx[pathIndex] = smp.wi.x, pathRays.dy[pathIndex] = smp.wi.y;
  pathRays.dz[pathIndex] = smp.wi.z;
  pathRays.self[pathIndex] = p.hit.prim;
  // The next ray: diffuse or glossy (sharp lobes are glossy), reflected to
  // the side the light left by or refracted through.
  bool reflected = dot(smp.wi, ng) * dot(wo, ng) > 0;
  p.rayType = rayTypeBit(smp.diffuse ? "diffuse" : "glossy") |
              rayTypeBit(reflected ? "reflection" : "refraction");
  if (!(p.throughput.x > 0) && !(p.throughput.y > 0) && !(p.throughput.z > 0)) {
    p.alive = false;
    return;
  }
  if (bounce + 1 >= kRouletteBounce)
    roulette.push_back({pathIndex, std::min(1.0f, p.throughput.max())});
}

/// Next-event estimation: one sample of each light the hit point sees,
/// weighted against the BSDF's pdf; its shadow ray is traced with the
/// bounce's others.
void PathWave::sampleLights(const ShadeQueue &q, size_t i, Vec3 wo, size_t firstLight) {
  int pathIndex = q.path[i];
  Path &p = paths[pathIndex];
  ShadingResult &res = results[pathIndex];
  Vec3 at = q.at.p(i);
  size_t end = firstLight + size_t(lightsSampledFrom(p.hit.prim));
  for (size_t k = firstLight; k < end; ++k) {
    float pdf = lightDraws.pdf[k];
    if (!(pdf > 0))
      continue;
    Vec3 dir = lightDraws.dir(k);
    BsdfEval e = res.eval(wo, dir);
    Vec3 contrib = p.throughput * e.value * (powerHeuristic(pdf, e.pdf) / pdf);
    if (!(contrib.sum() > 0))
      continue;
    shadowRays.push_back({pathIndex, lightDraws.light[k], contrib});
    rays.push(at, dir, p.hit.prim);
  }
}

/// The bounce's shadow rays, traced together: each that reaches its light
/// queues a query for the light's shader, in the order they were sampled
/// (a path adds its lights' radiance in that order).
void PathWave::traceShadowRays() {
  intersectBatch(scene, rays, width, hits);
  for (size_t k = 0; k < shadowRays.size(); ++k) {
    const ShadowRay &s = shadowRays[k];
    if (hits[k].prim != s.light)
      continue;
    ShadeQueue &q = lightQueries[scene.prims[s.light].shader];
    q.at.push(s.light, int(k), hits[k].t);
    q.path.push_back(s.path);
    q.contrib.push_back(s.contrib);
  }
  for (ShadeQueue &q : lightQueries)
    laneKernels().hitGeometry(prims, rays, q.at, width);
}

/// Adds each path's radiance to its pixel.
void PathWave::accumulate(float *sum) {
  const RenderOptions &opt = r.options;
  for (size_t i = 0; i < paths.size(); ++i) {
    Vec3 c = paths[i].radiance;
    if (!(std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z)))
      continue; // one bad sample must not turn a pixel into NaN
    size_t at = 3 * opt.windowIndex(pathPixels[i]);
    sum[at] += c.x;
    sum[at + 1] += c.y;
    sum[at + 2] += c.z;
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
  for (float &v : rgb)
    v /= float(spp);
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
