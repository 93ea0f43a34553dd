//===- SplineBuilder.cpp - OSL spline() and splineinverse() on lanes ------===//
//
// OSL's spline: x is clamped to [0,1] and split into nsegs = (n-4)/step + 1
// segments; segment s uses knots [s*step, s*step+4) weighted by the basis
// matrix, then evaluated by Horner's rule ("constant" takes knot s+1). The
// knot window is chosen per lane with selects, so a varying x (or a varying
// knot count) over uniform knots stays vector code.
//
// splineinverse searches segment by segment with OIIO's invert: regula
// falsi for 3/4 of 32 iterations, then bisection, until the bracket or the
// value is within 1e-6. Lanes converge at different iterations, so every
// lane runs the 32 iterations and keeps its value once it has converged.
//
//===----------------------------------------------------------------------===//
#include "OslLanes/LaneMath.h"
#include "OslLanes/LibraryBuilders.h"

#include "mlir/Dialect/Arith/IR/Arith.h"
#include "mlir/Dialect/SCF/IR/SCF.h"
#include "mlir/Dialect/Vector/IR/VectorOps.h"
#include "mlir/IR/Matchers.h"

#include <algorithm>

using namespace mlir;
using namespace mlir::osl;

namespace {

/// A basis as OSL's spline matrix: segment i uses knots i*step .. i*step+3.
struct BasisMatrix {
  double m[4][4];
  int step;
  bool constant = false;
};

BasisMatrix basisMatrix(SplineBasis basis) {
  switch (basis) {
  case SplineBasis::catmullrom:
    return BasisMatrix{{{-0.5, 1.5, -1.5, 0.5}, {1, -2.5, 2, -0.5}, {-0.5, 0, 0.5, 0}, {0, 1, 0, 0}},
                       1};
  case SplineBasis::bezier:
    return BasisMatrix{{{-1, 3, -3, 1}, {3, -6, 3, 0}, {-3, 3, 0, 0}, {1, 0, 0, 0}}, 3};
  case SplineBasis::bspline:
    return BasisMatrix{{{-1.0 / 6, 3.0 / 6, -3.0 / 6, 1.0 / 6},
                        {3.0 / 6, -6.0 / 6, 3.0 / 6, 0},
                        {-3.0 / 6, 0, 3.0 / 6, 0},
                        {1.0 / 6, 4.0 / 6, 1.0 / 6, 0}},
                       1};
  case SplineBasis::hermite:
    return BasisMatrix{{{2, 1, -2, 1}, {-3, -2, 3, -1}, {0, 1, 0, 0}, {1, 0, 0, 0}}, 2};
  case SplineBasis::linear:
    return BasisMatrix{{{0, 0, 0, 0}, {0, 0, 0, 0}, {0, -1, 1, 0}, {0, 1, 0, 0}}, 1};
  case SplineBasis::constant:
    return BasisMatrix{{{0}}, 1, /*constant=*/true};
  }
  llvm_unreachable("spline basis");
}

Value selectLane(OpBuilder &b, Location loc, Value cond, Value t, Value f) {
  return b.create<arith::SelectOp>(loc, cond, t, f);
}

Value cmpF(OpBuilder &b, Location loc, arith::CmpFPredicate p, Value x, Value y) {
  return b.create<arith::CmpFOp>(loc, p, x, y);
}

/// A spline over `knots` (components per knot) with a possibly dynamic
/// knot count, evaluated at lane values of one shape.
class LaneSpline {
public:
  LaneSpline(OpBuilder &b, Location loc, const BasisMatrix &basis,
             ArrayRef<SmallVector<Value>> knots, Value count, Type floatLane)
      : b(b), loc(loc), basis(basis), knots(knots), floatLane(floatLane) {
    intLane = lane::withElement(floatLane, b.getI32Type());
    int len = knots.size();
    maxSegs = (len - 4) / basis.step + 1;
    if (!count) {
      nsegs = intConst(maxSegs);
      n = intConst(len);
      return;
    }
    // Only the first `count` knots (at most all of them). Fewer than 4
    // make no whole segment: OSL's count of segments, (n - 4) / step + 1
    // in C's division, is then 0 or less and its segment negative, and it
    // reads knots before the array (osl-mlir reads the first knot there).
    n = lane::min(b, loc, {count, intConst(len)});
    Value segs = b.create<arith::DivSIOp>(
        loc, b.create<arith::SubIOp>(loc, n, intConst(4)), intConst(basis.step));
    nsegs = b.create<arith::AddIOp>(loc, segs, intConst(1));
    // The segments a count below 4 selects (down to a count of 0's), unless
    // the count is known to be 4 or more.
    APInt known;
    if (!matchPattern(count, m_ConstantInt(&known)) || known.getSExtValue() < 4)
      minSeg = (0 - 4) / basis.step;
  }

