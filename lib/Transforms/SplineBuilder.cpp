//===- SplineBuilder.cpp - OSL spline() on lane values --------------------===//
//
// OSL's spline: x is clamped to [0,1] and split into nsegs = (n-4)/step + 1
// segments; segment s uses knots [s*step, s*step+4) weighted by the basis
// matrix, then evaluated by Horner's rule. The knot window is chosen per
// lane with selects, so a varying x over uniform knots stays vector code.
//
//===----------------------------------------------------------------------===//
#include "OslTransforms/LaneMath.h"
#include "OslTransforms/LibraryBuilders.h"

#include "mlir/Dialect/Arith/IR/Arith.h"
#include "mlir/Dialect/Vector/IR/VectorOps.h"

using namespace mlir;
using namespace mlir::osl;

namespace {

struct SplineBasis {
  double m[4][4];
  int step;
};

std::optional<SplineBasis> lookupBasis(StringRef name) {
  if (name == "catmull-rom")
    return SplineBasis{{{-0.5, 1.5, -1.5, 0.5},
                        {1, -2.5, 2, -0.5},
                        {-0.5, 0, 0.5, 0},
                        {0, 1, 0, 0}},
                       1};
  if (name == "bezier")
    return SplineBasis{{{-1, 3, -3, 1}, {3, -6, 3, 0}, {-3, 3, 0, 0}, {1, 0, 0, 0}}, 3};
  if (name == "bspline")
    return SplineBasis{{{-1.0 / 6, 3.0 / 6, -3.0 / 6, 1.0 / 6},
                        {3.0 / 6, -6.0 / 6, 3.0 / 6, 0},
                        {-3.0 / 6, 0, 3.0 / 6, 0},
                        {1.0 / 6, 4.0 / 6, 1.0 / 6, 0}},
                       1};
  if (name == "hermite")
    return SplineBasis{{{2, 1, -2, 1}, {-3, -2, 3, -1}, {0, 1, 0, 0}, {1, 0, 0, 0}}, 2};
  if (name == "linear")
    return SplineBasis{{{0, 0, 0, 0}, {0, 0, 0, 0}, {0, -1, 1, 0}, {0, 1, 0, 0}}, 1};
  return std::nullopt;
}

} // namespace

FailureOr<SmallVector<Value>>
mlir::osl::buildSpline(OpBuilder &b, Location loc, StringRef basisName,
                       Value x, ArrayRef<SmallVector<Value>> knots) {
  std::optional<SplineBasis> basis = lookupBasis(basisName);
  int n = knots.size();
  if (!basis || n < 4)
    return failure();
  int nsegs = (n - 4) / basis->step + 1;
  Type intLane = lane::withElement(x.getType(), b.getI32Type());

  x = lane::clamp(b, loc, {x, lane::constantLike(b, loc, x, 0),
                           lane::constantLike(b, loc, x, 1)});
  Value segX = b.create<arith::MulFOp>(loc, x, lane::constantLike(b, loc, x, nsegs));
  Value seg = b.create<arith::FPToSIOp>(loc, intLane, segX);
  seg = lane::min(b, loc, {seg, lane::constant(b, loc, intLane, nsegs - 1)});
  segX = b.create<arith::SubFOp>(loc, segX,
                                 b.create<arith::SIToFPOp>(loc, x.getType(), seg));

  auto asLane = [&](Value knotComponent) {
    if (auto vec = dyn_cast<VectorType>(x.getType()))
      return lane::broadcast(b, loc, knotComponent, vec.getDimSize(0));
    return knotComponent;
  };
  SmallVector<Value> result;
  for (size_t c = 0; c < knots.front().size(); ++c) {
    // The four control points of each lane's segment.
    Value cp[4];
    for (int i = 0; i < 4; ++i) {
      cp[i] = asLane(knots[i][c]);
      for (int s = 1; s < nsegs; ++s) {
        Value isSeg = b.create<arith::CmpIOp>(loc, arith::CmpIPredicate::eq, seg,
                                              lane::constant(b, loc, intLane, s));
        cp[i] = b.create<arith::SelectOp>(loc, isSeg,
                                          asLane(knots[s * basis->step + i][c]), cp[i]);
      }
    }
    Value tk[4];
    for (int j = 0; j < 4; ++j) {
      Value sum;
      for (int i = 0; i < 4; ++i) {
        Value term = b.create<arith::MulFOp>(
            loc, lane::constantLike(b, loc, segX, float(basis->m[j][i])), cp[i]);
        sum = sum ? b.create<arith::AddFOp>(loc, sum, term).getResult() : term;
      }
      tk[j] = sum;
    }
    Value r = tk[0];
    for (int j = 1; j < 4; ++j)
      r = b.create<arith::AddFOp>(loc, b.create<arith::MulFOp>(loc, r, segX), tk[j]);
    result.push_back(r);
  }
  return result;
}
