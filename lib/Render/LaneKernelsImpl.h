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
#include "OslRender/Sampler.h"
#include "OslRender/Sampling.h"
#include "Dual.h"

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

/// Distance along each lane's ray to sphere `s` (primitive `index`), or 0,
/// as testrender computes it: a ray leaving the sphere (self) takes the
/// root farther from its origin.
template <int W>
OSL_LANE_TARGET void sphereLanes(const Primitive &s, int index, const RayLanes<W> &r,
                                 float *__restrict t) {
  const float r2 = s.radius * s.radius;
  for (int l = 0; l < W; ++l) {
    float ocx = s.center.x - r.ox[l], ocy = s.center.y - r.oy[l], ocz = s.center.z - r.oz[l];
    float b = ocx * r.dx[l] + ocy * r.dy[l] + ocz * r.dz[l];
    float det = b * b - (ocx * ocx + ocy * ocy + ocz * ocz) + r2;
    float root = std::sqrt(det >= 0 ? det : 0.0f);
    float near = b - root, far = b + root;
    float leaving = std::fabs(near) > std::fabs(far) ? (near > 0 ? near : 0.0f)
                                                      : (far > 0 ? far : 0.0f);
    float arriving = near > 0 ? near : far > 0 ? far : 0.0f;
    float hit = r.self[l] == index ? leaving : arriving;
    t[l] = det >= 0 ? hit : 0.0f;
  }
}

/// Distance along each lane's ray to quad `q` (primitive `index`), or 0
/// (never its own), as testrender computes it.
template <int W>
OSL_LANE_TARGET void quadLanes(const Primitive &q, int index, const QuadFrame &f,
                               const RayLanes<W> &r, float *__restrict t) {
  const Vec3 n = f.n;
  for (int l = 0; l < W; ++l) {
    float dn = r.dx[l] * n.x + r.dy[l] * n.y + r.dz[l] * n.z;
    float cx = q.corner.x - r.ox[l], cy = q.corner.y - r.oy[l], cz = q.corner.z - r.oz[l];
    float en = cx * n.x + cy * n.y + cz * n.z;
    float along = en / (dn * en > 0 ? dn : 1.0f);
    float hx = (r.ox[l] + r.dx[l] * along) - q.corner.x;
    float hy = (r.oy[l] + r.dy[l] * along) - q.corner.y;
    float hz = (r.oz[l] + r.dz[l] * along) - q.corner.z;
    float u = (hx * q.edgeX.x + hy * q.edgeX.y + hz * q.edgeX.z) * f.eu;
    float v = (hx * q.edgeY.x + hy * q.edgeY.y + hz * q.edgeY.z) * f.ev;
    bool inside = u >= 0 && u < 1 && v >= 0 && v < 1;
    bool hit = dn * en > 0 && inside && r.self[l] != index;
    t[l] = hit ? along : 0.0f;
  }
}

