//===- GaborBuilder.cpp - OSL's Gabor noise as lane ops -------------------===//
//
// Sparse-convolution Gabor noise as OSL 1.13 computes it:
//
//  * Parameters (uniform): bandwidth clamped to [0.01, 100];
//    a = 2 * ((2^bw - 1) / (2^bw + 1)) * sqrt(pi / ln 2), with OSL's fast
//    exp2 and the quotient in double; kernel radius
//    sqrt(-ln(0.02) / pi) / a; impulse density lambda = impulses (clamped
//    to [1, 32]) / (1.33333 pi radius^3); result scale
//    0.5 / (3 sqrt(1 / (4 sqrt(2) a^3))).
//  * The point is divided by the radius; the 3x3x3 cells around it each
//    seed a linear congruential generator (multiplier 3039177861, floats
//    x / 2^32) with inthash(cell, seed). A Poisson count (Knuth's product
//    of uniforms against e^-(lambda radius^3)) gives the cell's impulses;
//    each draws its position (z, y, then x), its frequency (none when
//    anisotropic, azimuth and cos(polar angle) when isotropic, azimuth when
//    hybrid) and a phase, and adds
//    exp(-pi a^2 |x|^2) cos(2 pi <omega, x> + phi) when |x| < radius.
//  * Filtering (do_filter and a non-degenerate Dx(P) x Dy(P)): each kernel
//    is sliced to the tangent plane of the derivatives and convolved with a
//    Gaussian pixel filter (Lagae et al. 2009, equations 6 and 10), falling
//    back to the plain kernel where that is not finite.
//  * pnoise wraps the cell coordinates by floor(period) (at least 1)
//    before seeding, so the impulses repeat.
//
// The discrete decisions (cells, seeds, counts, the radius test) use the
// same float operations as OSL, so they agree exactly; exp and cos use
// OSL's fast approximations where OSL calls libm, which moves values by
// about 1e-6. The Poisson bound e^-mean is computed in double and rounded,
// like libm's expf.
//
//===----------------------------------------------------------------------===//

#include "OslLanes/GaborBuilder.h"
#include "OslLanes/LaneEmitter.h"
#include "OslLanes/NoiseBuilder.h"

#include "mlir/Dialect/Arith/IR/Arith.h"
#include "mlir/Dialect/Math/IR/Math.h"
#include "mlir/Dialect/SCF/IR/SCF.h"
#include "mlir/Dialect/Vector/IR/VectorOps.h"
#include "mlir/IR/BuiltinAttributes.h"
#include "mlir/IR/BuiltinTypes.h"
#include "mlir/IR/Matchers.h"

#include <cmath>
#include <cstdint>

using namespace mlir;

namespace mlir::osl {
namespace {

using FP = arith::CmpFPredicate;
using Vec3 = std::array<Value, 3>;
using Mat2 = std::array<std::array<Value, 2>, 2>;
using Mat3 = std::array<Vec3, 3>;

constexpr float kPi = float(M_PI);
constexpr float kTwoPi = float(2.0 * M_PI);
constexpr uint32_t kRngMultiplier = 3039177861u;

//===----------------------------------------------------------------------===//
// Ops on one lane shape (f32 / vector<W x f32> and their i32 / i1 forms)
//===----------------------------------------------------------------------===//

/// The lane emitter with Gabor noise's pieces. Constants are made where
/// they are used (no cache): the builder moves in and out of loop bodies,
/// where a cached constant would not dominate.
class Lanes : public LaneEmitter {
public:
  Lanes(OpBuilder &b, Location loc, Type floatType) : LaneEmitter(b, loc, floatType) {}

  /// (int)floorf(x) as on x86: INT_MIN when out of range or NaN.
  Value ifloor(Value x) {
    Value fl = floor(x);
    Value inRange = band(cmpf(FP::OGE, fl, f(-2147483648.0f)),
                         cmpf(FP::OLT, fl, f(2147483648.0f)));
    return select(inRange, b.create<arith::FPToSIOp>(loc, ity, fl),
                  i(0x80000000u));
  }

