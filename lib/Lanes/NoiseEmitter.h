//===- NoiseEmitter.h - Lane ops for the noise builders ---------*- C++ -*-===//
//
// The lane emitter (OslLanes/LaneEmitter.h) with what the noise algorithms
// add to it (OSL's hashes, sign flips, floorfrac, small vectors and
// matrices), and the simplex noise pieces that SimplexNoise.cpp builds for
// NoiseBuilder.cpp's entry points.
//
//===----------------------------------------------------------------------===//
#ifndef OSLLANES_NOISEEMITTER_H
#define OSLLANES_NOISEEMITTER_H

#include "OslDialect/OslDialect.h"
#include "OslLanes/NoiseBuilder.h"
#include "OslLanes/LaneEmitter.h"
#include "OslLanes/LaneMath.h"

#include "mlir/Dialect/Arith/IR/Arith.h"
#include "mlir/Dialect/Math/IR/Math.h"
#include "mlir/IR/BuiltinAttributes.h"
#include "mlir/IR/BuiltinTypes.h"
#include "mlir/IR/TypeUtilities.h"
#include "llvm/ADT/DenseMap.h"
#include "llvm/ADT/STLExtras.h"
#include "llvm/ADT/STLFunctionalExtras.h"
#include "llvm/ADT/SmallVector.h"
#include "llvm/ADT/StringSwitch.h"
#include "llvm/Support/ErrorHandling.h"

#include <cassert>
#include <cstdint>
#include <cstring>

namespace mlir::osl::noise {

//===----------------------------------------------------------------------===//
// Op helpers over one lane type (f32 / i32 / i1 or vectors of them)
//===----------------------------------------------------------------------===//

class Emitter : public LaneEmitter {
public:
  Emitter(OpBuilder &b, Location loc, Type floatType)
      : LaneEmitter(b, loc, floatType, Constants::Cached) {
    assert(getElementTypeOrSelf(floatType).isF32() && "noise operands must be f32");
  }

  /// cond ? -v : v
  Value negateIf(Value v, Value cond) { return select(cond, neg(v), v); }
  /// -v where bit `bit` of the integer h is set, else v: that bit moved to
  /// the sign and xor'ed in (negation flips the sign bit and nothing else,
  /// so the bits are those of negateIf), one or two vector ops fewer than
  /// a test, a negation and a select.
  Value negateIfBit(Value v, Value h, unsigned bit) {
    Value sign = shl(h, 31 - bit);
    if (bit > 0)
      sign = iand(sign, 0x80000000u);
    auto flipped = b.create<arith::BitcastOp>(loc, fty, ixor(bitsOf(v), sign));
    flipped->setAttr(kDualRuleAttr, b.getStringAttr(kDualRuleSignFlip));
    return flipped;
  }

  //===--------------------------------------------------------------------===//
  // Shared noise pieces
  //===--------------------------------------------------------------------===//

  Value rotl(Value x, unsigned k) { return ior(shl(x, k), shr(x, 32 - k)); }

  /// x - y behind an osl.codegen_fence: the hash's subtractions, where
  /// LLVM's known-bits queries of the chain stop (they cost it 1.9x the
  /// instruction selection time of the fenced chain).
  Value hashSub(Value x, Value y) {
    Value difference = isub(x, y);
    return b.create<CodegenFenceOp>(loc, difference.getType(), difference);
  }

  void bjmix(Value &a, Value &bb, Value &c) {
    a = hashSub(a, c); a = ixor(a, rotl(c, 4));  c = iadd(c, bb);
    bb = hashSub(bb, a); bb = ixor(bb, rotl(a, 6));  a = iadd(a, c);
    c = hashSub(c, bb); c = ixor(c, rotl(bb, 8));  bb = iadd(bb, a);
    a = hashSub(a, c); a = ixor(a, rotl(c, 16)); c = iadd(c, bb);
    bb = hashSub(bb, a); bb = ixor(bb, rotl(a, 19)); a = iadd(a, c);
    c = hashSub(c, bb); c = ixor(c, rotl(bb, 4));  bb = iadd(bb, a);
  }

