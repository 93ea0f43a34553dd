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
  case 16: return fn(std::integral_constant<int, 16>());
  case 8: return fn(std::integral_constant<int, 8>());
  case 4: return fn(std::integral_constant<int, 4>());
  default: return fn(std::integral_constant<int, 1>());
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
OSL_LANE_TARGET void intersectAt(const Scene &scene, const RayBatch &rays,
                                 std::vector<Hit> &hits) {
  RayLanes<W> r;
  float t[W];
  int prim[W];
  for (size_t start = 0; start < rays.size(); start += W) {
    int count = int(std::min<size_t>(W, rays.size() - start));
    for (int l = 0; l < W; ++l) {
      size_t k = start + size_t(std::min(l, count - 1));
      r.ox[l] = rays.ox[k], r.oy[l] = rays.oy[k], r.oz[l] = rays.oz[k];
      r.dx[l] = rays.dx[k], r.dy[l] = rays.dy[k], r.dz[l] = rays.dz[k];
      r.self[l] = rays.self[k];
    }
    intersectLanes<W>(scene, r, t, prim);
    for (int l = 0; l < count; ++l)
      hits[start + size_t(l)] = Hit{prim[l], t[l]};
  }
}

void intersect(const Scene &scene, const RayBatch &rays, int width, std::vector<Hit> &hits) {
  hits.resize(rays.size());
  atWidth(width, [&](auto w) { intersectAt<decltype(w)::value>(scene, rays, hits); });
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
  static const LaneKernels kernels{OSL_LANE_ISA_NAME, intersect, drawPoints};
  return kernels;
}

} // namespace osl::render
