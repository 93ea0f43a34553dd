//===- LaneKernels.h - The renderer's SIMD loops, per instruction set -----===//
//
// Loops over W lanes (W the shading width: 1, 4, 8 or 16) in which every
// lane computes what one ray or path computes alone, in the same order.
// Each is compiled for plain x86-64, AVX2 and AVX-512 (the render library
// is built with -ffp-contract=off, so no instruction set fuses a multiply
// and add another would round twice) and the widest the CPU runs is chosen
// once: results are the same at every width and on every machine.
//
//===----------------------------------------------------------------------===//
#ifndef OSLRENDER_LANEKERNELS_H
#define OSLRENDER_LANEKERNELS_H

#include "BackgroundMap.h"
#include "Dual.h"
#include "OslRender/Bsdf.h"
#include "OslRender/Geometry.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace osl::render {

/// Sizes each column for at least n lanes, never shrinking it: a batch
/// whose count falls and rises from bounce to bounce keeps its storage, and
/// zero-fills only rows it never had (a resize down and up again fills the
/// rows anew each time).
template <typename... Columns> void growTo(size_t n, Columns &...columns) {
  ((columns.size() < n ? columns.resize(n) : void()), ...);
}

/// Sampler points to draw, as structure of arrays: lane i gets
/// samplerPoint(seed[i], index[i]) into x, y, z (Sampler::reserve gives a
/// path's seed, Sampler::sampleIndex its index).
struct PointDraws {
  std::vector<uint32_t> seed, index;
  std::vector<float> x, y, z;
  size_t count = 0;
  void clear() { resize(0); }
  /// Room for n draws, which set() fills by index (a push per draw cost
  /// more than the draw). Columns only grow (growTo): size() is the count.
  void resize(size_t n) {
    growTo(n, seed, index);
    count = n;
  }
  void set(size_t i, uint32_t s, uint32_t k) { seed[i] = s, index[i] = k; }
  void push(uint32_t s, uint32_t k) {
    resize(size() + 1);
    set(size() - 1, s, k);
  }
  size_t size() const { return count; }
};

/// A quad's unit normal and its edges' inverse squared lengths, as
/// testrender keeps them.
struct QuadFrame {
  Vec3 n;
  float eu = 1, ev = 1;
  QuadFrame() = default;
  explicit QuadFrame(const Primitive &q)
      : n(normalize(cross(q.edgeX, q.edgeY))), eu(1 / dot(q.edgeX, q.edgeX)),
        ev(1 / dot(q.edgeY, q.edgeY)) {}
};

/// The scene's primitives as structure of arrays, for lanes that each hit
/// another primitive.
struct PrimTable {
  std::vector<int> kind;                     // Primitive::Kind
  std::vector<float> cx, cy, cz, radius, r2; // spheres
  std::vector<float> qx, qy, qz;             // quads: corner,
  std::vector<float> ex, ey, ez, fx, fy, fz; // edges (x and y),
  std::vector<float> nx, ny, nz, eu, ev;     // QuadFrame
  std::vector<float> area;                   // what surfacearea() answers
  explicit PrimTable(const Scene &scene);
};

/// The pdf the renderer's light sampling (sampleLights) gives the direction
/// from `x` that hits light `k` at `p` (for the MIS weight of a hit).
float lightPdf(const PrimTable &prims, int k, Vec3 x, Vec3 p);

/// Where rays hit, as structure of arrays: each lane's primitive, ray (an
/// index into a RayBatch) and distance in; the ray's origin and direction,
/// and the globals a shader sees there, out. The normal faces the ray, as
/// testrender's does, and backfacing says it was turned.
struct HitPoints {
  std::vector<int> prim, ray;
  std::vector<float> t;
  size_t count = 0;
  std::vector<float> ox, oy, oz, dx, dy, dz;
  std::vector<float> px, py, pz, nx, ny, nz, dPdux, dPduy, dPduz, dPdvx, dPdvy, dPdvz;
  std::vector<float> u, v, backfacing, area;
  /// testrender's ray differentials: of P, I, u and v; whether dPdx x dPdy
  /// turns against N; the footprint's radius at the hit.
  std::vector<float> dPdxX, dPdxY, dPdxZ, dPdyX, dPdyY, dPdyZ;
  std::vector<float> dIdxX, dIdxY, dIdxZ, dIdyX, dIdyY, dIdyZ;
  std::vector<float> dudx, dudy, dvdx, dvdy, flip, radius;
  /// Forgets the lanes (the outputs stay stale until hitGeometry runs, and
  /// keep their storage: sizeOutputs only grows them, since zeroing what
  /// hitGeometry overwrites cost as much as hitGeometry).
  void clear() { resize(0); }
  /// Room for n lanes' inputs, which set() fills by index (columns only
  /// grow: size() is the count).
  void resize(size_t n) {
    growTo(n, prim, ray, t);
    count = n;
  }
  void set(size_t i, int k, int r, float distance) { prim[i] = k, ray[i] = r, t[i] = distance; }
  void push(int k, int r, float distance) {
    resize(size() + 1);
    set(size() - 1, k, r, distance);
  }
  size_t size() const { return count; }
  /// Makes room in the outputs for every lane.
  void sizeOutputs();
  Vec3 o(size_t i) const { return {ox[i], oy[i], oz[i]}; }
  Vec3 d(size_t i) const { return {dx[i], dy[i], dz[i]}; }
  Vec3 p(size_t i) const { return {px[i], py[i], pz[i]}; }
  Vec3 n(size_t i) const { return {nx[i], ny[i], nz[i]}; }
  /// A lane without a surface (the background): I and its differentials.
  void setDirection(size_t i, const Dual3 &dir) {
    dx[i] = dir.v.x, dy[i] = dir.v.y, dz[i] = dir.v.z;
    dIdxX[i] = dir.dx.x, dIdxY[i] = dir.dx.y, dIdxZ[i] = dir.dx.z;
    dIdyX[i] = dir.dy.x, dIdyY[i] = dir.dy.y, dIdyZ[i] = dir.dy.z;
  }
};

