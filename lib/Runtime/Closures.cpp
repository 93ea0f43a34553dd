//===- Closures.cpp - The closure arena and the kernels' entry points -----===//
#include "OslAbi/EntryPoints.h"
#include "OslRuntime/Closure.h"

#include <algorithm>

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

int32_t ClosureArena::component(int32_t id, const uint32_t *params, int32_t count) {
  int32_t first = int32_t(words.size());
  // A resize and a copy of known words: insert's general path costs more
  // than the copy, once per lane of every closure call.
  words.resize(words.size() + size_t(count));
  std::copy_n(params, count, words.data() + first);
  nodes.push_back({kPrimitive, id, first, {1, 1, 1}});
  return int32_t(nodes.size());
}

int32_t ClosureArena::mul(int32_t closure, const float weight[3]) {
  // A zero weight (either sign) leaves nothing, as OSL's closure product.
  if (closure == 0 || (weight[0] == 0 && weight[1] == 0 && weight[2] == 0))
    return 0;
  nodes.push_back({kMul, closure, 0, {weight[0], weight[1], weight[2]}});
  return int32_t(nodes.size());
}

int32_t ClosureArena::add(int32_t a, int32_t b) {
  if (a == 0)
    return b;
  if (b == 0)
    return a;
  nodes.push_back({kAdd, a, b, {0, 0, 0}});
  return int32_t(nodes.size());
}

void ClosureArena::flatten(int32_t handle, std::vector<ClosurePrimitive> &out) const {
  forEachPrimitive(handle, [&](const ClosurePrimitive &p) { out.push_back(p); });
}

//===----------------------------------------------------------------------===//
// Kernel entry points (ClosureCall.h)
//===----------------------------------------------------------------------===//

extern "C" void osl_rt_closure_component(int32_t id, int32_t *rows, int32_t width,
                                         uint32_t laneMask) {
  ClosureArena &arena = threadClosureArena();
  int32_t count = paramWords(id);
  int32_t *result = rows + count * width;
  uint32_t params[3 * kMaxClosureParams];
  for (int32_t lane = 0; lane < width; ++lane) {
    if (!(laneMask >> lane & 1)) {
      result[lane] = 0;
      continue;
    }
    for (int32_t w = 0; w < count; ++w)
      params[w] = uint32_t(rows[w * width + lane]);
    result[lane] = arena.component(id, params, count);
  }
}

extern "C" void osl_rt_closure_mul(int32_t *rows, int32_t width, uint32_t laneMask) {
  ClosureArena &arena = threadClosureArena();
  const float *weights = reinterpret_cast<const float *>(rows + width);
  for (int32_t lane = 0; lane < width; ++lane) {
    if (!(laneMask >> lane & 1)) {
      rows[4 * width + lane] = 0;
      continue;
    }
    const float w[3] = {weights[lane], weights[width + lane], weights[2 * width + lane]};
    rows[4 * width + lane] = arena.mul(rows[lane], w);
  }
}

extern "C" void osl_rt_closure_add(int32_t *rows, int32_t width, uint32_t laneMask) {
  ClosureArena &arena = threadClosureArena();
  for (int32_t lane = 0; lane < width; ++lane)
    rows[2 * width + lane] =
        laneMask >> lane & 1 ? arena.add(rows[lane], rows[width + lane]) : 0;
}
