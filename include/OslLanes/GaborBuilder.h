//===- GaborBuilder.h - Emit OSL's Gabor noise as lane ops -------*- C++ -*-===//
//
// OSL's sparse-convolution Gabor noise (Lagae et al. 2009, as OSL 1.13
// implements it) built from arith/math/scf ops on lane values: f32 for a
// uniform point, vector<W x f32> for a varying one. The per-cell Poisson
// impulse count differs between lanes, so each cell runs scf.while loops
// that carry a lane mask; the 27 cells are one scf.for. The random draws,
// cell seeds and the comparisons that decide which impulses count are
// computed exactly as OSL does, so every width gives the same result.
//
//===----------------------------------------------------------------------===//
#ifndef OSLLANES_GABORBUILDER_H
#define OSLLANES_GABORBUILDER_H

#include "mlir/IR/Builders.h"
#include "mlir/IR/Location.h"
#include "mlir/IR/Value.h"

#include <array>
#include <optional>

namespace mlir::osl {

/// The noise options of noise("gabor", ...). Each Value is a uniform (scalar)
/// lane value or null for OSL's default: anisotropic (i32) 0, direction
/// (three f32) (1, 0, 0), bandwidth (f32) 1, impulses (f32) 16, do_filter
/// (i32) 1.
struct GaborOptions {
  Value anisotropic;
  std::array<Value, 3> direction;
  Value bandwidth;
  Value impulses;
  Value doFilter;
};

/// `options` with OSL's default, as a constant built at `b`'s insertion
/// point, for each option left null.
GaborOptions withGaborDefaults(OpBuilder &b, Location loc, GaborOptions options);

/// The lookup point of one Gabor evaluation, always 3D (OSL slices 1D and
/// 2D domains as (x, 0, 0) and (x, y, 0) and ignores a 4th coordinate).
struct GaborPoint {
  std::array<Value, 3> p;
  /// Dx and Dy of p, for the filter; null when the caller has none (then
  /// the noise is not filtered, as OSL does when the derivatives vanish).
  std::optional<std::array<Value, 3>> dPdx, dPdy;
  /// pnoise's period per component (null: not periodic).
  std::optional<std::array<Value, 3>> period;
};

/// OSL's gabor()/pgabor() (one channel, seed 0) and gabor3()/pgabor3()
/// (three channels, seeds 0, 1, 2). All point values share one lane type;
/// the results have that type.
Value buildGaborFloat(OpBuilder &b, Location loc, const GaborPoint &point,
                      const GaborOptions &options);
std::array<Value, 3> buildGaborTriple(OpBuilder &b, Location loc,
                                      const GaborPoint &point,
                                      const GaborOptions &options);

} // namespace mlir::osl

#endif // OSLLANES_GABORBUILDER_H