/// Light samples, as structure of arrays: each lane's light, the point it
/// is seen from and two uniform numbers in; the unit direction toward the
/// sampled point of the light and its solid-angle pdf (0: none) out.
struct LightDraws {
  std::vector<int> light;
  std::vector<float> ox, oy, oz, rx, ry;
  std::vector<float> dx, dy, dz, pdf;
  size_t count = 0;
  void clear() { resize(0); }
  /// Room for n draws, which set() fills by index (columns only grow:
  /// size() is the count).
  void resize(size_t n) {
    growTo(n, light, ox, oy, oz, rx, ry);
    count = n;
  }
  void set(size_t i, int l, Vec3 from, float r0, float r1) {
    light[i] = l;
    ox[i] = from.x, oy[i] = from.y, oz[i] = from.z;
    rx[i] = r0, ry[i] = r1;
  }
  void push(int l, Vec3 from, float r0, float r1) {
    resize(size() + 1);
    set(size() - 1, l, from, r0, r1);
  }
  size_t size() const { return count; }
  Vec3 dir(size_t i) const { return {dx[i], dy[i], dz[i]}; }
};

/// Directions drawn from the background's table, as structure of arrays:
/// each lane's direction, radiance over pdf, and pdf.
struct BackgroundDraws {
  std::vector<float> dx, dy, dz, r, g, b, pdf;
  void resize(size_t n) {
    for (std::vector<float> *v : {&dx, &dy, &dz, &r, &g, &b, &pdf})
      v->resize(n);
  }
  Vec3 dir(size_t i) const { return {dx[i], dy[i], dz[i]}; }
  Vec3 value(size_t i) const { return {r[i], g[i], b[i]}; }
};

/// Cosine lobes' samples (isCosineLobe), as structure of arrays: each
/// lane's normal (turned for a translucent lobe), whether it is
/// Oren-Nayar and its roughness, the direction toward the viewer and two
/// uniform numbers in; the sample (sampleCosineLobe) out.
struct CosineDraws {
  std::vector<int> orenNayar;
  std::vector<float> nx, ny, nz, sigma, wox, woy, woz, rx, ry;
  std::vector<float> wix, wiy, wiz, f, pdf, roughness;
  void clear() {
    orenNayar.clear();
    for (std::vector<float> *v : {&nx, &ny, &nz, &sigma, &wox, &woy, &woz, &rx, &ry})
      v->clear();
  }
  void push(const Lobe &l, Vec3 wo, float r0, float r1) {
    Vec3 n = cosineLobeNormal(l);
    orenNayar.push_back(l.model == Lobe::OrenNayar);
    nx.push_back(n.x), ny.push_back(n.y), nz.push_back(n.z), sigma.push_back(l.a);
    wox.push_back(wo.x), woy.push_back(wo.y), woz.push_back(wo.z);
    rx.push_back(r0), ry.push_back(r1);
  }
  size_t size() const { return orenNayar.size(); }
  BsdfSample result(size_t i) const {
    return {{wix[i], wiy[i], wiz[i]}, {f[i], f[i], f[i]}, pdf[i], roughness[i]};
  }
};

/// Mixtures of cosine lobes alone (each lobe isCosineLobe, as most
/// materials' are), as structure of arrays, for ShadingResult's prepare,
/// pick, mixSample and eval in lanes. Lobe j of mixture m is at
/// [j * size() + m]: its normal (turned for a translucent lobe), whether it
/// is Oren-Nayar and its sigma, its closure weight, and its pick
/// probability (out). Each mixture's path weight, whether its path may end
/// there (absorb), the direction toward the viewer and two uniform numbers
/// in; its BSDF sample out.
struct CosineMixtures {
  size_t mixtureCount = 0;
  std::vector<int> count;
  int maxCount = 0;
  std::vector<int> orenNayar;
  std::vector<float> nx, ny, nz, sigma, wx, wy, wz, pick;
  std::vector<int> absorb;
  std::vector<float> pwx, pwy, pwz, wox, woy, woz, rx, ry;
  std::vector<float> wix, wiy, wiz, fx, fy, fz, pdf, roughness;
  /// Between the lane loops: each mixture's pick total, the picks below
  /// rx, and the lobe picked (-1: none).
  std::vector<float> total, accum;
  std::vector<int> chosen;
  /// Room for `mixtures` of at most `lobes` lobes each, for set() to fill.
  void reset(size_t mixtures, int lobes);
  /// Mixture m: `lobes` (every one a cosine lobe) as ShadingResult::prepare
  /// would see them.
  void set(size_t m, const std::vector<Lobe> &lobes, Vec3 wo, Vec3 pathWeight, bool mayEnd);
  size_t size() const { return mixtureCount; }
  BsdfSample result(size_t m) const {
    return {{wix[m], wiy[m], wiz[m]}, {fx[m], fy[m], fz[m]}, pdf[m], roughness[m]};
  }
};