  /// The value of component `c` of the spline at x.
  Value evaluate(Value x, size_t c) {
    // OSL clamps a Dual2 x as x < 0 ? 0 : (x > 1 ? 1 : x): x exactly at 0 or 1
    // keeps its derivative (lane::clamp, OSL's clamp(), takes the bound's).
    Value zero = floatConst(0), one = floatConst(1);
    x = selectLane(b, loc, cmpF(b, loc, arith::CmpFPredicate::OLT, x, zero), zero,
                   selectLane(b, loc, cmpF(b, loc, arith::CmpFPredicate::OGT, x, one), one, x));
    Value segX = b.create<arith::MulFOp>(
        loc, x, b.create<arith::SIToFPOp>(loc, floatLane, nsegs));
    Value seg = b.create<arith::FPToSIOp>(loc, intLane, segX);
    seg = lane::min(b, loc, {seg, b.create<arith::SubIOp>(loc, nsegs, intConst(1))});
    if (basis.constant)
      return knotOfSegment(seg, 1, c);
    segX = b.create<arith::SubFOp>(loc, segX, b.create<arith::SIToFPOp>(loc, floatLane, seg));
    Value cp[4];
    for (int i = 0; i < 4; ++i)
      cp[i] = knotOfSegment(seg, i, c);
    Value tk[4];
    for (int j = 0; j < 4; ++j) {
      Value sum;
      for (int i = 0; i < 4; ++i) {
        Value term =
            b.create<arith::MulFOp>(loc, floatConst(float(basis.m[j][i])), cp[i]);
        sum = sum ? b.create<arith::AddFOp>(loc, sum, term).getResult() : term;
      }
      tk[j] = sum;
    }
    Value r = tk[0];
    for (int j = 1; j < 4; ++j)
      r = b.create<arith::AddFOp>(loc, b.create<arith::MulFOp>(loc, r, segX), tk[j]);
    return r;
  }

  /// Component c of knot `index` (a lane i32), for indices in [lo, hi].
  Value knotAt(Value index, int lo, int hi, size_t c) {
    Value r = asLane(knots[lo][c]);
    for (int k = lo + 1; k <= hi; ++k)
      r = b.create<arith::SelectOp>(loc, isIndex(index, k), asLane(knots[k][c]), r);
    return r;
  }

  Value intConst(int v) { return lane::constant(b, loc, intLane, v); }
  Value floatConst(double v) { return lane::constant(b, loc, floatLane, v); }
  Value asLane(Value v) {
    if (auto vec = dyn_cast<VectorType>(floatLane); vec && !isa<VectorType>(v.getType()))
      return lane::broadcast(b, loc, v, vec.getDimSize(0));
    return v;
  }

