//===- LibraryBuilders.h - Transforms and splines on lane values -*- C++ -*-===//
//
// Like LaneMath.h, these build arith ops on lane values (f32 or
// vector<W x f32>) so one lowering serves uniform and varying operands.
//
//===----------------------------------------------------------------------===//
#ifndef OSLLANES_LIBRARYBUILDERS_H
#define OSLLANES_LIBRARYBUILDERS_H

#include "OslDialect/OslDialect.h"
#include "mlir/IR/Builders.h"
#include "mlir/Support/LogicalResult.h"

#include <array>
#include <optional>

namespace mlir::osl {

/// A 4x4 matrix applied to row vectors (p' = p * M), row-major.
using Matrix44 = std::array<double, 16>;

/// The matrix from space `from` to space `to`, for the fixed spaces of
/// testshade ("common", "world", "camera", "shader", "object", "myspace"),
/// or nullopt for a name it does not know.
std::optional<Matrix44> namedSpaceTransform(StringRef from, StringRef to);

/// Applies `m` to a point (with translation), a vector (without) or a
/// normal (by the inverse transpose), given as three lane values.
std::array<Value, 3> buildTransform(OpBuilder &b, Location loc,
                                    const Matrix44 &m, TransformKind kind,
                                    std::array<Value, 3> p);

/// OSL's spline(basis, x, knots): `knots[i]` holds the components of knot
/// i (one lane value for float knots, three for triples); the result has
/// as many components. `count` (a lane i32 shaped like x, or null for all)
/// limits the knots used. Fails for a basis it does not implement.
FailureOr<SmallVector<Value>> buildSpline(OpBuilder &b, Location loc,
                                          SplineBasis basis, Value x, Value count,
                                          ArrayRef<SmallVector<Value>> knots);

/// OSL's splineinverse(basis, y, knots) over float knots (see buildSpline).
FailureOr<Value> buildSplineInverse(OpBuilder &b, Location loc, SplineBasis basis,
                                    Value y, Value count,
                                    ArrayRef<SmallVector<Value>> knots);

} // namespace mlir::osl

#endif // OSLLANES_LIBRARYBUILDERS_H
