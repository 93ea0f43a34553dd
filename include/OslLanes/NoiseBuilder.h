//===- NoiseBuilder.h - Emit OSL noise as arith ops --------------*- C++ -*-===//
//
// Builds OSL's noise functions out of `arith` (plus `math.floor`) ops, for
// scalar f32 or vector<W x f32> operands, so that the lowering of the noise
// ops is inlined and width-generic. The emitted computation mirrors
// osl::ref (OslReference/Noise.h) operation by operation and is
// bit-identical to it at every width: no FMA, no fast-math flags.
//
//===----------------------------------------------------------------------===//
#ifndef OSLLANES_NOISEBUILDER_H
#define OSLLANES_NOISEBUILDER_H

#include "mlir/IR/Builders.h"
#include "mlir/IR/Location.h"
#include "mlir/IR/Value.h"
#include "mlir/IR/ValueRange.h"
#include "llvm/ADT/ArrayRef.h"
#include "llvm/ADT/StringRef.h"

#include <array>
#include <optional>

#include "OslDialect/OslDialect.h"

namespace mlir::osl {

/// `kind` is any NoiseKind but gabor (GaborBuilder.h builds that one).
/// Every Value in `coords` (1 to 4 of them, OSL's domain order x, y, z, w)
/// has the same type: f32 or vector<W x f32>. Results have that same type.
/// Emits only arith ops (vector constants as splat arith.constant) and
/// math.floor at b's insertion point; the Math dialect must be loaded.
mlir::Value buildNoiseFloat(mlir::OpBuilder &b, mlir::Location loc,
                            NoiseKind kind, mlir::ValueRange coords);
std::array<mlir::Value, 3> buildNoiseTriple(mlir::OpBuilder &b,
                                            mlir::Location loc, NoiseKind kind,
                                            mlir::ValueRange coords);

/// Periodic noise (OSL's pnoise): `periods` has one value per coordinate, of
/// the same type. Perlin/UPerlin wrap the integer lattice (periods are
/// floored and clamped to at least 1); Cell/Hash wrap the coordinates.
/// Returns a null Value (or nulls) for Simplex/USimplex, which OSL does not
/// define as periodic.
mlir::Value buildPeriodicNoiseFloat(mlir::OpBuilder &b, mlir::Location loc,
                                    NoiseKind kind, mlir::ValueRange coords,
                                    mlir::ValueRange periods);
std::array<mlir::Value, 3>
buildPeriodicNoiseTriple(mlir::OpBuilder &b, mlir::Location loc,
                         NoiseKind kind, mlir::ValueRange coords,
                         mlir::ValueRange periods);

/// OSL's inthash (Bob Jenkins' lookup3) of 1 to 5 keys, all scalars or all
/// vector<W x ...>; an f32 key hashes by its bits (osl.hash, hashnoise).
/// The cell seeds of Gabor noise use it like cellnoise.
mlir::Value buildIntHash(mlir::OpBuilder &b, mlir::Location loc,
                         llvm::ArrayRef<mlir::Value> keys);

} // namespace mlir::osl

#endif // OSLLANES_NOISEBUILDER_H
