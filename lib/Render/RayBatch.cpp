//===- RayBatch.cpp - Rays intersected a SIMD batch at a time --------------===//
//
// The rays of a batch are tested against each primitive together, one lane
// per ray (LaneKernelsImpl.h): the hits are the same at every width.
//
//===----------------------------------------------------------------------===//
#include "LaneKernels.h"

namespace osl::render {

void RayBatch::push(Vec3 o, Vec3 d, int leaving, float r, float s) {
  resize(size() + 1);
  set(size() - 1, o, d, leaving, r, s);
}

void RayBatch::resize(size_t n) {
  growTo(n, ox, oy, oz, dx, dy, dz, radius, spread, self);
  count = n;
}

void intersectBatch(const Scene &scene, const RayBatch &rays, int width, std::vector<Hit> &hits) {
  laneKernels().intersect(scene, rays, nullptr, rays.size(), width, hits);
}

void intersectBatch(const Scene &scene, const RayBatch &rays, const std::vector<int> &which,
                    int width, std::vector<Hit> &hits) {
  laneKernels().intersect(scene, rays, which.data(), which.size(), width, hits);
}

Hit intersect(const Scene &scene, Vec3 o, Vec3 d, int self) {
  RayBatch one;
  one.push(o, d, self);
  std::vector<Hit> hit;
  intersectBatch(scene, one, 1, hit);
  return hit[0];
}

} // namespace osl::render
