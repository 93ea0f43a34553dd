//===- Closures.cpp - The closure arena and the kernels' entry points -----===//
#include "OslAbi/EntryPoints.h"
#include "OslRuntime/Closure.h"

using namespace osl;

namespace {

/// Word offsets of every closure's parameters, computed once.
struct ParamOffsets {
  int32_t offset[kClosureCount][kMaxClosureParams + 1] = {};
  int32_t words[kClosureCount] = {};
  ParamOffsets() {
    for (int32_t id = 0; id < kClosureCount; ++id) {
      char kinds[kMaxClosureParams];
      int32_t n = closureParamKinds(id, kinds, kMaxClosureParams);
      int32_t words = 0;
      for (int32_t i = 0; i < n; ++i) {
        offset[id][i] = words;
        words += closureParamRows(kinds[i]);
      }
      offset[id][n] = words;
      this->words[id] = words;
    }
  }
};

const ParamOffsets &paramOffsets() {
  static const ParamOffsets offsets;
  return offsets;
}

/// Words the parameters of closure `id` take.
int32_t paramWords(int32_t id) { return paramOffsets().words[id]; }

} // namespace

int32_t ClosurePrimitive::offset(int32_t i) const { return paramOffsets().offset[id][i]; }


ClosureArena &osl::threadClosureArena() {
  static thread_local ClosureArena arena;
  return arena;
}

// One lane's component and product are the lane versions at width 1.
int32_t ClosureArena::component(int32_t id, const uint32_t *params, int32_t count) {
  int32_t handle;
  componentLanes(id, reinterpret_cast<const int32_t *>(params), count, 1, 1, &handle);
  return handle;
}

int32_t ClosureArena::mul(int32_t closure, const float weight[3]) {
  int32_t handle;
  mulLanes(&closure, weight, 1, 1, &handle);
  return handle;
}

int32_t ClosureArena::add(int32_t a, int32_t b) {
  if (a == 0)
    return b;
  if (b == 0)
    return a;
  nodes.push_back({kAdd, a, b, {0, 0, 0}});
  return int32_t(nodes.size());
}

void ClosureArena::componentLanes(int32_t id, const int32_t *params, int32_t count,
                                  int32_t width, uint32_t laneMask, int32_t *result) {
  for (int32_t lane = 0; lane < width; ++lane) {
    if (!(laneMask >> lane & 1)) {
      result[lane] = 0;
      continue;
    }
    nodes.push_back({kPrimitive, id, int32_t(words.size()), {1, 1, 1}});
    made |= idBit(id);
    const int32_t *from = params + lane;
    for (int32_t w = 0; w < count; ++w, from += width)
      words.push_back(uint32_t(*from));
    result[lane] = int32_t(nodes.size());
  }
}

void ClosureArena::mulLanes(const int32_t *closures, const float *weights, int32_t width,
                            uint32_t laneMask, int32_t *result) {
  for (int32_t lane = 0; lane < width; ++lane) {
    result[lane] = 0;
    if (!(laneMask >> lane & 1) || closures[lane] == 0)
      continue;
    float w0 = weights[lane], w1 = weights[width + lane], w2 = weights[2 * width + lane];
    // A zero weight (either sign) leaves nothing, as OSL's closure product.
    if (w0 == 0 && w1 == 0 && w2 == 0)
      continue;
    nodes.push_back({kMul, closures[lane], 0, {w0, w1, w2}});
    result[lane] = int32_t(nodes.size());
  }
}

void ClosureArena::flatten(int32_t handle, std::vector<ClosurePrimitive> &out) const {
  forEachPrimitive(handle, [&](const ClosurePrimitive &p) { out.push_back(p); });
}

//===----------------------------------------------------------------------===//
// Kernel entry points (ClosureCall.h)
//===----------------------------------------------------------------------===//

extern "C" void osl_rt_closure_component(int32_t id, int32_t *rows, int32_t width,
                                         uint32_t laneMask) {
  int32_t count = paramWords(id);
  threadClosureArena().componentLanes(id, rows, count, width, laneMask, rows + count * width);
}

extern "C" void osl_rt_closure_mul(int32_t *rows, int32_t width, uint32_t laneMask) {
  threadClosureArena().mulLanes(rows, reinterpret_cast<const float *>(rows + width), width,
                                laneMask, rows + 4 * width);
}

extern "C" void osl_rt_closure_add(int32_t *rows, int32_t width, uint32_t laneMask) {
  ClosureArena &arena = threadClosureArena();
  for (int32_t lane = 0; lane < width; ++lane)
    rows[2 * width + lane] =
        laneMask >> lane & 1 ? arena.add(rows[lane], rows[width + lane]) : 0;
}