template <int W>
OSL_LANE_TARGET void intersectLanes(const Scene &scene, const std::vector<QuadFrame> &frames,
                                    const RayLanes<W> &r, float *__restrict bestT,
                                    int *__restrict bestPrim) {
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
      quadLanes<W>(p, i, frames[size_t(i)], r, t);
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
  // Each quad's frame once per call, not once per batch of rays.
  std::vector<QuadFrame> frames;
  for (const Primitive &p : scene.prims)
    frames.push_back(p.kind == Primitive::Quad ? QuadFrame(p) : QuadFrame());
  for (size_t start = 0; start < n; start += W) {
    int count = int(std::min<size_t>(W, n - start));
    auto copyRay = [&](int l, size_t k) __attribute__((always_inline)) {
      r.ox[l] = rays.ox[k], r.oy[l] = rays.oy[k], r.oz[l] = rays.oz[k];
      r.dx[l] = rays.dx[k], r.dy[l] = rays.dy[k], r.dz[l] = rays.dz[k];
      r.self[l] = rays.self[k];
    };
    if (!which && count == W) {
      // Consecutive rays (the shadow rays): vector moves, not a gather.
#pragma clang loop vectorize(assume_safety) interleave(disable)
      for (int l = 0; l < W; ++l)
        copyRay(l, start + size_t(l));
    } else {
      for (int l = 0; l < W; ++l) {
        size_t at = start + size_t(std::min(l, count - 1));
        copyRay(l, which ? size_t(which[at]) : at);
      }
    }
    intersectLanes<W>(scene, frames, r, t, prim);
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

/// forLanes, where a full batch whose lanes share one `key` (a primitive)
/// runs body(i, k) with that k the same for every lane, so what the body
/// reads at k is loaded once and broadcast instead of gathered per lane;
/// other batches run body(i, key[i]).
template <int W, typename Body>
OSL_LANE_TARGET void forLanesSharing(size_t n, const int *__restrict key, Body body) {
  size_t full = W > 1 ? n / W * W : 0;
  if constexpr (W > 1) {
    for (size_t start = 0; start < full; start += W) {
      const int k = key[start];
      bool shared = true;
      for (int l = 1; l < W; ++l)
        shared &= key[start + size_t(l)] == k;
      if (shared) {
#pragma clang loop vectorize(assume_safety) interleave(disable)
        for (int l = 0; l < W; ++l)
          body(start + size_t(l), k);
      } else {
#pragma clang loop vectorize(assume_safety) interleave(disable)
        for (int l = 0; l < W; ++l)
          body(start + size_t(l), key[start + size_t(l)]);
      }
    }
  }
  for (size_t i = full; i < n; ++i)
    body(i, key[i]);
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
  forLanes<W>(
      n, [&](size_t i) __attribute__((always_inline)) {
        // The pixel's row and column, exactly for any int index (a quotient
        // in double, corrected by one where it rounded up).
        int p = pixel[i];
        int row = int(double(p) / double(c.xres));
        row = row * c.xres > p ? row - 1 : row;
        int col = p - row * c.xres;
        float sx = (float(col) + 0.5f + tent(jx[i])) * c.invw - 0.5f;
        float sy = 0.5f - (float(row) + 0.5f + tent(jy[i])) * c.invh;
        float x = (c.cx.x * sx + c.cy.x * sy) + c.dir.x;
        float y = (c.cx.y * sx + c.cy.y * sy) + c.dir.y;
        float z = (c.cx.z * sx + c.cy.z * sy) + c.dir.z;
        float len = std::sqrt(x * x + y * y + z * z);
        dx[i] = x / len, dy[i] = y / len, dz[i] = z / len;
      });
}

void cameraRays(const CameraSetup &camera, const int *pixel, const float *jx, const float *jy,
                size_t n, float *dx, float *dy, float *dz, int width) {
  atWidth(width,
          [&](auto w) { cameraRaysAt<decltype(w)::value>(camera, pixel, jx, jy, n, dx, dy, dz); });
}

/// Each lane's point, normal, parametric frame and ray differentials on
/// its primitive, as testrender's globals_from_hit computes them: in
/// lanes, but for a sphere's u and v and its frame from them, which take
/// libm's atan2, acos, sin and cos (testrender's) one sphere at a time.
template <int W>
OSL_LANE_TARGET void hitGeometryAt(const PrimTable &T, const RayBatch &rays, HitPoints &h) {
  const float pi = float(M_PI);
  auto set3 = [](std::vector<float> &x, std::vector<float> &y, std::vector<float> &z, size_t i,
                 Vec3 v) { x[i] = v.x, y[i] = v.y, z[i] = v.z; };
  // A queue's hits come path by path, a pixel's samples together: most
  // batches of the first bounces are on one primitive.
  forLanesSharing<W>(h.size(), h.prim.data(), [&](size_t i, int k) __attribute__((always_inline)) {
    int ray = h.ray[i];
    Vec3 o(rays.ox[ray], rays.oy[ray], rays.oz[ray]);
    Vec3 d(rays.dx[ray], rays.dy[ray], rays.dz[ray]);
    set3(h.ox, h.oy, h.oz, i, o);
    set3(h.dx, h.dy, h.dz, i, d);
    float t = h.t[i];
    // The footprint: the ray's radius grown by its spread over t, across
    // two directions orthogonal to it.
    float radius = rays.radius[ray] + rays.spread[ray] * t;
    Vec3 ex, ey;
    orthoBasis(d, ex, ey);
    Vec3 pv = o + d * t, pdx = ex * radius, pdy = ey * radius;
    bool sphere = T.kind[k] == Primitive::Sphere;
    // Both primitives' normal and (u, v) slopes, one kept: a sphere's
    // values of u and v wait for libm below, its slopes do not.
    Dual nsx{pv.x - T.cx[k], pdx.x, pdy.x}, nsy{pv.y - T.cy[k], pdx.y, pdy.y},
        nsz{pv.z - T.cz[k], pdx.z, pdy.z};
    normalize(nsx, nsy, nsz);
    Dual us = (atan2Slopes(nsx, nsz) + Dual(pi)) * 0.5f * float(M_1_PI);
    Dual vs = safeAcosSlopes(nsy) * float(M_1_PI);
    Vec3 nq(T.nx[k], T.ny[k], T.nz[k]);
    Dual relx{pv.x - T.qx[k], pdx.x, pdy.x}, rely{pv.y - T.qy[k], pdx.y, pdy.y},
        relz{pv.z - T.qz[k], pdx.z, pdy.z};
    Vec3 dPdu(T.ex[k], T.ey[k], T.ez[k]), dPdv(T.fx[k], T.fy[k], T.fz[k]);
    Dual uq = dot(relx, rely, relz, dPdu) * T.eu[k];
    Dual vq = dot(relx, rely, relz, dPdv) * T.ev[k];
    Vec3 n = select(sphere, Vec3(nsx.v, nsy.v, nsz.v), nq);
    Dual u = select(sphere, us, uq), v = select(sphere, vs, vq);
    bool back = dot(n, d) > 0;
    Vec3 normal = select(back, -n, n);
    set3(h.px, h.py, h.pz, i, pv);
    set3(h.nx, h.ny, h.nz, i, normal);
    set3(h.dPdux, h.dPduy, h.dPduz, i, dPdu);
    set3(h.dPdvx, h.dPdvy, h.dPdvz, i, dPdv);
    set3(h.dPdxX, h.dPdxY, h.dPdxZ, i, pdx);
    set3(h.dPdyX, h.dPdyY, h.dPdyZ, i, pdy);
    // I's differentials: the same directions, by the spread alone.
    float spread = rays.spread[ray];
    set3(h.dIdxX, h.dIdxY, h.dIdxZ, i, ex * spread);
    set3(h.dIdyX, h.dIdyY, h.dIdyZ, i, ey * spread);
    h.u[i] = u.v, h.v[i] = v.v;
    h.dudx[i] = u.dx, h.dudy[i] = u.dy, h.dvdx[i] = v.dx, h.dvdy[i] = v.dy;
    h.backfacing[i] = back ? 1.0f : 0.0f;
    h.flip[i] = dot(cross(pdx, pdy), normal) < 0 ? 1.0f : 0.0f;
    h.area[i] = T.area[k];
    h.radius[i] = radius;
  });
  // A sphere's u and v, and its frame from them (the unit normal, before
  // it was turned toward the ray, is back * normal).
  for (size_t i = 0; i < h.size(); ++i) {
    int k = h.prim[i];
    if (T.kind[k] != Primitive::Sphere)
      continue;
    float turn = h.backfacing[i] != 0 ? -1.0f : 1.0f;
    float nx = h.nx[i] * turn, ny = h.ny[i] * turn, nz = h.nz[i] * turn;
    float u = (std::atan2(nx, nz) + pi) * 0.5f * float(M_1_PI);
    float v = safeAcosValue(ny) * float(M_1_PI);
    h.u[i] = u, h.v[i] = v;
    float sin2piu = std::sin(2.0f * pi * u), cos2piu = std::cos(2.0f * pi * u);
    float sinpiv = std::sin(pi * v), cospiv = std::cos(pi * v);
    float pir = pi * T.radius[k];
    set3(h.dPdux, h.dPduy, h.dPduz, i,
         Vec3(-2.0f * pir * sinpiv * cos2piu, 0.0f, 2.0f * pir * sinpiv * sin2piu));
    set3(h.dPdvx, h.dPdvy, h.dPdvz, i,
         Vec3(-pir * cospiv * sin2piu, -pir * sinpiv, -pir * cospiv * cos2piu));
  }
}

void hitGeometry(const PrimTable &prims, const RayBatch &rays, HitPoints &hits, int width) {
  hits.sizeOutputs();
  atWidth(width, [&](auto w) { hitGeometryAt<decltype(w)::value>(prims, rays, hits); });
}

/// testrender's light samples in lanes: a sphere's and a quad's sample
/// both computed, the light's kept.
template <int W> OSL_LANE_TARGET void sampleLightsAt(const PrimTable &T, LightDraws &s) {
  forLanes<W>(s.size(), [&](size_t i) __attribute__((always_inline)) {
    int k = s.light[i];
    Vec3 x(s.ox[i], s.oy[i], s.oz[i]);
    float rx = s.rx[i], ry = s.ry[i];
    // Sphere: a direction in the cone the light subtends, about its center.
    constexpr float twoPi = float(2 * M_PI);
    Vec3 toC = Vec3(T.cx[k], T.cy[k], T.cz[k]) - x;
    float cmax2 = 1 - T.r2[k] / dot(toC, toC);
    float cmax = cmax2 > 0 ? std::sqrt(cmax2) : 0.0f;
    float cosA = 1 - rx + rx * cmax;
    float sinA = std::sqrt(1 - cosA * cosA);
    float sp, cp;
    fast::sincos(twoPi * ry, sp, cp);
    Vec3 sw = normalize(toC), su, sv;
    orthoBasis(sw, su, sv);
    Vec3 sphereDir = normalize(su * (cp * sinA) + sv * (sp * sinA) + sw * cosA);
    float spherePdf = 1 / (twoPi * (1 - cmax));
    // Quad: a point on it, uniformly by area.
    Vec3 l = (Vec3(T.qx[k], T.qy[k], T.qz[k]) + rx * Vec3(T.ex[k], T.ey[k], T.ez[k]) +
              ry * Vec3(T.fx[k], T.fy[k], T.fz[k])) -
             x;
    float d2 = dot(l, l);
    Vec3 quadDir = normalize(l);
    float quadPdf = d2 / (T.area[k] * std::fabs(dot(quadDir, Vec3(T.nx[k], T.ny[k], T.nz[k]))));
    bool sphere = T.kind[k] == Primitive::Sphere;
    Vec3 dir = select(sphere, sphereDir, quadDir);
    s.dx[i] = dir.x, s.dy[i] = dir.y, s.dz[i] = dir.z;
    s.pdf[i] = sphere ? spherePdf : quadPdf;
  });
}

void sampleLights(const PrimTable &prims, LightDraws &draws, int width) {
  growTo(draws.size(), draws.dx, draws.dy, draws.dz, draws.pdf);
  atWidth(width, [&](auto w) { sampleLightsAt<decltype(w)::value>(prims, draws); });
}

/// std::upper_bound (NaN past the end) in W lanes at once, stepping
/// together: lane l searches cdf[offset[l], offset[l] + n) for x[l].
template <int W>
OSL_LANE_TARGET void upperBoundLanes(const float *__restrict cdf, const int *__restrict offset,
                                     int n, const float *__restrict x, int *__restrict index) {
  int base[W];
  for (int l = 0; l < W; ++l)
    base[l] = 0;
  for (int len = n; len > 1;) {
    int half = len / 2;
    for (int l = 0; l < W; ++l)
      base[l] = !(x[l] < cdf[offset[l] + base[l] + half - 1]) ? base[l] + half : base[l];
    len -= half;
  }
  for (int l = 0; l < W; ++l)
    index[l] = !(x[l] < cdf[offset[l] + base[l]]) ? base[l] + 1 : base[l];
}

/// testrender's background sample: a row from the rows' distribution, a
/// column from the row's, and the cell's radiance over its pdf. Padded
/// with copies of the last draw.
template <int W>
OSL_LANE_TARGET void sampleBackgroundAt(const BackgroundMap::Table &t, const float *__restrict rx,
                                        const float *__restrict ry, size_t n,
                                        BackgroundDraws &out) {
  const int last = t.res - 1;
  for (size_t start = 0; start < n; start += W) {
    int count = int(std::min<size_t>(W, n - start));
    float x[W], y[W], rowPdf[W], colPdf[W];
    int row[W], col[W], offset[W];
    for (int l = 0; l < W; ++l) {
      size_t k = start + size_t(std::min(l, count - 1));
      x[l] = rx[k], y[l] = ry[k], offset[l] = 0;
    }
    // x below 1 always: only a table of zeros has no entry above it.
    upperBoundLanes<W>(t.rows, offset, t.res, y, row);
    for (int l = 0; l < W; ++l) {
      row[l] = std::min(row[l], last);
      y[l] = rescaleInCdf(t.rows, row[l], y[l], rowPdf[l]);
      offset[l] = row[l] * t.res;
    }
    upperBoundLanes<W>(t.cols, offset, t.res, x, col);
    float dx[W], dy[W], dz[W], r[W], g[W], b[W], pdf[W];
    for (int l = 0; l < W; ++l) {
      col[l] = std::min(col[l], last);
      x[l] = rescaleInCdf(t.cols + offset[l], col[l], x[l], colPdf[l]);
      Vec3 dir = tableDirection(t, float(col[l]) + x[l], float(row[l]) + y[l]).v;
      dx[l] = dir.x, dy[l] = dir.y, dz[l] = dir.z;
      pdf[l] = rowPdf[l] * colPdf[l] * t.invjacobian;
      Vec3 value = t.values[size_t(offset[l] + col[l])];
      r[l] = value.x, g[l] = value.y, b[l] = value.z;
    }
    for (int l = 0; l < count; ++l) {
      size_t k = start + size_t(l);
      out.dx[k] = dx[l], out.dy[k] = dy[l], out.dz[k] = dz[l];
      out.r[k] = r[l], out.g[k] = g[l], out.b[k] = b[l], out.pdf[k] = pdf[l];
    }
  }
}

void sampleBackground(const BackgroundMap::Table &table, const float *rx, const float *ry,
                      size_t n, BackgroundDraws &out, int width) {
  out.resize(n);
  atWidth(width,
          [&](auto w) { sampleBackgroundAt<decltype(w)::value>(table, rx, ry, n, out); });
}

template <int W> OSL_LANE_TARGET void sampleCosineLobesAt(CosineDraws &d) {
  forLanes<W>(d.size(), [&](size_t i) __attribute__((always_inline)) {
    BsdfSample s = sampleCosineLobe(d.orenNayar[i] != 0, Vec3(d.nx[i], d.ny[i], d.nz[i]),
                                    d.sigma[i], Vec3(d.wox[i], d.woy[i], d.woz[i]), d.rx[i],
                                    d.ry[i]);
    d.wix[i] = s.wi.x, d.wiy[i] = s.wi.y, d.wiz[i] = s.wi.z;
    d.f[i] = s.weight.x, d.pdf[i] = s.pdf, d.roughness[i] = s.roughness;
  });
}

void sampleCosineLobes(CosineDraws &draws, int width) {
  for (std::vector<float> *v :
       {&draws.wix, &draws.wiy, &draws.wiz, &draws.f, &draws.pdf, &draws.roughness})
    v->resize(draws.size());
  atWidth(width, [&](auto w) { sampleCosineLobesAt<decltype(w)::value>(draws); });
}

/// Lobe k of `c` evaluated toward wi (its weight applied).
[[gnu::always_inline]] inline BsdfSample evalMixtureLobe(const CosineMixtures &c, size_t k,
                                                         Vec3 wo, Vec3 wi) {
  BsdfSample b = cosineLobeEval(c.orenNayar[k] != 0, Vec3(c.nx[k], c.ny[k], c.nz[k]), c.sigma[k],
                                wo, wi);
  b.weight *= Vec3(c.wx[k], c.wy[k], c.wz[k]);
  return b;
}

/// ShadingResult::prepare, pick, sampleLobe and mixSample of each mixture:
/// each step over the lobes is one lane loop per lobe (the mixtures'
/// running values in columns between them), with the lanes past their own
/// count masked: the same operations, in the same order, as one mixture's
/// own.
template <int W> OSL_LANE_TARGET void sampleCosineMixturesAt(CosineMixtures &c) {
  const size_t n = c.size();
  auto forLobes = [&](auto body) {
    for (int j = 0; j < c.maxCount; ++j)
      forLanes<W>(n, [&](size_t m) __attribute__((always_inline)) {
        body(j, m, size_t(j) * n + m);
      });
  };
  // prepare: a cosine lobe's albedo is 1.
  forLobes([&](int j, size_t m, size_t k) __attribute__((always_inline)) {
    Vec3 pw(c.pwx[m], c.pwy[m], c.pwz[m]);
    float p = dot(Vec3(c.wx[k], c.wy[k], c.wz[k]), pw * Vec3(1, 1, 1)) / (pw.x + pw.y + pw.z);
    c.pick[k] = p;
    float total = j == 0 ? 0.0f : c.total[m];
    c.total[m] = j < c.count[m] ? total + p : total;
  });
  forLobes([&](int, size_t m, size_t k) __attribute__((always_inline)) {
    float total = c.total[m];
    bool normalize = (c.absorb[m] == 0 && total > 0) || total > 1;
    c.pick[k] = normalize ? c.pick[k] / total : c.pick[k];
  });
  // pick: the first lobe whose share of [0, 1) holds rx.
  forLobes([&](int j, size_t m, size_t k) __attribute__((always_inline)) {
    float accum = j == 0 ? 0.0f : c.accum[m];
    int chosen = j == 0 ? -1 : c.chosen[m];
    float p = c.pick[k];
    bool open = j < c.count[m] && chosen < 0;
    bool here = open && c.rx[m] < p + accum;
    c.accum[m] = open && !here ? accum + p : accum;
    c.chosen[m] = here ? j : chosen;
  });
  // The picked lobe's sample, weighed by its pick (an empty mixture's
  // lanes, or a zero pdf: no sample).
  forLanes<W>(n, [&](size_t m) __attribute__((always_inline)) {
    int chosen = c.maxCount == 0 ? -1 : c.chosen[m];
    size_t k = size_t(chosen < 0 ? 0 : chosen) * n + m;
    float pick = chosen < 0 ? 1.0f : c.pick[k];
    float rx = std::min((c.rx[m] - c.accum[m]) / pick, 0.99999994f);
    BsdfSample s = sampleCosineLobe(c.orenNayar[k] != 0, Vec3(c.nx[k], c.ny[k], c.nz[k]),
                                    c.sigma[k], Vec3(c.wox[m], c.woy[m], c.woz[m]), rx, c.ry[m]);
    s.weight *= Vec3(c.wx[k], c.wy[k], c.wz[k]) * (1 / pick);
    s.pdf *= pick;
    bool none = chosen < 0 || s.pdf == 0.0f;
    c.chosen[m] = none ? -1 : chosen;
    c.wix[m] = none ? 0.0f : s.wi.x, c.wiy[m] = none ? 0.0f : s.wi.y;
    c.wiz[m] = none ? 0.0f : s.wi.z;
    c.fx[m] = none ? 0.0f : s.weight.x, c.fy[m] = none ? 0.0f : s.weight.y;
    c.fz[m] = none ? 0.0f : s.weight.z;
    c.pdf[m] = none ? 0.0f : s.pdf, c.roughness[m] = none ? 0.0f : s.roughness;
  });
  // mixSample: the other lobes toward the sampled direction.
  forLobes([&](int j, size_t m, size_t k) __attribute__((always_inline)) {
    int chosen = c.chosen[m];
    Vec3 wo(c.wox[m], c.woy[m], c.woz[m]), wi(c.wix[m], c.wiy[m], c.wiz[m]);
    Vec3 weight(c.fx[m], c.fy[m], c.fz[m]);
    float pdf = c.pdf[m];
    BsdfSample b = evalMixtureLobe(c, k, wo, wi);
    misMix(chosen >= 0 && j != chosen && j < c.count[m], weight, pdf, b.weight, b.pdf,
           c.pick[k]);
    c.fx[m] = weight.x, c.fy[m] = weight.y, c.fz[m] = weight.z, c.pdf[m] = pdf;
  });
}

void sampleCosineMixtures(CosineMixtures &mixtures, int width) {
  atWidth(width, [&](auto w) { sampleCosineMixturesAt<decltype(w)::value>(mixtures); });
}

/// ShadingResult::eval of each lane's mixture (its lobes read at the
/// lane's own mixture), one lane loop per lobe as above.
template <int W>
OSL_LANE_TARGET void evalCosineMixturesAt(const CosineMixtures &c, MixtureEvals &e) {
  const size_t n = c.size();
  for (int j = 0; j < c.maxCount; ++j)
    forLanes<W>(e.size(), [&](size_t i) __attribute__((always_inline)) {
      size_t m = size_t(e.mixture[i]), k = size_t(j) * n + m;
      Vec3 wo(c.wox[m], c.woy[m], c.woz[m]), wi(e.wix[i], e.wiy[i], e.wiz[i]);
      Vec3 weight(e.fx[i], e.fy[i], e.fz[i]);
      float pdf = e.pdf[i];
      BsdfSample b = evalMixtureLobe(c, k, wo, wi);
      misMix(j < c.count[m], weight, pdf, b.weight, b.pdf, c.pick[k]);
      e.fx[i] = weight.x, e.fy[i] = weight.y, e.fz[i] = weight.z, e.pdf[i] = pdf;
    });
}

void evalCosineMixtures(const CosineMixtures &mixtures, MixtureEvals &evals, int width) {
  for (std::vector<float> *v : {&evals.fx, &evals.fy, &evals.fz, &evals.pdf})
    v->assign(evals.size(), 0.0f);
  atWidth(width, [&](auto w) { evalCosineMixturesAt<decltype(w)::value>(mixtures, evals); });
}

template <int W>
OSL_LANE_TARGET void evalBackgroundAt(const BackgroundMap::Table &t, const RayBatch &rays,
                                      const int *__restrict which, size_t n,
                                      BackgroundDraws &out) {
  forLanes<W>(n, [&](size_t i) __attribute__((always_inline)) {
    int k = which[i];
    Vec3 dir(rays.dx[k], rays.dy[k], rays.dz[k]);
    float pdf;
    Vec3 value = t.values[tableCell(t, dir, pdf)];
    out.dx[i] = dir.x, out.dy[i] = dir.y, out.dz[i] = dir.z;
    out.r[i] = value.x, out.g[i] = value.y, out.b[i] = value.z;
    out.pdf[i] = pdf;
  });
}

void evalBackground(const BackgroundMap::Table &table, const RayBatch &rays, const int *which,
                    size_t n, BackgroundDraws &out, int width) {
  out.resize(n);
  atWidth(width,
          [&](auto w) { evalBackgroundAt<decltype(w)::value>(table, rays, which, n, out); });
}

/// W sampler points, one per lane.
template <int W>
OSL_LANE_TARGET void drawLanes(const uint32_t *__restrict seed, const uint32_t *__restrict index,
                               float *__restrict x, float *__restrict y, float *__restrict z) {
  for (int l = 0; l < W; ++l) {
    Vec3 p = samplerPoint(seed[l], index[l]);
    x[l] = p.x, y[l] = p.y, z[l] = p.z;
  }
}

template <int W> OSL_LANE_TARGET void drawPointsAt(PointDraws &d) {
  size_t n = d.size(), full = n / W * W;
  for (size_t start = 0; start < full; start += W)
    drawLanes<W>(&d.seed[start], &d.index[start], &d.x[start], &d.y[start], &d.z[start]);
  if (full == n)
    return;
  // The last, partial batch: padded with copies of its last draw.
  uint32_t seed[W], index[W];
  float x[W], y[W], z[W];
  for (int l = 0; l < W; ++l) {
    size_t k = std::min(full + size_t(l), n - 1);
    seed[l] = d.seed[k], index[l] = d.index[k];
  }
  drawLanes<W>(seed, index, x, y, z);
  for (size_t k = full; k < n; ++k)
    d.x[k] = x[k - full], d.y[k] = y[k - full], d.z[k] = z[k - full];
}

void drawPoints(PointDraws &draws, int width) {
  growTo(draws.size(), draws.x, draws.y, draws.z);
  atWidth(width, [&](auto w) { drawPointsAt<decltype(w)::value>(draws); });
}

} // namespace

const LaneKernels &OSL_LANE_KERNELS() {
  static const LaneKernels kernels{OSL_LANE_ISA_NAME, intersect,        drawPoints,
                                   cameraRays,        hitGeometry,      sampleLights,
                                   sampleBackground,  sampleCosineLobes,
                                   evalBackground,    sampleCosineMixtures,
                                   evalCosineMixtures};
  return kernels;
}

} // namespace osl::render