/// Cosine mixtures evaluated toward directions (ShadingResult::eval), as
/// structure of arrays: each lane's mixture (an index into CosineMixtures,
/// whose direction toward the viewer it uses) and direction in; the
/// mixture's weight and pdf out.
struct MixtureEvals {
  std::vector<int> mixture;
  std::vector<float> wix, wiy, wiz;
  std::vector<float> fx, fy, fz, pdf;
  size_t count = 0;
  void clear() { resize(0); }
  /// Room for n evaluations, which set() fills by index (columns only
  /// grow: size() is the count).
  void resize(size_t n) {
    growTo(n, mixture, wix, wiy, wiz);
    count = n;
  }
  void set(size_t i, int m, Vec3 wi) { mixture[i] = m, wix[i] = wi.x, wiy[i] = wi.y, wiz[i] = wi.z; }
  void push(int m, Vec3 wi) {
    resize(size() + 1);
    set(size() - 1, m, wi);
  }
  size_t size() const { return count; }
  Vec3 weight(size_t i) const { return {fx[i], fy[i], fz[i]}; }
};

/// testrender's camera, set up once: rays leave `eye` toward
/// dir + cx * (x / xres - 0.5) + cy * (0.5 - y / yres).
struct CameraSetup {
  Vec3 eye, dir, cx, cy;
  float invw = 1, invh = 1;
  int xres = 1, yres = 1;
};

struct LaneKernels {
  const char *isa;
  /// intersect() of rays `which[0..n)` of `rays` into hits[0..n), `width` at
  /// a time (`which` null: every ray, in order).
  void (*intersect)(const Scene &scene, const RayBatch &rays, const int *which, size_t n, int width,
                    std::vector<Hit> &hits);
  /// Fills x, y, z of every draw, `width` at a time.
  void (*drawPoints)(PointDraws &draws, int width);
  /// First rays: lane i's pixel and two uniform numbers (a tent-filtered
  /// offset in the pixel) in, its unit direction out.
  void (*cameraRays)(const CameraSetup &camera, const int *pixel, const float *jx, const float *jy,
                     size_t n, float *dx, float *dy, float *dz, int width);
  /// The outputs of every lane of `hits` (sized by it), its rays in `rays`.
  void (*hitGeometry)(const PrimTable &prims, const RayBatch &rays, HitPoints &hits, int width);
  /// The outputs of every lane of `draws` (sized by it): as testrender
  /// samples lights: a sphere's cone uniformly in solid angle, a quad
  /// uniformly by area.
  void (*sampleLights)(const PrimTable &prims, LightDraws &draws, int width);
  /// Lane i draws from `table` with (rx[i], ry[i]), as testrender samples it,
  /// into `out` (sized by it), `width` at a time.
  void (*sampleBackground)(const BackgroundMap::Table &table, const float *rx, const float *ry,
                           size_t n, BackgroundDraws &out, int width);
  /// The outputs of every lane of `draws` (sized by it).
  void (*sampleCosineLobes)(CosineDraws &draws, int width);
  /// What `table` holds toward rays which[0..n) of `rays` (radiance over
  /// pdf and pdf, as BackgroundMap::eval; the direction too) into `out`.
  void (*evalBackground)(const BackgroundMap::Table &table, const RayBatch &rays,
                         const int *which, size_t n, BackgroundDraws &out, int width);
  /// Each mixture's pick probabilities (prepare) and its BSDF sample with
  /// (rx, ry) (pick, the picked lobe's sample, mixSample), `width` at a time.
  void (*sampleCosineMixtures)(CosineMixtures &mixtures, int width);
  /// Every lane of `evals` (outputs sized by it), after
  /// sampleCosineMixtures gave the picks.
  void (*evalCosineMixtures)(const CosineMixtures &mixtures, MixtureEvals &evals, int width);
};

/// The kernels of the widest instruction set this CPU runs, or those the
/// environment's OSL_MLIR_RENDER_ISA names (generic, avx2, avx512), to
/// compare them.
const LaneKernels &laneKernels();

/// Every instruction set's kernels this CPU runs, plain x86-64 first.
std::vector<const LaneKernels *> laneKernelsThisCpuRuns();

const LaneKernels &genericLaneKernels();
const LaneKernels &avx2LaneKernels();
const LaneKernels &avx512LaneKernels();

} // namespace osl::render

#endif // OSLRENDER_LANEKERNELS_H
