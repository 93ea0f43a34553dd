//===- PointKdTree.cpp - Nearest points of a cloud ------------------------===//
//
// A balanced kd-tree kept as a permutation of the point indices: the node
// of a range is its middle, split on the axis where the range's points
// spread most. A search keeps the best points found in a max-heap ordered
// by (squared distance, index), so the answer is exactly the maxPoints
// least of those pairs among the points within the radius, whatever the
// tree's shape: the same as a search of every point.
//
//===----------------------------------------------------------------------===//
#include "OslRuntime/PointCloud.h"

#include <algorithm>
#include <cstring>

namespace osl {
namespace {

float coordinate(const std::vector<float> &positions, int32_t point, int axis) {
  return positions[3 * static_cast<size_t>(point) + axis];
}

} // namespace

PointKdTree::PointKdTree(const std::vector<float> &positions) : positions(positions) {
  int32_t n = static_cast<int32_t>(positions.size() / 3);
  order.resize(n);
  for (int32_t i = 0; i < n; ++i)
    order[i] = i;
  axis.assign(n, 0);
  build(0, n);
}

void PointKdTree::build(int32_t begin, int32_t end) {
  if (end - begin <= 1)
    return;
  float lo[3], hi[3];
  for (int a = 0; a < 3; ++a)
    lo[a] = hi[a] = coordinate(positions, order[begin], a);
  for (int32_t i = begin + 1; i < end; ++i)
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], coordinate(positions, order[i], a));
      hi[a] = std::max(hi[a], coordinate(positions, order[i], a));
    }
  int split = 0;
  for (int a = 1; a < 3; ++a)
    if (hi[a] - lo[a] > hi[split] - lo[split])
      split = a;
  int32_t mid = begin + (end - begin) / 2;
  std::nth_element(order.begin() + begin, order.begin() + mid, order.begin() + end,
                   [&](int32_t x, int32_t y) {
                     float cx = coordinate(positions, x, split);
                     float cy = coordinate(positions, y, split);
                     return cx < cy || (cx == cy && x < y);
                   });
  axis[mid] = static_cast<uint8_t>(split);
  build(begin, mid);
  build(mid + 1, end);
}

namespace {
struct FoundLess {
  template <typename F> bool operator()(const F &a, const F &b) const {
    return a.distance2 < b.distance2 || (a.distance2 == b.distance2 && a.index < b.index);
  }
};
} // namespace

void PointKdTree::search(int32_t begin, int32_t end, const float center[3],
                         std::vector<Found> &heap, size_t maxPoints, float &limit2) const {
  if (begin >= end)
    return;
  int32_t mid = begin + (end - begin) / 2;
  int32_t point = order[mid];
  float d[3];
  for (int a = 0; a < 3; ++a)
    d[a] = center[a] - coordinate(positions, point, a);
  Found found{d[0] * d[0] + d[1] * d[1] + d[2] * d[2], point};
  bool full = heap.size() == maxPoints;
  if (full ? FoundLess()(found, heap.front()) : found.distance2 < limit2) {
    if (full) {
      std::pop_heap(heap.begin(), heap.end(), FoundLess());
      heap.back() = found;
    } else {
      heap.push_back(found);
    }
    std::push_heap(heap.begin(), heap.end(), FoundLess());
    if (heap.size() == maxPoints)
      limit2 = heap.front().distance2;
  }
  float offset = d[axis[mid]];
  bool leftNear = offset <= 0;
  search(leftNear ? begin : mid + 1, leftNear ? mid : end, center, heap, maxPoints, limit2);
  // The far side can hold a point as near as the splitting plane (equal
  // distances count: a lower index wins).
  full = heap.size() == maxPoints;
  if (full ? offset * offset <= limit2 : offset * offset < limit2)
    search(leftNear ? mid + 1 : begin, leftNear ? end : mid, center, heap, maxPoints, limit2);
}

int32_t PointKdTree::nearest(const float center[3], float radius, int32_t maxPoints,
                             std::vector<int32_t> &indices, std::vector<float> &distance2) const {
  indices.clear();
  distance2.clear();
  if (maxPoints <= 0 || !(radius > 0) || order.empty())
    return 0;
  std::vector<Found> heap;
  heap.reserve(std::min<size_t>(static_cast<size_t>(maxPoints), order.size()));
  float limit2 = radius * radius;
  search(0, static_cast<int32_t>(order.size()), center, heap, static_cast<size_t>(maxPoints),
         limit2);
  std::sort_heap(heap.begin(), heap.end(), FoundLess());
  for (const Found &f : heap) {
    indices.push_back(f.index);
    distance2.push_back(f.distance2);
  }
  return static_cast<int32_t>(heap.size());
}

} // namespace osl
