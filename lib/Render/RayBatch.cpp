//===- RayBatch.cpp - Rays intersected a SIMD batch at a time --------------===//
//
// The rays of a batch are tested against each primitive together: one lane
// per ray, a fixed width per instantiation, the lanes' branches turned into
// selects so the compiler vectorizes each test (built with -fno-math-errno
// so sqrt is an instruction). Every lane computes exactly what a ray tested
// alone computes, in the same order, so hits are the same at every width.
//
//===----------------------------------------------------------------------===//
#include "OslRender/Geometry.h"

#include <algorithm>
#include <cmath>

namespace osl::render {
namespace {

/// A batch of W rays, padded past `count` with copies of the last one.
template <int W> struct RayLanes {
  float ox[W], oy[W], oz[W], dx[W], dy[W], dz[W];
  int self[W];
};

/// Distance along each lane's ray to sphere `s` (primitive `index`), or -1;
/// a ray leaving the sphere (self) keeps only the far root.
template <int W>
void sphereLanes(const Primitive &s, int index, const RayLanes<W> &r, float *t) {
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
void quadLanes(const Primitive &q, int index, const RayLanes<W> &r, float *t) {
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
void intersectLanes(const Scene &scene, const RayLanes<W> &r, float *bestT, int *bestPrim) {
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
void intersectBatchAt(const Scene &scene, const RayBatch &rays, std::vector<Hit> &hits) {
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

} // namespace

void RayBatch::push(Vec3 o, Vec3 d, int leaving) {
  ox.push_back(o.x), oy.push_back(o.y), oz.push_back(o.z);
  dx.push_back(d.x), dy.push_back(d.y), dz.push_back(d.z);
  self.push_back(leaving);
}

void RayBatch::clear() {
  for (std::vector<float> *v : {&ox, &oy, &oz, &dx, &dy, &dz})
    v->clear();
  self.clear();
}

void intersectBatch(const Scene &scene, const RayBatch &rays, int width,
                    std::vector<Hit> &hits) {
  hits.resize(rays.size());
  switch (width) {
  case 16: return intersectBatchAt<16>(scene, rays, hits);
  case 8: return intersectBatchAt<8>(scene, rays, hits);
  case 4: return intersectBatchAt<4>(scene, rays, hits);
  default: return intersectBatchAt<1>(scene, rays, hits);
  }
}

Hit intersect(const Scene &scene, Vec3 o, Vec3 d, int self) {
  RayBatch one;
  one.push(o, d, self);
  std::vector<Hit> hit;
  intersectBatch(scene, one, 1, hit);
  return hit[0];
}

} // namespace osl::render