  OpBuilder &b;
  Location loc;
  const BasisMatrix &basis;
  ArrayRef<SmallVector<Value>> knots;
  Type floatLane, intLane;
  int maxSegs;
  int minSeg = 0; // the lowest segment a count below 4 selects
  Value nsegs, n; // lane i32

private:
  Value isIndex(Value index, int k) {
    return b.create<arith::CmpIOp>(loc, arith::CmpIPredicate::eq, index, intConst(k));
  }
  /// Knot s*step + i of each lane's segment s (the first knot for an index
  /// before the array).
  Value knotOfSegment(Value seg, int i, size_t c) {
    int last = int(knots.size()) - 1;
    auto knot = [&](int s) { return asLane(knots[std::clamp(s * basis.step + i, 0, last)][c]); };
    Value r = knot(0);
    for (int s = minSeg; s < maxSegs; ++s)
      if (s != 0)
        r = b.create<arith::SelectOp>(loc, isIndex(seg, s), knot(s), r);
    return r;
  }
};

/// OIIO's invert of the spline on [xmin, xmax] for target y: the x found
/// and whether [xmin, xmax] brackets y.
std::pair<Value, Value> invertSegment(LaneSpline &spline, Value y, Value xmin, Value xmax) {
  OpBuilder &b = spline.b;
  Location loc = spline.loc;
  using P = arith::CmpFPredicate;
  const int maxIters = 32, rfIters = 3 * maxIters / 4;
  Value eps = spline.floatConst(1.0e-6);
  Value v0 = spline.evaluate(xmin, 0), v1 = spline.evaluate(xmax, 0);
  Value increasing = cmpF(b, loc, P::OLT, v0, v1);
  Value vmin = selectLane(b, loc, increasing, v0, v1);
  Value vmax = selectLane(b, loc, increasing, v1, v0);
  Value bracketed = b.create<arith::AndIOp>(loc, cmpF(b, loc, P::OGE, y, vmin),
                                            cmpF(b, loc, P::OLE, y, vmax));
  Value belowIsLow = b.create<arith::CmpIOp>(loc, arith::CmpIPredicate::eq,
                                             cmpF(b, loc, P::OLT, y, vmin), increasing);
  Value edge = selectLane(b, loc, belowIsLow, xmin, xmax);
  Value closeEnough =
      cmpF(b, loc, P::OLT, lane::abs(b, loc, {b.create<arith::SubFOp>(loc, v0, v1)}), eps);
  Value notBracketed = lane::logicalNot(b, loc, {bracketed});
  Value done = b.create<arith::OrIOp>(loc, notBracketed, closeEnough);
  Value x = selectLane(b, loc, bracketed, xmin, edge);

  // Iterates while some lane is not done (at most maxIters times): a lane
  // that is done keeps its values, so stopping when none is left changes no
  // result, and a segment no lane brackets costs no iteration.
  Value zero = b.create<arith::ConstantIntOp>(loc, 0, 32);
  SmallVector<Value> init = {zero, xmin, xmax, v0, v1, x, done};
  SmallVector<Type> types;
  for (Value v : init)
    types.push_back(v.getType());
  auto loop = b.create<scf::WhileOp>(
      loc, types, init,
      [&](OpBuilder &b, Location loc, ValueRange st) {
        Value more = b.create<arith::CmpIOp>(loc, arith::CmpIPredicate::slt, st[0],
                                             b.create<arith::ConstantIntOp>(loc, maxIters, 32));
        Value pending = lane::any(b, loc, lane::logicalNot(b, loc, {st[6]}));
        b.create<scf::ConditionOp>(loc, b.create<arith::AndIOp>(loc, more, pending), st);
      },
      [&](OpBuilder &b, Location loc, ValueRange st) {
        Value iter = st[0], lo = st[1], hi = st[2], f0 = st[3], f1 = st[4], xc = st[5],
              dn = st[6];
        Value half = spline.floatConst(0.5);
        Value rf = b.create<arith::DivFOp>(loc, b.create<arith::SubFOp>(loc, y, f0),
                                           b.create<arith::SubFOp>(loc, f1, f0));
        Value outside = b.create<arith::OrIOp>(
            loc, cmpF(b, loc, P::OLE, rf, spline.floatConst(0)),
            cmpF(b, loc, P::OGE, rf, spline.floatConst(1)));
        rf = selectLane(b, loc, outside, half, rf);
        Value useRf = b.create<arith::CmpIOp>(loc, arith::CmpIPredicate::slt, iter,
                                              b.create<arith::ConstantIntOp>(loc, rfIters, 32));
        Value t = b.create<arith::SelectOp>(loc, useRf, rf, half);
        // lerp(lo, hi, t) = lo*(1-t) + hi*t
        Value xn = b.create<arith::AddFOp>(
            loc,
            b.create<arith::MulFOp>(loc, lo,
                                    b.create<arith::SubFOp>(loc, spline.floatConst(1), t)),
            b.create<arith::MulFOp>(loc, hi, t));
        Value v = spline.evaluate(xn, 0);
        Value goLow = b.create<arith::CmpIOp>(loc, arith::CmpIPredicate::eq,
                                              cmpF(b, loc, P::OLT, v, y), increasing);
        Value nlo = selectLane(b, loc, goLow, xn, lo);
        Value nf0 = selectLane(b, loc, goLow, v, f0);
        Value nhi = selectLane(b, loc, goLow, hi, xn);
        Value nf1 = selectLane(b, loc, goLow, f1, v);
        Value converged = b.create<arith::OrIOp>(
            loc,
            cmpF(b, loc, P::OLT, lane::abs(b, loc, {b.create<arith::SubFOp>(loc, nhi, nlo)}),
                 eps),
            cmpF(b, loc, P::OLT, lane::abs(b, loc, {b.create<arith::SubFOp>(loc, v, y)}), eps));
        // Lanes already done keep everything.
        SmallVector<Value> next = {
            b.create<arith::AddIOp>(loc, iter, b.create<arith::ConstantIntOp>(loc, 1, 32))};
        Value fresh[] = {nlo, nhi, nf0, nf1, xn}, old[] = {lo, hi, f0, f1, xc};
        for (int k = 0; k < 5; ++k)
          next.push_back(selectLane(b, loc, dn, old[k], fresh[k]));
        next.push_back(b.create<arith::OrIOp>(loc, dn, converged));
        b.create<scf::YieldOp>(loc, next);
      });
  return {loop.getResult(5), bracketed};
}

} // namespace