  Value bjfinal(Value a, Value bb, Value c) {
    c = ixor(c, bb); c = hashSub(c, rotl(bb, 14));
    a = ixor(a, c); a = hashSub(a, rotl(c, 11));
    bb = ixor(bb, a); bb = hashSub(bb, rotl(a, 25));
    c = ixor(c, bb); c = hashSub(c, rotl(bb, 16));
    a = ixor(a, c); a = hashSub(a, rotl(c, 4));
    bb = ixor(bb, a); bb = hashSub(bb, rotl(a, 14));
    c = ixor(c, bb); c = hashSub(c, rotl(bb, 24));
    return c;
  }

  static uint32_t startValue(uint32_t nkeys) {
    return 0xdeadbeefu + (nkeys << 2) + 13u;
  }

  /// lookup3 of 1 to 5 keys, as OSL's inthash.
  Value inthash(ArrayRef<Value> k) {
    assert(!k.empty() && k.size() <= 5);
    Value s = i(startValue(k.size()));
    switch (k.size()) {
    case 1:
      return bjfinal(iadd(s, k[0]), s, s);
    case 2:
      return bjfinal(iadd(s, k[0]), iadd(s, k[1]), s);
    case 3:
      return bjfinal(iadd(s, k[0]), iadd(s, k[1]), iadd(s, k[2]));
    default: {
      Value a = iadd(s, k[0]), bb = iadd(s, k[1]), c = iadd(s, k[2]);
      bjmix(a, bb, c);
      a = iadd(a, k[3]);
      if (k.size() == 5)
        bb = iadd(bb, k[4]);
      return bjfinal(a, bb, c);
    }
    }
  }

  /// uitofp(bits) * float(1 / (2^32 - 1)) (= 2^-32), OSL's bits_to_01.
  Value bitsTo01(Value h) {
    return mul(uitofp(h), f(static_cast<float>(1.0 / 4294967295.0)));
  }

  /// int(floor(x)), INT_MIN when out of range or NaN.
  Value ifloor(Value x) {
    Value unused;
    return floorSplit(x, unused);
  }

  /// int(floor(x)) as ifloor, and `frac` = x - float(that int), OSL's
  /// floorfrac. The floor is clamped in float (|floor| < 2^31, else -2^31,
  /// which is also INT_MIN's value) before one in-range conversion, so the
  /// fraction needs no conversion back: 7 vector ops where converting,
  /// selecting the integer and converting back took 8.
  Value floorSplit(Value x, Value &frac) {
    Value fl = floor(x);
    Value inRange = cmpf(arith::CmpFPredicate::OLT, b.create<math::AbsFOp>(loc, fl),
                         f(2147483648.0f));
    // + 0 makes floor(-0) = -0 the +0 an integer converts back to, so
    // frac(-0) stays -0 - (+0) = -0.
    Value clamped = add(select(inRange, fl, f(-2147483648.0f)), f(0.0f));
    frac = sub(x, clamped);
    return b.create<arith::FPToSIOp>(loc, ity, clamped);
  }

  Value fade(Value t) {
    Value t3 = mul(mul(t, t), t);
    return mul(t3, add(mul(t, sub(mul(t, f(6.0f)), f(15.0f))), f(10.0f)));
  }

  Value lerp(Value a, Value c, Value t) {
    return add(mul(a, sub(f(1.0f), t)), mul(c, t));
  }

  Value unsignedOf(Value n) { return mul(f(0.5f), add(n, f(1.0f))); }
};

/// All corners of the simplex containing a 2-4D point: distance vectors
/// and lattice points, in OSL's order.
struct SimplexCorners {
  SmallVector<SmallVector<Value, 4>, 5> d, lat;
};

/// 1D simplex noise at x with the hash seed `seed`.
Value simplex1(Emitter &e, Value x, uint32_t seed);
/// The corners of the simplex around p (2-4 dimensions).
SimplexCorners simplexCorners(Emitter &e, ValueRange p);
/// One channel of N-dimensional simplex noise over those corners.
Value simplexN(Emitter &e, const SimplexCorners &sc, uint32_t seed);

} // namespace mlir::osl::noise

#endif // OSLLANES_NOISEEMITTER_H
