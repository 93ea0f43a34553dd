//===- Closure.h - Closure storage and the renderer's view -------*- C++ -*-===//
//
// Each shading thread has one closure arena. A renderer resets it before a
// batch, runs the kernel, then reads each lane's `Ci` handle (a closure
// output's row holds handles, as the bits of its floats) and flattens it
// into (primitive, weight, parameters) entries. Nodes and parameters live
// in two vectors that keep their capacity across resets, so shading
// allocates nothing per point once the arena has grown to the largest
// batch.
//
//===----------------------------------------------------------------------===//
#ifndef OSLRUNTIME_CLOSURE_H
#define OSLRUNTIME_CLOSURE_H

#include "OslAbi/Closures.h"

#include <array>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace osl {

/// One primitive of a flattened closure: which closure, its accumulated
/// weight, and its parameters in closureParamKinds order.
struct ClosurePrimitive {
  int32_t id = -1;
  std::array<float, 3> weight{};
  const uint32_t *words = nullptr; // the parameters' 32-bit words

  /// Word offset of parameter `i` (triples take three words).
  int32_t offset(int32_t i) const;
  float floatParam(int32_t i) const {
    float f;
    std::memcpy(&f, words + offset(i), 4);
    return f;
  }
  std::array<float, 3> tripleParam(int32_t i) const {
    std::array<float, 3> t;
    std::memcpy(t.data(), words + offset(i), 12);
    return t;
  }
  int32_t intParam(int32_t i) const { return int32_t(words[offset(i)]); }
  /// A string parameter's handle (stringText in StringCall.h gives its text).
  int32_t stringParam(int32_t i) const { return int32_t(words[offset(i)]); }
  /// A closure parameter (layer's top and base): a handle to flatten.
  int32_t closureParam(int32_t i) const { return int32_t(words[offset(i)]); }
  const char *name() const { return kClosures[id].name; }
};

class ClosureArena {
public:
  /// Forgets every node (keeps the storage). Handles issued before are void.
  void reset() {
    nodes.clear();
    words.clear();
    made = 0;
  }
  /// A primitive of closure `id` with weight 1; `params` holds its words.
  int32_t component(int32_t id, const uint32_t *params, int32_t count);
  /// `closure` scaled by `weight`; the empty closure (0) when either is.
  int32_t mul(int32_t closure, const float weight[3]);
  /// The sum of two closures (an empty side gives the other).
  int32_t add(int32_t a, int32_t b);
  /// component() and mul() for each lane of a batch, in lane order (the
  /// same nodes as lane by lane, with the arena grown once): lane l's
  /// operands at [row * width + l]; lanes outside `laneMask` get 0.
  void componentLanes(int32_t id, const int32_t *params, int32_t count, int32_t width,
                      uint32_t laneMask, int32_t *result);
  void mulLanes(const int32_t *closures, const float *weights, int32_t width, uint32_t laneMask,
                int32_t *result);
  /// Appends the primitives of `handle` to `out`, depth first, with their
  /// weights multiplied through. Deterministic: the same tree gives the
  /// same list whatever the batch width that built it.
  void flatten(int32_t handle, std::vector<ClosurePrimitive> &out) const;
  /// Calls visit(const ClosurePrimitive &) for each primitive of `handle`,
  /// in flatten's order and with its weights, without building the list.
  template <typename Visit> void forEachPrimitive(int32_t handle, Visit &&visit) const {
    const float one[3] = {1, 1, 1};
    visitScaled(handle, one, visit);
  }
  size_t nodeCount() const { return nodes.size(); }
  /// Whether a component of closure `id` was made since the last reset (a
  /// reader can skip a pass no such component would change).
  bool madeAny(uint64_t idBits) const { return made & idBits; }
  static constexpr uint64_t idBit(int32_t id) { return uint64_t(1) << id; }

private:
  enum Kind : int32_t { kPrimitive, kMul, kAdd };
  struct Node {
    Kind kind;
    int32_t id;   // kPrimitive: the closure; kMul, kAdd: the first operand
    int32_t b;    // kPrimitive: first word of its parameters; kAdd: the second operand
    float w[3];   // kMul: the weight
  };
  template <typename Visit>
  void visitScaled(int32_t handle, const float w[3], Visit &visit) const {
    // Handles come from kernels; one outside the arena is a bug upstream,
    // but reading it must not crash the renderer.
    if (handle <= 0 || size_t(handle) > nodes.size())
      return;
    const Node &n = nodes[size_t(handle) - 1];
    switch (n.kind) {
    case kPrimitive: {
      ClosurePrimitive p;
      p.id = n.id;
      p.weight = {w[0], w[1], w[2]};
      p.words = words.data() + n.b;
      const ClosurePrimitive &primitive = p;
      visit(primitive);
      return;
    }
    case kMul: {
      const float scaled[3] = {w[0] * n.w[0], w[1] * n.w[1], w[2] * n.w[2]};
      visitScaled(n.id, scaled, visit);
      return;
    }
    case kAdd:
      visitScaled(n.id, w, visit);
      visitScaled(n.b, w, visit);
      return;
    }
  }
  std::vector<Node> nodes;
  std::vector<uint32_t> words;
  /// idBit of each closure a component was made of since reset. Primitive
  /// nodes are made in componentLanes alone (nodes are private), so a
  /// reader that skips a pass on it skips nothing that was made.
  uint64_t made = 0;
  static_assert(kClosureCount <= 64, "one bit per closure");
};

/// This thread's arena (the one compiled kernels build in).
ClosureArena &threadClosureArena();

/// The closure handle a kernel stored in an output row's float.
inline int32_t closureHandleFromOutput(float value) {
  int32_t h;
  std::memcpy(&h, &value, 4);
  return h;
}

} // namespace osl

#endif // OSLRUNTIME_CLOSURE_H