  Value dot(const Vec3 &x, const Vec3 &y) {
    return add(add(mul(x[0], y[0]), mul(x[1], y[1])), mul(x[2], y[2]));
  }
  /// Imath's normalize: a zero vector stays as it is.
  Vec3 normalized(const Vec3 &v) {
    Value len = sqrt(dot(v, v));
    Value zero = cmpf(FP::OEQ, len, f(0.0f));
    Vec3 out;
    for (int k = 0; k < 3; ++k)
      out[k] = select(zero, v[k], div(v[k], len));
    return out;
  }
  Vec3 cross(const Vec3 &x, const Vec3 &y) {
    return {sub(mul(x[1], y[2]), mul(x[2], y[1])),
            sub(mul(x[2], y[0]), mul(x[0], y[2])),
            sub(mul(x[0], y[1]), mul(x[1], y[0]))};
  }
  /// Row vector times matrix (OSL's multMatrix).
  Vec3 rowTimes(const Vec3 &v, const Mat3 &m) {
    Vec3 out;
    for (int j = 0; j < 3; ++j)
      out[j] = add(add(mul(v[0], m[0][j]), mul(v[1], m[1][j])),
                   mul(v[2], m[2][j]));
    return out;
  }

  // 2x2 matrices, with Imath's element order in each operation.
  Value det(const Mat2 &m) {
    return sub(mul(m[0][0], m[1][1]), mul(m[1][0], m[0][1]));
  }
  Mat2 inverse(const Mat2 &m) {
    Value r = det(m);
    return {{{div(m[1][1], r), div(neg(m[0][1]), r)},
             {div(neg(m[1][0]), r), div(m[0][0], r)}}};
  }
  Mat2 plus(const Mat2 &x, const Mat2 &y) {
    return {{{add(x[0][0], y[0][0]), add(x[0][1], y[0][1])},
             {add(x[1][0], y[1][0]), add(x[1][1], y[1][1])}}};
  }
  Mat2 times(const Mat2 &x, const Mat2 &y) {
    Mat2 out;
    for (int r = 0; r < 2; ++r)
      for (int c = 0; c < 2; ++c)
        out[r][c] = add(mul(x[r][0], y[0][c]), mul(x[r][1], y[1][c]));
    return out;
  }
  Mat2 scaled(Value s, const Mat2 &m) {
    return {{{mul(s, m[0][0]), mul(s, m[0][1])},
             {mul(s, m[1][0]), mul(s, m[1][1])}}};
  }
  /// v * m for a row 2-vector (OSL's gabor_mul_m22_v2).
  std::array<Value, 2> rowTimes(const std::array<Value, 2> &v, const Mat2 &m) {
    return {add(mul(v[0], m[0][0]), mul(v[1], m[1][0])),
            add(mul(v[0], m[0][1]), mul(v[1], m[1][1]))};
  }
};

/// Imath's clamp: x < lo ? lo : (x > hi ? hi : x).
Value clampTo(Lanes &l, Value x, float lo, float hi) {
  return l.select(l.cmpf(FP::OLT, x, l.f(lo)), l.f(lo),
                  l.select(l.cmpf(FP::OGT, x, l.f(hi)), l.f(hi), x));
}

/// e^x for a moderate f32 x (|x| < 80), computed in double and rounded
/// once: 2^k e^r with |r| <= ln(2)/2 and a degree-13 Taylor polynomial
/// (relative error below 1e-15), so the result is libm's correctly rounded
/// expf except in astronomically rare ties.
Value expInDouble(OpBuilder &b, Location loc, Value x) {
  Type f64 = b.getF64Type(), i64 = b.getI64Type();
  auto cf = [&](double v) {
    return b.create<arith::ConstantOp>(loc, b.getF64FloatAttr(v)).getResult();
  };
  auto ci = [&](int64_t v) {
    return b.create<arith::ConstantOp>(loc, b.getI64IntegerAttr(v)).getResult();
  };
  Value xd = b.create<arith::ExtFOp>(loc, f64, x);
  // k = round(x / ln 2) (half away from zero, via truncation of x/ln2 +- 0.5).
  Value scaled = b.create<arith::MulFOp>(loc, xd, cf(1.4426950408889634));
  Value half = b.create<math::CopySignOp>(loc, cf(0.5), scaled);
  Value k = b.create<arith::FPToSIOp>(loc, i64,
                                      b.create<arith::AddFOp>(loc, scaled, half));
  Value kd = b.create<arith::SIToFPOp>(loc, f64, k);
  // r = x - k ln2, with ln2 split so k * ln2Hi is exact.
  Value r = b.create<arith::SubFOp>(
      loc, b.create<arith::SubFOp>(loc, xd, b.create<arith::MulFOp>(loc, kd, cf(0x1.62e42fefa3800p-1))),
      b.create<arith::MulFOp>(loc, kd, cf(0x1.ef35793c76730p-45)));
  Value poly = cf(1.0 / 6227020800.0); // 1/13!
  double factorial = 6227020800.0;
  for (int n = 12; n >= 0; --n) {
    factorial /= (n + 1);
    poly = b.create<arith::AddFOp>(loc, b.create<arith::MulFOp>(loc, poly, r),
                                   cf(1.0 / factorial));
  }
  // 2^k from the exponent bits.
  Value bits = b.create<arith::ShLIOp>(loc, b.create<arith::AddIOp>(loc, k, ci(1023)), ci(52));
  Value twoK = b.create<arith::BitcastOp>(loc, f64, bits);
  Value e = b.create<arith::MulFOp>(loc, poly, twoK);
  return b.create<arith::TruncFOp>(loc, b.getF32Type(), e);
}

//===----------------------------------------------------------------------===//
// Parameters (uniform)
//===----------------------------------------------------------------------===//

/// The anisotropy modes of the "anisotropic" option.
enum Mode : int32_t { Isotropic = 0, Anisotropic = 1, Hybrid = 2 };

struct Params {
  Value a, radius, radius2, radiusInv, poissonBound, sqrtLambdaInv, scale;
  Vec3 direction;
  Value directionLength;
  /// The mode when known at compile time; otherwise `modeValue` (i32).
  std::optional<int32_t> mode;
  Value modeValue;
  /// do_filter as i1 (uniform); null when filtering is off for certain.
  Value doFilter;
};

} // namespace

GaborOptions withGaborDefaults(OpBuilder &b, Location loc, GaborOptions options) {
  auto f32 = [&](float v) -> Value {
    return b.create<arith::ConstantOp>(loc, b.getF32FloatAttr(v));
  };
  auto i32 = [&](int32_t v) -> Value {
    return b.create<arith::ConstantOp>(loc, b.getI32IntegerAttr(v));
  };
  if (!options.anisotropic)
    options.anisotropic = i32(Isotropic);
  for (int k = 0; k < 3; ++k)
    if (!options.direction[k])
      options.direction[k] = f32(k == 0 ? 1.0f : 0.0f);
  if (!options.bandwidth)
    options.bandwidth = f32(1.0f);
  if (!options.impulses)
    options.impulses = f32(16.0f);
  if (!options.doFilter)
    options.doFilter = i32(1);
  return options;
}

namespace {

/// OSL's GaborParams, on uniform (scalar) values.
Params buildParams(OpBuilder &b, Location loc, const GaborOptions &given,
                   bool haveDerivs) {
  GaborOptions opt = withGaborDefaults(b, loc, given);
  Lanes u(b, loc, b.getF32Type());
  Params p;
  Value bandwidth = clampTo(u, opt.bandwidth, 0.01f, 100.0f);
  // a in double: OSL writes (2^bw - 1.0) / (2^bw + 1.0) with double literals.
  Type f64 = b.getF64Type();
  auto d = [&](double v) {
    return b.create<arith::ConstantOp>(loc, b.getF64FloatAttr(v)).getResult();
  };
  Value twoToBw = b.create<arith::ExtFOp>(loc, f64, b.create<math::Exp2Op>(loc, bandwidth).getResult());
  Value ratio = b.create<arith::DivFOp>(loc, b.create<arith::SubFOp>(loc, twoToBw, d(1.0)),
                                        b.create<arith::AddFOp>(loc, twoToBw, d(1.0)));
  // sqrt(pi / ln 2) as OSL spells it (GCC's float value).
  Value aDouble = b.create<arith::MulFOp>(
      loc, b.create<arith::MulFOp>(loc, d(2.0), ratio), d(double(2.128934e+00f)));
  p.a = b.create<arith::TruncFOp>(loc, b.getF32Type(), aDouble);

  const float truncateRadius = std::sqrt(-std::log(0.02f) / kPi);
  p.radius = u.div(u.f(truncateRadius), p.a);
  p.radius2 = u.mul(p.radius, p.radius);
  Value radius3 = u.mul(p.radius2, p.radius);
  p.radiusInv = u.div(u.f(1.0f), p.radius);
  Value impulses = clampTo(u, opt.impulses, 1.0f, 32.0f);
  Value lambda = u.div(impulses, u.mul(u.f(float(1.33333 * M_PI)), radius3));
  p.sqrtLambdaInv = u.div(u.f(1.0f), u.sqrt(lambda));
  p.poissonBound = expInDouble(b, loc, u.neg(u.mul(lambda, radius3)));

  Value a3 = u.mul(u.mul(p.a, p.a), p.a);
  Value variance = u.div(u.f(1.0f), u.mul(u.f(4.0f * std::sqrt(2.0f)), a3));
  p.scale = u.mul(u.div(u.f(1.0f), u.mul(u.f(3.0f), u.sqrt(variance))), u.f(0.5f));

  p.direction = opt.direction;
  p.directionLength = u.sqrt(u.dot(p.direction, p.direction));

  APInt known;
  if (matchPattern(opt.anisotropic, m_ConstantInt(&known)))
    p.mode = int32_t(known.getSExtValue());
  else
    p.modeValue = opt.anisotropic;

  if (haveDerivs) {
    if (!matchPattern(opt.doFilter, m_ConstantInt(&known)) || !known.isZero())
      p.doFilter = b.create<arith::CmpIOp>(
          loc, arith::CmpIPredicate::ne, opt.doFilter,
          b.create<arith::ConstantOp>(loc, b.getI32IntegerAttr(0)));
  }
  return p;
}

//===----------------------------------------------------------------------===//
// Filter (per lane, shared by every channel)
//===----------------------------------------------------------------------===//

struct Filter {
  Value on; ///< i1 lanes: filter this lane
  Vec3 normal;
  Mat3 local; ///< texture to tangent space (columns t, b, n)
  Value cF, kGF, aF;
  Mat2 sumInverse, gfTimesGInverse;
};

/// OSL's gabor_setup_filter and the impulse-independent half of its
/// filter_gabor_kernel_2d.
Filter buildFilter(Lanes &l, const Params &p, const Vec3 &dx, const Vec3 &dy) {
  Filter fl;
  Vec3 n = l.cross(dx, dy);
  // OSL skips filtering when |n|^2 < 1e-6 (NaN included, as its test fails).
  fl.on = l.band(l.splat(p.doFilter), l.cmpf(FP::UGE, l.dot(n, n), l.f(1.0e-6f)));
  n = l.normalized(n);
  Value nearX = l.cmpf(FP::OLT, l.abs(n[0]), l.f(0.9f));
  Vec3 t = {l.select(nearX, l.f(0.0f), l.neg(n[2])), l.select(nearX, n[2], l.f(0.0f)),
            l.select(nearX, l.neg(n[1]), n[0])};
  t = l.normalized(t);
  Vec3 bt = l.cross(n, t);
  fl.normal = n;
  for (int r = 0; r < 3; ++r)
    fl.local[r] = {t[r], bt[r], n[r]};
  Mat3 screenToTex;
  for (int r = 0; r < 3; ++r)
    screenToTex[r] = {dx[r], dy[r], l.f(0.0f)};
  Mat2 scrTan;
  for (int r = 0; r < 2; ++r)
    for (int c = 0; c < 2; ++c)
      scrTan[r][c] = l.add(l.add(l.mul(screenToTex[r][0], fl.local[0][c]),
                                 l.mul(screenToTex[r][1], fl.local[1][c])),
                           l.mul(screenToTex[r][2], fl.local[2][c]));
  Mat2 scrTanT = {{{scrTan[0][0], scrTan[1][0]}, {scrTan[0][1], scrTan[1][1]}}};
  Mat2 sigmaScr = {{{l.f(0.25f), l.f(0.0f)}, {l.f(0.0f), l.f(0.25f)}}};
  Mat2 sigmaF = l.times(l.times(scrTanT, sigmaScr), scrTan);
  Value detF = l.det(sigmaF);
  fl.on = l.band(fl.on, l.cmpf(FP::UGE, detF, l.f(1.0e-18f)));

  // Equation 10 of Lagae et al., all but the impulse's own frequency.
  Value a = l.splat(p.a);
  Value sg = l.div(l.mul(a, a), l.f(kTwoPi));
  Mat2 sigmaG = {{{l.mul(sg, l.f(1.0f)), l.mul(sg, l.f(0.0f))},
                  {l.mul(sg, l.f(0.0f)), l.mul(sg, l.f(1.0f))}}};
  fl.cF = l.div(l.f(1.0f), l.mul(l.f(kTwoPi), l.sqrt(detF)));
  Mat2 sigmaFilter = l.scaled(l.f(float(1.0 / (4.0 * M_PI * M_PI))), l.inverse(sigmaF));
  Mat2 sum = l.plus(sigmaG, sigmaFilter);
  fl.kGF = l.div(l.f(1.0f), l.mul(l.f(kTwoPi), l.sqrt(l.det(sum))));
  fl.sumInverse = l.inverse(sum);
  Mat2 sigmaGInv = l.inverse(sigmaG);
  Mat2 sigmaGF = l.inverse(l.plus(l.inverse(sigmaFilter), sigmaGInv));
  fl.gfTimesGInverse = l.times(sigmaGF, sigmaGInv);
  // sqrtf(M_TWO_PI * sqrtf(det)): the product is in double.
  Type f64 = l.b.getF64Type();
  Value rootDet = l.b.create<arith::ExtFOp>(l.loc, l.withElement(f64), l.sqrt(l.det(sigmaGF)));
  Value twoPiD = l.constant(l.withElement(f64), l.b.getF64FloatAttr(2.0 * M_PI));
  Value prod = l.b.create<arith::MulFOp>(l.loc, twoPiD, rootDet);
  fl.aF = l.sqrt(l.b.create<arith::TruncFOp>(l.loc, l.fty, prod));
  return fl;
}

//===----------------------------------------------------------------------===//
// Impulses
//===----------------------------------------------------------------------===//

/// The generator's next state and its uniform float in [0, 1].
std::pair<Value, Value> draw(Lanes &l, Value state) {
  Value next = l.imul(state, l.i(kRngMultiplier));
  return {next, l.div(l.uitofp(next), l.f(4294967295.0f))};
}

struct Impulse {
  Value state; ///< generator state after the impulse's draws
  Vec3 position;
  Vec3 omega;
  Value phi;
};

/// Frequency of one mode (OSL's gabor_sample), drawing from `state`.
std::pair<Value, Vec3> sampleOmega(Lanes &l, const Params &p, int32_t mode,
                                   Value state) {
  if (mode == Anisotropic)
    return {state, {l.splat(p.direction[0]), l.splat(p.direction[1]),
                    l.splat(p.direction[2])}};
  auto [s1, u1] = draw(l, state);
  Value azimuth = l.mul(l.f(kTwoPi), u1);
  Value sinT = l.sin(azimuth), cosT = l.cos(azimuth);
  if (mode == Isotropic) {
    auto [s2, u2] = draw(l, s1);
    // lerp(-1, 1, u) = -1 * (1 - u) + 1 * u
    Value cosP = l.add(l.mul(l.f(-1.0f), l.sub(l.f(1.0f), u2)), l.mul(l.f(1.0f), u2));
    Value rest = l.sub(l.f(1.0f), l.mul(cosP, cosP));
    Value sinP = l.sqrt(l.select(l.cmpf(FP::OLT, l.f(0.0f), rest), rest, l.f(0.0f)));
    return {s2, l.normalized({l.mul(cosT, sinP), l.mul(sinT, sinP), cosP})};
  }
  Value r = l.splat(p.directionLength);
  return {s1, {l.mul(r, cosT), l.mul(r, sinT), l.mul(r, l.f(0.0f))}};
}

/// Draws one impulse: position (z, y, x order), frequency, phase.
Impulse drawImpulse(Lanes &l, const Params &p, Value state) {
  Impulse imp;
  auto [sz, z] = draw(l, state);
  auto [sy, y] = draw(l, sz);
  auto [sx, x] = draw(l, sy);
  imp.position = {x, y, z};
  Value afterOmega;
  if (p.mode) {
    std::tie(afterOmega, imp.omega) = sampleOmega(l, p, *p.mode, sx);
  } else {
    // The mode is a uniform value: build all three and pick.
    auto [sIso, wIso] = sampleOmega(l, p, Isotropic, sx);
    auto [sAni, wAni] = sampleOmega(l, p, Anisotropic, sx);
    auto [sHyb, wHyb] = sampleOmega(l, p, Hybrid, sx);
    auto is = [&](int32_t m) {
      Value c = l.b.create<arith::CmpIOp>(
          l.loc, arith::CmpIPredicate::eq, p.modeValue,
          l.b.create<arith::ConstantOp>(l.loc, l.b.getI32IntegerAttr(m)));
      return l.splat(c);
    };
    Value iso = is(Isotropic), ani = is(Anisotropic);
    afterOmega = l.select(ani, sAni, l.select(iso, sIso, sHyb));
    for (int k = 0; k < 3; ++k)
      imp.omega[k] = l.select(ani, wAni[k], l.select(iso, wIso[k], wHyb[k]));
  }
  auto [sPhi, uPhi] = draw(l, afterOmega);
  imp.state = sPhi;
  imp.phi = l.mul(l.f(kTwoPi), uPhi);
  return imp;
}

/// w exp(-pi a^2 |x|^2) cos(2 pi <omega, x> + phi), in OSL's order.
Value kernel(Lanes &l, Value weight, ArrayRef<Value> omega, Value phi, Value a,
             ArrayRef<Value> x) {
  Value xx = l.mul(x[0], x[0]), wx = l.mul(omega[0], x[0]);
  for (size_t k = 1; k < x.size(); ++k) {
    xx = l.add(xx, l.mul(x[k], x[k]));
    wx = l.add(wx, l.mul(omega[k], x[k]));
  }
  Value g = l.exp(l.mul(l.mul(l.f(-kPi), l.mul(a, a)), xx));
  Value h = l.cos(l.add(l.mul(l.f(kTwoPi), wx), phi));
  return l.mul(l.mul(weight, g), h);
}

/// The filtered kernel of one impulse at x (OSL's slice + filter + 2D
/// kernel), or the plain one where filtering is off or not finite.
Value impulseValue(Lanes &l, const Params &p, const Filter *fl,
                   const Impulse &imp, const Vec3 &x) {
  Value a = l.splat(p.a);
  Value plain = kernel(l, l.f(1.0f), imp.omega, imp.phi, a, x);
  if (!fl)
    return plain;
  Vec3 omegaT = l.rowTimes(imp.omega, fl->local);
  Value d = l.neg(l.dot(fl->normal, x));
  // Slice (equation 6).
  Value ws = l.mul(l.f(1.0f), l.exp(l.mul(l.mul(l.f(-kPi), l.mul(a, a)), l.mul(d, d))));
  std::array<Value, 2> mu = {omegaT[0], omegaT[1]};
  Value phiS = l.sub(imp.phi, l.mul(l.mul(l.f(kTwoPi), d), omegaT[2]));
  // Filter (equation 10).
  std::array<Value, 2> v = l.rowTimes(mu, fl->sumInverse);
  Value quad = l.add(l.mul(v[0], mu[0]), l.mul(v[1], mu[1]));
  Value wF = l.mul(l.mul(l.mul(fl->cF, ws), fl->kGF), l.exp(l.mul(l.f(-0.5f), quad)));
  std::array<Value, 2> omegaF = l.rowTimes(mu, fl->gfTimesGInverse);
  Vec3 xt = l.rowTimes(x, fl->local);
  Value filtered = kernel(l, wF, omegaF, phiS, fl->aF, {xt[0], xt[1]});
  Value finite = l.cmpf(FP::ONE, l.abs(filtered), l.f(INFINITY));
  return l.select(l.band(fl->on, finite), filtered, plain);
}

//===----------------------------------------------------------------------===//
// Cells and the grid
//===----------------------------------------------------------------------===//

/// pnoise's wrap of a cell coordinate: s - p floor(s / p), p = floor(period)
/// raised to at least 1.
Value wrapCoord(Lanes &l, Value s, Value period) {
  Value q = l.floor(period);
  q = l.select(l.cmpf(FP::OLT, q, l.f(1.0f)), l.f(1.0f), q);
  return l.sub(s, l.mul(q, l.floor(l.div(s, q))));
}

/// Knuth's Poisson sampling per lane: count while the running product of
/// uniforms stays above `bound`. Returns (state, count).
std::pair<Value, Value> poissonCount(Lanes &l, Value bound, Value seed) {
  auto [s0, t0] = draw(l, seed);
  Value active0 = l.cmpf(FP::OGT, t0, bound);
  SmallVector<Type> types = {l.ity, l.fty, l.ity, l.bty};
  SmallVector<Value> init = {s0, t0, l.i(0), active0};
  auto loop = l.b.create<scf::WhileOp>(
      l.loc, types, init,
      [&](OpBuilder &b, Location loc, ValueRange args) {
        b.create<scf::ConditionOp>(loc, l.any(args[3]), args);
      },
      [&](OpBuilder &b, Location loc, ValueRange args) {
        Value state = args[0], t = args[1], count = args[2], active = args[3];
        auto [sNext, u] = draw(l, state);
        Value tNext = l.mul(t, u);
        Value stillActive = l.band(active, l.cmpf(FP::OGT, tNext, bound));
        b.create<scf::YieldOp>(
            loc, ValueRange{l.select(active, sNext, state), l.select(active, tNext, t),
                            l.select(active, l.iadd(count, l.i(1)), count), stillActive});
      });
  return {loop.getResult(0), loop.getResult(2)};
}

/// The sum of one cell's impulses at x_c_i (the point relative to the
/// cell's corner, in cell units).
Value cellSum(Lanes &l, const Params &p, const Filter *fl, Value seed,
              const Vec3 &xci) {
  auto [state, count] = poissonCount(l, l.splat(p.poissonBound), seed);
  Value radius = l.splat(p.radius), radius2 = l.splat(p.radius2);
  SmallVector<Type> types = {l.ity, l.ity, l.fty};
  SmallVector<Value> init = {state, count, l.f(0.0f)};
  auto loop = l.b.create<scf::WhileOp>(
      l.loc, types, init,
      [&](OpBuilder &b, Location loc, ValueRange args) {
        Value left = l.cmpi(arith::CmpIPredicate::sgt, args[1], l.i(0));
        b.create<scf::ConditionOp>(loc, l.any(left), args);
      },
      [&](OpBuilder &b, Location loc, ValueRange args) {
        Value st = args[0], left = args[1], sum = args[2];
        Value active = l.cmpi(arith::CmpIPredicate::sgt, left, l.i(0));
        Impulse imp = drawImpulse(l, p, st);
        Vec3 xk;
        for (int k = 0; k < 3; ++k)
          xk[k] = l.mul(radius, l.sub(xci[k], imp.position[k]));
        Value inside = l.cmpf(FP::OLT, l.dot(xk, xk), radius2);
        Value value = impulseValue(l, p, fl, imp, xk);
        Value counted = l.band(active, inside);
        b.create<scf::YieldOp>(
            loc, ValueRange{l.select(active, imp.state, st),
                            l.iadd(left, l.i(uint32_t(-1))),
                            l.select(counted, l.add(sum, value), sum)});
      });
  return loop.getResult(2);
}

/// One channel: OSL's gabor_evaluate / gabor_grid with `seedKey`.
Value evaluate(Lanes &l, const Params &p, const Filter *fl,
               const GaborPoint &pt, uint32_t seedKey) {
  OpBuilder &b = l.b;
  Location loc = l.loc;
  Vec3 xg, base, xc;
  for (int k = 0; k < 3; ++k) {
    xg[k] = l.mul(pt.p[k], l.splat(p.radiusInv));
    base[k] = l.floor(xg[k]);
    xc[k] = l.sub(xg[k], base[k]);
  }
  Value lb = b.create<arith::ConstantIndexOp>(loc, 0);
  Value ub = b.create<arith::ConstantIndexOp>(loc, 27);
  Value step = b.create<arith::ConstantIndexOp>(loc, 1);
  auto cells = b.create<scf::ForOp>(loc, lb, ub, step, ValueRange{l.f(0.0f)});
  {
    OpBuilder::InsertionGuard guard(b);
    Block *body = cells.getBody();
    if (!body->empty())
      body->back().erase(); // the default empty yield
    b.setInsertionPointToEnd(body);
    // Cell (i, j, k) in [-1, 1]^3, i fastest, as OSL's loops nest.
    Value idx = b.create<arith::IndexCastOp>(loc, b.getI32Type(), cells.getInductionVar());
    auto cst = [&](int32_t v) {
      return b.create<arith::ConstantOp>(loc, b.getI32IntegerAttr(v)).getResult();
    };
    Value three = cst(3);
    Value offsets[3] = {
        b.create<arith::RemSIOp>(loc, idx, three),
        b.create<arith::RemSIOp>(loc, b.create<arith::DivSIOp>(loc, idx, three), three),
        b.create<arith::DivSIOp>(loc, idx, cst(9))};
    Vec3 corner, xci;
    SmallVector<Value, 4> keys;
    for (int k = 0; k < 3; ++k) {
      Value c = b.create<arith::SIToFPOp>(
          loc, b.getF32Type(), b.create<arith::SubIOp>(loc, offsets[k], cst(1)));
      Value cl = l.splat(c);
      corner[k] = l.add(base[k], cl);
      xci[k] = l.sub(xc[k], cl);
      Value cellCoord = pt.period ? wrapCoord(l, corner[k], (*pt.period)[k]) : corner[k];
      keys.push_back(l.ifloor(cellCoord));
    }
    keys.push_back(l.i(seedKey));
    Value seed = buildIntHash(b, loc, keys);
    seed = l.select(l.cmpi(arith::CmpIPredicate::eq, seed, l.i(0)), l.i(1), seed);
    Value sum = cells.getRegionIterArgs()[0];
    b.create<scf::YieldOp>(loc, l.add(sum, cellSum(l, p, fl, seed, xci)));
  }
  return l.mul(cells.getResult(0), l.splat(p.sqrtLambdaInv));
}

SmallVector<Value, 3> buildGabor(OpBuilder &b, Location loc, const GaborPoint &pt,
                                 const GaborOptions &options, unsigned channels) {
  Type fty = pt.p[0].getType();
  Lanes l(b, loc, fty);
  bool haveDerivs = pt.dPdx && pt.dPdy;
  Params p = buildParams(b, loc, options, haveDerivs);
  std::optional<Filter> fl;
  if (haveDerivs && p.doFilter)
    fl = buildFilter(l, p, *pt.dPdx, *pt.dPdy);
  SmallVector<Value, 3> out;
  for (unsigned c = 0; c < channels; ++c)
    out.push_back(l.mul(evaluate(l, p, fl ? &*fl : nullptr, pt, c), l.splat(p.scale)));
  return out;
}

} // namespace

Value buildGaborFloat(OpBuilder &b, Location loc, const GaborPoint &point,
                      const GaborOptions &options) {
  return buildGabor(b, loc, point, options, 1).front();
}

std::array<Value, 3> buildGaborTriple(OpBuilder &b, Location loc,
                                      const GaborPoint &point,
                                      const GaborOptions &options) {
  SmallVector<Value, 3> r = buildGabor(b, loc, point, options, 3);
  return {r[0], r[1], r[2]};
}

} // namespace mlir::osl
