//===- LaneKernels.h - The renderer's SIMD loops, per instruction set -----===//
//
// Loops over W lanes (W the shading width: 1, 4, 8 or 16) in which every
// lane computes what one ray or path computes alone, in the same order.
// Each is compiled for plain x86-64, AVX2 and AVX-512 (the render library
// is built with -ffp-contract=off, so no instruction set fuses a multiply
// and add another would round twice) and the widest the CPU runs is chosen
// once: results are the same at every width and on every machine.
//
//===----------------------------------------------------------------------===//
#ifndef OSLRENDER_LANEKERNELS_H
#define OSLRENDER_LANEKERNELS_H

#include "OslRender/Geometry.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace osl::render {

/// Sampler points to draw, as structure of arrays: lane i gets point
/// `call[i]` of the path seeded (`key[i]`, `index[i]`) into x, y, z.
struct PointDraws {
  std::vector<uint32_t> key, index, call;
  std::vector<float> x, y, z;
  void clear();
  void push(uint32_t key, uint32_t index, uint32_t call);
  size_t size() const { return call.size(); }
};

struct LaneKernels {
  const char *isa;
  /// intersect() of each ray of `rays` into `hits`, `width` at a time.
  void (*intersect)(const Scene &scene, const RayBatch &rays, int width,
                    std::vector<Hit> &hits);
  /// Fills x, y, z of every draw, `width` at a time.
  void (*drawPoints)(PointDraws &draws, int width);
};

/// The kernels of the widest instruction set this CPU runs, or those the
/// environment's OSL_MLIR_RENDER_ISA names (generic, avx2, avx512), to
/// compare them.
const LaneKernels &laneKernels();

/// Every instruction set's kernels this CPU runs, plain x86-64 first.
std::vector<const LaneKernels *> laneKernelsThisCpuRuns();

const LaneKernels &genericLaneKernels();
const LaneKernels &avx2LaneKernels();
const LaneKernels &avx512LaneKernels();

} // namespace osl::render

#endif // OSLRENDER_LANEKERNELS_H
