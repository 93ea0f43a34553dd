//===- LaneKernelsImpl.h - The loops, for one instruction set -------------===//
//
// Included once per instruction set by LaneKernels{Generic,Avx2,Avx512}.cpp
// with OSL_LANE_TARGET (a target attribute, or nothing) and
// OSL_LANE_KERNELS (the function returning the table) defined. Everything
// here has internal linkage and the target attribute is on each function,
// not on the translation unit, so the inline helpers it calls (Vec3.h,
// Sampler.h) keep one plain out-of-line copy, safe for any CPU.
//
// Branches are selects, so each W-lane loop vectorizes (the file is built
// with -fno-math-errno: sqrt is an instruction).
//
//===----------------------------------------------------------------------===//
#include "LaneKernels.h"
#include "OslRender/RenderMath.h"
#include "OslRender/Sampler.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>

namespace osl::render {
namespace {

/// fn(std::integral_constant<int, W>) for the lane count `width` (1, 4, 8
/// or 16): each loop is instantiated once per width.
template <typename Fn> void atWidth(int width, Fn fn) {
  switch (width) {
  case 16:
    return fn(std::integral_constant<int, 16>());
  case 8:
    return fn(std::integral_constant<int, 8>());
  case 4:
    return fn(std::integral_constant<int, 4>());
  default:
    return fn(std::integral_constant<int, 1>());
  }
}

/// A batch of W rays, padded past the count with copies of the last one.
template <int W> struct RayLanes {
  float ox[W], oy[W], oz[W], dx[W], dy[W], dz[W];
  int self[W];
};

/// Distance along each lane's ray to sphere `s` (primitive `index`), or -1;
/// a ray leaving the sphere (self) keeps only the far root.
template <int W>
OSL_LANE_TARGET void sphereLanes(const Primitive &s, int index, const RayLanes<W> &r,
                                 float *__restrict t) {
  const double radius = s.radius, eps = 1e-4 * radius;
  for (int l = 0; l < W; ++l) {
    float ocx = s.center.x - r.ox[l], ocy = s.center.y - r.oy[l], ocz = s.center.z - r.oz[l];
    double b = ocx * r.dx[l] + ocy * r.dy[l] + ocz * r.dz[l];
    double det = b * b - double(ocx * ocx + ocy * ocy + ocz * ocz) + radius * radius;
    double root = std::sqrt(det < 0 ? 0.0 : det);
    double near = b - root, far = b + root;
    // Leaving the surface, the near root is ~0 (or the far one, going out):
    // a hit must be a real distance away.
    float leaving = far > eps && b > 0 ? float(far) : -1.0f;
    float arriving = near > eps ? float(near) : far > eps ? float(far) : -1.0f;
    float hit = r.self[l] == index ? leaving : arriving;
    t[l] = det < 0 ? -1.0f : hit;
  }
}

/// Distance along each lane's ray to quad `q`, or -1 (never its own).
template <int W>
OSL_LANE_TARGET void quadLanes(const Primitive &q, int index, const RayLanes<W> &r,
                               float *__restrict t) {
  const Vec3 n = cross(q.edgeX, q.edgeY);
  const float ex2 = dot(q.edgeX, q.edgeX), ey2 = dot(q.edgeY, q.edgeY);
  for (int l = 0; l < W; ++l) {
    float dn = r.dx[l] * n.x + r.dy[l] * n.y + r.dz[l] * n.z;
    float cx = q.corner.x - r.ox[l], cy = q.corner.y - r.oy[l], cz = q.corner.z - r.oz[l];
    float along = (cx * n.x + cy * n.y + cz * n.z) / dn;
    float hx = r.ox[l] + r.dx[l] * along - q.corner.x;
    float hy = r.oy[l] + r.dy[l] * along - q.corner.y;
    float hz = r.oz[l] + r.dz[l] * along - q.corner.z;
    float u = (hx * q.edgeX.x + hy * q.edgeX.y + hz * q.edgeX.z) / ex2;
    float v = (hx * q.edgeY.x + hy * q.edgeY.y + hz * q.edgeY.z) / ey2;
    bool inside = u >= 0 && u <= 1 && v >= 0 && v <= 1;
    bool hit = dn != 0 && along > 0 && inside && r.self[l] != index;
    t[l] = hit ? along : -1.0f;
  }
}

template <int W>
OSL_LANE_TARGET void intersectLanes(const Scene &scene, const RayLanes<W> &r,
                                    float *__restrict bestT, int *__restrict bestPrim) {
  for (int l = 0; l < W; ++l) {
    bestT[l] = std::numeric_limits<float>::infinity();
    bestPrim[l] = -1;
  }
  float t[W];
  for (int i = 0; i < int(scene.prims.size()); ++i) {
    const Primitive &p = scene.prims[i];
    if (p.kind == Primitive::Sphere)
      sphereLanes<W>(p, i, r, t);
    else
      quadLanes<W>(p, i, r, t);
    for (int l = 0; l < W; ++l) {
      bool closer = t[l] > 0 && t[l] < bestT[l];
      bestT[l] = closer ? t[l] : bestT[l];
      bestPrim[l] = closer ? i : bestPrim[l];
    }
  }
}

template <int W>
OSL_LANE_TARGET void intersectAt(const Scene &scene, const RayBatch &rays, const int *which,
                                 size_t n, std::vector<Hit> &hits) {
  RayLanes<W> r;
  float t[W];
  int prim[W];
  for (size_t start = 0; start < n; start += W) {
    int count = int(std::min<size_t>(W, n - start));
    for (int l = 0; l < W; ++l) {
      size_t at = start + size_t(std::min(l, count - 1));
      size_t k = which ? size_t(which[at]) : at;
      r.ox[l] = rays.ox[k], r.oy[l] = rays.oy[k], r.oz[l] = rays.oz[k];
      r.dx[l] = rays.dx[k], r.dy[l] = rays.dy[k], r.dz[l] = rays.dz[k];
      r.self[l] = rays.self[k];
    }
    intersectLanes<W>(scene, r, t, prim);
    for (int l = 0; l < count; ++l)
      hits[start + size_t(l)] = Hit{prim[l], t[l]};
  }
}

void intersect(const Scene &scene, const RayBatch &rays, const int *which, size_t n, int width,
               std::vector<Hit> &hits) {
  hits.resize(n);
  atWidth(width, [&](auto w) { intersectAt<decltype(w)::value>(scene, rays, which, n, hits); });
}

/// Runs body(i) for i in [0, n), W at a time: the full batches as W-lane
/// loops the compiler vectorizes, the rest one by one (each lane's result
/// is the same either way). Lanes touch only element i of each array, so
/// the loop is declared free of dependences between them (the arrays are
/// too many for the vectorizer's run-time overlap checks).
template <int W, typename Body> OSL_LANE_TARGET void forLanes(size_t n, Body body) {
  size_t full = W > 1 ? n / W * W : 0;
  if constexpr (W > 1) {
    for (size_t start = 0; start < full; start += W)
#pragma clang loop vectorize(assume_safety) interleave(disable)
      for (int l = 0; l < W; ++l)
        body(start + size_t(l));
  }
  for (size_t i = full; i < n; ++i)
    body(i);
}

/// testrender's pixel filter: a uniform number warped to a tent on [-1, 1).
[[gnu::always_inline]] inline float tent(float u) {
  u *= 2;
  float below = std::sqrt(u) - 1, above = 1 - std::sqrt(std::fmax(0.0f, 2 - u));
  return u < 1 ? below : above;
}

template <int W>
OSL_LANE_TARGET void cameraRaysAt(const CameraSetup &c, const int *__restrict pixel,
                                  const float *__restrict jx, const float *__restrict jy, size_t n,
                                  float *__restrict dx, float *__restrict dy,
                                  float *__restrict dz) {
  const float xres = float(c.xres), yres = float(c.yres);
  forLanes<W>(
      n, [&](size_t i) __attribute__((always_inline)) {
        // The pixel's row and column, exactly for any int index (a quotient
        // in double, corrected by one where it rounded up).
        int p = pixel[i];
        int row = int(double(p) / double(c.xres));
        row = row * c.xres > p ? row - 1 : row;
        int col = p - row * c.xres;
        float sx = (float(col) + 0.5f + tent(jx[i])) / xres - 0.5f;
        float sy = 0.5f - (float(row) + 0.5f + tent(jy[i])) / yres;
        float x = c.right.x * sx + c.up.x * sy + c.dir.x;
        float y = c.right.y * sx + c.up.y * sy + c.dir.y;
        float z = c.right.z * sx + c.up.z * sy + c.dir.z;
        float len = std::sqrt(x * x + y * y + z * z);
        dx[i] = x / len, dy[i] = y / len, dz[i] = z / len;
      });
}

void cameraRays(const CameraSetup &camera, const int *pixel, const float *jx, const float *jy,
                size_t n, float *dx, float *dy, float *dz, int width) {
  atWidth(width,
          [&](auto w) { cameraRaysAt<decltype(w)::value>(camera, pixel, jx, jy, n, dx, dy, dz); });
}

/// Each lane's point, normal and parametric frame on its primitive: a
/// sphere's and a quad's both computed, the lane's kind selected.
template <int W>
OSL_LANE_TARGET void hitGeometryAt(const PrimTable &T, const RayBatch &rays, HitPoints &h) {
  constexpr float twoPi = 2 * kRenderPi;
  forLanes<W>(
      h.size(), [&](size_t i) __attribute__((always_inline)) {
        int k = h.prim[i], ray = h.ray[i];
        float ox = rays.ox[ray], oy = rays.oy[ray], oz = rays.oz[ray];
        float dx = rays.dx[ray], dy = rays.dy[ray], dz = rays.dz[ray];
        h.ox[i] = ox, h.oy[i] = oy, h.oz[i] = oz, h.dx[i] = dx, h.dy[i] = dy, h.dz[i] = dz;
        float px = ox + dx * h.t[i];
        float py = oy + dy * h.t[i];
        float pz = oz + dz * h.t[i];
        // Sphere: the outward normal; u around y from +x, v from +y down.
        float r = T.radius[k];
        float sx = px - T.cx[k], sy = py - T.cy[k], sz = pz - T.cz[k];
        float sl = std::sqrt(sx * sx + sy * sy + sz * sz);
        float div = sl > 0 ? sl : 1.0f; // as normalize() divides
        sx /= div, sy /= div, sz /= div;
        float phi = polyAtan2(sz, sx);
        float su = phi / twoPi + (phi < 0 ? 1.0f : 0.0f);
        float sv = polyAcos(sy) / kRenderPi;
        float sux = -sz * (twoPi * r), suz = sx * (twoPi * r);
        // dPdv: cross(dPdu, n) scaled to length pi r.
        float vx = -suz * sy, vy = suz * sx - sux * sz, vz = sux * sy;
        float vl = std::sqrt(vx * vx + vy * vy + vz * vz);
        float vs = vl > 0 ? kRenderPi * r / vl : 0.0f;
        // Quad: its plane's normal; u and v along its edges.
        float hx = px - T.qx[k], hy = py - T.qy[k], hz = pz - T.qz[k];
        float qu = (hx * T.ex[k] + hy * T.ey[k] + hz * T.ez[k]) / T.edgeX2[k];
        float qv = (hx * T.fx[k] + hy * T.fy[k] + hz * T.fz[k]) / T.edgeY2[k];
        bool sphere = T.kind[k] == Primitive::Sphere;
        float nx = sphere ? sx : T.nx[k], ny = sphere ? sy : T.ny[k], nz = sphere ? sz : T.nz[k];
        bool back = dx * nx + dy * ny + dz * nz > 0;
        h.px[i] = px, h.py[i] = py, h.pz[i] = pz;
        h.nx[i] = back ? -nx : nx, h.ny[i] = back ? -ny : ny, h.nz[i] = back ? -nz : nz;
        h.dPdux[i] = sphere ? sux : T.ex[k];
        h.dPduy[i] = sphere ? 0.0f : T.ey[k];
        h.dPduz[i] = sphere ? suz : T.ez[k];
        h.dPdvx[i] = sphere ? vx * vs : T.fx[k];
        h.dPdvy[i] = sphere ? vy * vs : T.fy[k];
        h.dPdvz[i] = sphere ? vz * vs : T.fz[k];
        h.u[i] = sphere ? su : qu;
        h.v[i] = sphere ? sv : qv;
        h.backfacing[i] = back ? 1.0f : 0.0f;
        h.area[i] = T.area[k];
      });
}

void hitGeometry(const PrimTable &prims, const RayBatch &rays, HitPoints &hits, int width) {
  hits.sizeOutputs();
  atWidth(width, [&](auto w) { hitGeometryAt<decltype(w)::value>(prims, rays, hits); });
}

template <int W> OSL_LANE_TARGET void sampleLightsAt(const PrimTable &T, LightDraws &s) {
  forLanes<W>(
      s.size(), [&](size_t i) __attribute__((always_inline)) {
        int k = s.light[i];
        Vec3 x(s.ox[i], s.oy[i], s.oz[i]);
        float rx = s.rx[i], ry = s.ry[i];
        // Sphere: a direction in the cone the light subtends, about its center.
        Vec3 toC = Vec3(T.cx[k], T.cy[k], T.cz[k]) - x;
        float d2 = dot(toC, toC), r2 = T.radius[k] * T.radius[k];
        float cosMax = std::sqrt(std::fmax(0.0f, 1 - r2 / d2));
        float cosT = 1 - rx * (1 - cosMax), sinT = std::sqrt(std::fmax(0.0f, 1 - cosT * cosT));
        float sinPhi, cosPhi;
        polySinCos(2 * kRenderPi * ry, sinPhi, cosPhi);
        Frame f(toC / std::sqrt(d2));
        Vec3 cone = f.toWorld(Vec3(sinT * cosPhi, sinT * sinPhi, cosT));
        float conePdf = sphereLightPdf(d2, r2);
        // Quad: a point on it, uniformly.
        Vec3 p = Vec3(T.qx[k], T.qy[k], T.qz[k]) + Vec3(T.ex[k], T.ey[k], T.ez[k]) * rx +
                 Vec3(T.fx[k], T.fy[k], T.fz[k]) * ry;
        Vec3 d = p - x;
        float q2 = dot(d, d);
        Vec3 toP = d / std::sqrt(q2);
        float areaPdf = quadLightPdf(Vec3(T.nx[k], T.ny[k], T.nz[k]), T.area[k], toP, q2);
        bool sphere = T.kind[k] == Primitive::Sphere;
        s.dx[i] = sphere ? cone.x : toP.x;
        s.dy[i] = sphere ? cone.y : toP.y;
        s.dz[i] = sphere ? cone.z : toP.z;
        s.pdf[i] = sphere ? conePdf : q2 > 0 ? areaPdf : 0.0f;
      });
}

void sampleLights(const PrimTable &prims, LightDraws &draws, int width) {
  for (std::vector<float> *v : {&draws.dx, &draws.dy, &draws.dz, &draws.pdf})
    v->resize(draws.size());
  atWidth(width, [&](auto w) { sampleLightsAt<decltype(w)::value>(prims, draws); });
}

template <int W, CosineModel M> OSL_LANE_TARGET void sampleCosineAt(CosineDraws &d) {
  forLanes<W>(
      d.size(), [&](size_t i) __attribute__((always_inline)) {
        CosineLobe l;
        l.n = Vec3(d.nx[i], d.ny[i], d.nz[i]);
        l.a = d.a[i];
        l.rho = Vec3(d.rhoX[i], d.rhoY[i], d.rhoZ[i]);
        l.through = d.through[i] != 0;
        CosineSample s =
            sampleCosineLobe<M>(l, Vec3(d.wox[i], d.woy[i], d.woz[i]), d.rx[i], d.ry[i]);
        d.wix[i] = s.wi.x, d.wiy[i] = s.wi.y, d.wiz[i] = s.wi.z;
        d.valueX[i] = s.eval.value.x, d.valueY[i] = s.eval.value.y;
        d.valueZ[i] = s.eval.value.z, d.pdf[i] = s.eval.pdf;
        // ShadingResult::finish for a mixture of this lobe alone: its
        // weighted f*cos over its pick-weighted pdf (sums from 0, as there).
        float mixturePdf = 0.0f + d.pick[i] * s.eval.pdf;
        bool sampled = s.eval.pdf > 0 && mixturePdf > 0;
        float divisor = sampled ? mixturePdf : 1.0f;
        d.aloneX[i] = (0.0f + d.weightX[i] * s.eval.value.x) / divisor;
        d.aloneY[i] = (0.0f + d.weightY[i] * s.eval.value.y) / divisor;
        d.aloneZ[i] = (0.0f + d.weightZ[i] * s.eval.value.z) / divisor;
        d.alonePdf[i] = sampled ? mixturePdf : 0.0f;
      });
}

void sampleCosineLobes(CosineModel model, CosineDraws &draws, int width) {
  for (std::vector<float> *v : {&draws.wix, &draws.wiy, &draws.wiz, &draws.valueX, &draws.valueY,
                                &draws.valueZ, &draws.pdf, &draws.aloneX, &draws.aloneY,
                                &draws.aloneZ, &draws.alonePdf})
    v->resize(draws.size());
  atCosineModel(model, [&](auto m) {
    atWidth(width, [&](auto w) {
      sampleCosineAt<decltype(w)::value, decltype(m)::value>(draws);
    });
  });
}

/// W sampler points, one per lane.
template <int W>
OSL_LANE_TARGET void drawLanes(const uint32_t *__restrict key, const uint32_t *__restrict index,
                               const uint32_t *__restrict call, float *__restrict x,
                               float *__restrict y, float *__restrict z) {
  for (int l = 0; l < W; ++l) {
    Vec3 p = samplerPoint(key[l], index[l], call[l]);
    x[l] = p.x, y[l] = p.y, z[l] = p.z;
  }
}

template <int W> OSL_LANE_TARGET void drawPointsAt(PointDraws &d) {
  size_t n = d.size(), full = n / W * W;
  for (size_t start = 0; start < full; start += W)
    drawLanes<W>(&d.key[start], &d.index[start], &d.call[start], &d.x[start], &d.y[start],
                 &d.z[start]);
  if (full == n)
    return;
  // The last, partial batch: padded with copies of its last draw.
  uint32_t key[W], index[W], call[W];
  float x[W], y[W], z[W];
  for (int l = 0; l < W; ++l) {
    size_t k = std::min(full + size_t(l), n - 1);
    key[l] = d.key[k], index[l] = d.index[k], call[l] = d.call[k];
  }
  drawLanes<W>(key, index, call, x, y, z);
  for (size_t k = full; k < n; ++k)
    d.x[k] = x[k - full], d.y[k] = y[k - full], d.z[k] = z[k - full];
}

void drawPoints(PointDraws &draws, int width) {
  draws.x.resize(draws.size());
  draws.y.resize(draws.size());
  draws.z.resize(draws.size());
  atWidth(width, [&](auto w) { drawPointsAt<decltype(w)::value>(draws); });
}

} // namespace

const LaneKernels &OSL_LANE_KERNELS() {
  static const LaneKernels kernels{OSL_LANE_ISA_NAME, intersect,    drawPoints,
                                   cameraRays,        hitGeometry,  sampleLights,
                                   sampleCosineLobes};
  return kernels;
}

} // namespace osl::render
