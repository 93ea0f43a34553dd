//===- Geometry.h - Ray hits, surface areas and light pdfs -----*- C++ -*-===//
#ifndef OSLRENDER_GEOMETRY_H
#define OSLRENDER_GEOMETRY_H

#include "OslRender/Scene.h"

#include <cmath>
#include <limits>
#include <vector>

namespace osl::render {

struct Hit {
  int prim = -1;
  float t = std::numeric_limits<float>::infinity();
};

/// The nearest primitive along o + t d (t > 0). `self` (the primitive the
/// ray leaves) is skipped, except a sphere's far side: a ray refracted into
/// a sphere leaves through it.
Hit intersect(const Scene &scene, Vec3 o, Vec3 d, int self);

/// Rays as structure of arrays: origins, directions and the primitive each
/// leaves (-1: none).
/// Rays as structure of arrays: origin, unit direction, the primitive each
/// leaves (-1: none), and testrender's differentials: the footprint's
/// radius at the origin and its spread per unit of distance.
struct RayBatch {
  std::vector<float> ox, oy, oz, dx, dy, dz, radius, spread;
  std::vector<int> self;
  /// The rays held: columns only grow, so they may be longer. Set by
  /// resize(), which every writer calls first.
  size_t count = 0;
  void push(Vec3 o, Vec3 d, int leaving, float radius = 0, float spread = 0);
  void clear() { resize(0); }
  /// Room for n rays, which set() fills by index (columns keep their
  /// storage when n falls).
  void resize(size_t n);
  void set(size_t i, Vec3 o, Vec3 d, int leaving, float radius, float spread) {
    ox[i] = o.x, oy[i] = o.y, oz[i] = o.z;
    dx[i] = d.x, dy[i] = d.y, dz[i] = d.z;
    this->radius[i] = radius, this->spread[i] = spread;
    self[i] = leaving;
  }
  size_t size() const { return count; }
};

/// intersect() of every ray of `rays` into `hits`, `width` rays at a time
/// (1, 4, 8 or 16 SIMD lanes; the hits are the same at every width).
void intersectBatch(const Scene &scene, const RayBatch &rays, int width, std::vector<Hit> &hits);
/// The same for rays which[0..n) of `rays`, into hits[0..n).
void intersectBatch(const Scene &scene, const RayBatch &rays, const std::vector<int> &which,
                    int width, std::vector<Hit> &hits);

/// What surfacearea() answers (emitters divide their power by it), as
/// testrender answers: a quad's area, a sphere's silhouette (pi r^2).
float surfaceArea(const Primitive &prim);

} // namespace osl::render

#endif // OSLRENDER_GEOMETRY_H