FailureOr<SmallVector<Value>>
mlir::osl::buildSpline(OpBuilder &b, Location loc, SplineBasis basisKind, Value x,
                       Value count, ArrayRef<SmallVector<Value>> knots) {
  if (knots.size() < 4)
    return failure();
  BasisMatrix basis = basisMatrix(basisKind);
  LaneSpline spline(b, loc, basis, knots, count, x.getType());
  SmallVector<Value> result;
  for (size_t c = 0; c < knots.front().size(); ++c)
    result.push_back(spline.evaluate(x, c));
  return result;
}

FailureOr<Value> mlir::osl::buildSplineInverse(OpBuilder &b, Location loc,
                                               SplineBasis basisKind, Value y, Value count,
                                               ArrayRef<SmallVector<Value>> knots) {
  if (knots.size() < 4)
    return failure();
  BasisMatrix basis = basisMatrix(basisKind);
  using P = arith::CmpFPredicate;
  LaneSpline spline(b, loc, basis, knots, count, y.getType());
  int len = knots.size();
  // Targets outside the knots' range map to 0 or 1.
  int lowIndex = basis.step == 1 ? 1 : 0;
  Value highIndex = b.create<arith::SubIOp>(loc, spline.n,
                                            spline.intConst(basis.step == 1 ? 2 : 1));
  Value kLow = spline.knotAt(spline.intConst(lowIndex), lowIndex, lowIndex, 0);
  Value kHigh = spline.knotAt(highIndex, 0, len - 1, 0);
  Value kBeforeLast =
      spline.knotAt(b.create<arith::SubIOp>(loc, spline.n, spline.intConst(2)), 0, len - 1, 0);
  Value increasing = cmpF(b, loc, P::OLT, spline.asLane(knots[1][0]), kBeforeLast);
  Value atLow = selectLane(b, loc, increasing, cmpF(b, loc, P::OLE, y, kLow),
                           cmpF(b, loc, P::OGE, y, kLow));
  Value atHigh = selectLane(b, loc, increasing, cmpF(b, loc, P::OGE, y, kHigh),
                            cmpF(b, loc, P::OLE, y, kHigh));

  // Each segment in turn; the first that brackets y gives the answer, else
  // the last segment's edge.
  Value segScale = b.create<arith::DivFOp>(
      loc, spline.floatConst(1), b.create<arith::SIToFPOp>(loc, y.getType(), spline.nsegs));
  Value r0 = spline.floatConst(0);
  Value found = lane::constant(b, loc, lane::withElement(y.getType(), b.getI1Type()), 0);
  Value answer = r0, fallback = r0;
  for (int s = 0; s < spline.maxSegs; ++s) {
    Value r1 = b.create<arith::MulFOp>(loc, segScale, spline.floatConst(s + 1));
    auto [x, bracketed] = invertSegment(spline, y, r0, r1);
    Value valid = b.create<arith::CmpIOp>(loc, arith::CmpIPredicate::slt,
                                          spline.intConst(s), spline.nsegs);
    Value take = b.create<arith::AndIOp>(
        loc, b.create<arith::AndIOp>(loc, valid, bracketed), lane::logicalNot(b, loc, {found}));
    answer = selectLane(b, loc, take, x, answer);
    fallback = selectLane(b, loc, valid, x, fallback);
    found = b.create<arith::OrIOp>(loc, found, take);
    r0 = r1;
  }
  Value r = selectLane(b, loc, found, answer, fallback);
  r = selectLane(b, loc, atHigh, spline.floatConst(1), r);
  return selectLane(b, loc, atLow, spline.floatConst(0), r);
}
