//===- GlobalsLayout.h - Batched shader globals, structure of arrays ------===//
//
// One batch of W shading points stores every shader global as rows of W
// floats: a triple takes three consecutive rows (x, y, z), a float one row.
// The compiler (the front end, osl-convert-to-vector) and the runtime both
// read this table, so a global's row index is defined once, here.
//
//===----------------------------------------------------------------------===//
#ifndef OSLABI_GLOBALSLAYOUT_H
#define OSLABI_GLOBALSLAYOUT_H

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <string_view>

namespace osl {

/// A shader global: its OSL name, first row, and number of float rows.
struct GlobalSlot {
  std::string_view name;
  int32_t row;
  int32_t rows; // 3 for point/vector/normal, 1 for float
};

// Derivative rows (dPdx, dudx, ...) follow the values so that a later
// derivatives pass can read them; testshade's conventions fill them.
inline constexpr GlobalSlot kGlobalSlots[] = {
    {"P", 0, 3},       {"I", 3, 3},       {"N", 6, 3},      {"Ng", 9, 3},
    {"dPdu", 12, 3},   {"dPdv", 15, 3},   {"dPdz", 18, 3},  {"dPdtime", 21, 3},
    {"Ps", 24, 3},     {"dPdx", 27, 3},   {"dPdy", 30, 3},  {"u", 33, 1},
    {"v", 34, 1},      {"dudx", 35, 1},   {"dudy", 36, 1},  {"dvdx", 37, 1},
    {"dvdy", 38, 1},   {"time", 39, 1},   {"dtime", 40, 1}, {"surfacearea", 41, 1},
    {"backfacing", 42, 1},
    // The ray's types as bits (kRayTypes), as a float: not an OSL global
    // (raytype() reads it where the renderer decides per point).
    {"raytype", 43, 1},
    // Nonzero where the renderer's transform flips handedness:
    // calculatenormal() then crosses its derivatives the other way round.
    {"flipHandedness", 44, 1},
    // The derivatives of I: not OSL globals, but what Dx(I) and Dy(I) read
    // (a renderer's ray differentials; 0 on a grid, as testshade's).
    {"dIdx", 45, 3},   {"dIdy", 48, 3},
};

/// Number of float rows in one batch of globals (multiply by the width).
inline constexpr int32_t kGlobalRows = 51;

/// The ray types raytype() names, as bits of the "raytype" row. A renderer
/// (osl-run --scene) sets them per point; osl-run on a grid shades one ray
/// type, known when the shader is compiled.
struct RayType {
  std::string_view name;
  int32_t bit;
};
inline constexpr RayType kRayTypes[] = {
    {"camera", 1},   {"shadow", 2},  {"reflection", 4},  {"refraction", 8},
    {"diffuse", 16}, {"glossy", 32}, {"subsurface", 64}, {"displacement", 128},
};

/// The bit of ray type `name`, or 0 for a name no ray has.
inline constexpr int32_t rayTypeBit(std::string_view name) {
  for (const RayType &t : kRayTypes)
    if (t.name == name)
      return t.bit;
  return 0;
}

/// The slot of a global by OSL name, or nullptr.
inline const GlobalSlot *findGlobal(std::string_view name) {
  for (const GlobalSlot &s : kGlobalSlots)
    if (s.name == name)
      return &s;
  return nullptr;
}

/// Copies the first n lanes of one batch row. A full batch is a copy of
/// known size (a few vector moves), not a call of memmove per row and
/// batch: the grid and the renderer stage every batch's rows this way.
inline void copyRowLanes(float *to, const float *from, int n) {
  switch (n) {
  case 16: std::memcpy(to, from, 16 * sizeof(float)); break;
  case 8: std::memcpy(to, from, 8 * sizeof(float)); break;
  case 4: std::memcpy(to, from, 4 * sizeof(float)); break;
  case 1: *to = *from; break;
  default: std::copy_n(from, n, to);
  }
}

/// The kernel the compiler emits for one batch at width W:
///   void kernel(const float *globals,  // kGlobalRows x W floats
///               float *outputs,        // (sum of output channels) x W floats
///               int32_t nactive);      // lanes [0, nactive) are shaded
/// Outputs are rows of W floats, one row per channel, in declaration order
/// of the shader's output parameters; int outputs are stored as float values.
/// Lanes >= nactive are never written.
using BatchKernel = void (*)(const float *globals, float *outputs,
                             int32_t nactive);

} // namespace osl

#endif // OSLABI_GLOBALSLAYOUT_H
