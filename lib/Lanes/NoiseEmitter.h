//===- NoiseEmitter.h - Lane ops for the noise builders ---------*- C++ -*-===//
//
// The op helpers the noise algorithms are written with, over one lane type
// (f32 / i32 / i1, or vectors of them), and the simplex noise pieces that
// SimplexNoise.cpp builds for NoiseBuilder.cpp's entry points.
//
//===----------------------------------------------------------------------===//
#ifndef OSLTRANSFORMS_NOISEEMITTER_H
#define OSLTRANSFORMS_NOISEEMITTER_H

#include "OslLanes/NoiseBuilder.h"
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

class Emitter {
public:
  Emitter(OpBuilder &b, Location loc, Type floatType)
      : b(b), loc(loc), fty(floatType) {
    Type i32 = b.getI32Type(), i1 = b.getI1Type();
    if (auto vt = dyn_cast<VectorType>(floatType)) {
      assert(vt.getElementType().isF32() && "noise operands must be f32");
      ity = VectorType::get(vt.getShape(), i32, vt.getScalableDims());
      bty = VectorType::get(vt.getShape(), i1, vt.getScalableDims());
    } else {
      assert(floatType.isF32() && "noise operands must be f32");
      ity = i32;
      bty = i1;
    }
  }

  /// `scalar` as a constant of `type`, splat if `type` is a vector.
  Value constant(Type type, TypedAttr scalar) {
    TypedAttr attr = scalar;
    if (auto vt = dyn_cast<VectorType>(type)) {
      Attribute elt = scalar;
      attr = DenseElementsAttr::get(vt, llvm::ArrayRef(elt));
    }
    return b.create<arith::ConstantOp>(loc, attr);
  }

  // Constants, cached per bit pattern.
  Value f(float v) {
    uint32_t bits;
    static_assert(sizeof bits == sizeof v);
    std::memcpy(&bits, &v, sizeof bits);
    Value &slot = floatConsts[bits];
    if (!slot)
      slot = constant(fty, b.getF32FloatAttr(v));
    return slot;
  }
  Value i(uint32_t v) {
    Value &slot = intConsts[v];
    if (!slot)
      slot = constant(ity, IntegerAttr::get(b.getI32Type(), APInt(32, v)));
    return slot;
  }

  // Float arithmetic: plain IEEE ops, no fastmath flags.
  Value add(Value a, Value c) { return b.create<arith::AddFOp>(loc, a, c); }
  Value sub(Value a, Value c) { return b.create<arith::SubFOp>(loc, a, c); }
  Value mul(Value a, Value c) { return b.create<arith::MulFOp>(loc, a, c); }
  Value div(Value a, Value c) { return b.create<arith::DivFOp>(loc, a, c); }
  Value neg(Value a) { return b.create<arith::NegFOp>(loc, a); }
  Value floor(Value a) { return b.create<math::FloorOp>(loc, a); }
  Value cmpf(arith::CmpFPredicate p, Value a, Value c) {
    return b.create<arith::CmpFOp>(loc, p, a, c);
  }

  // Integer arithmetic on i32 lanes (wrap-around, like C unsigned).
  Value iadd(Value a, Value c) { return b.create<arith::AddIOp>(loc, a, c); }
  Value isub(Value a, Value c) { return b.create<arith::SubIOp>(loc, a, c); }
  Value ixor(Value a, Value c) { return b.create<arith::XOrIOp>(loc, a, c); }
  Value iand(Value a, Value c) { return b.create<arith::AndIOp>(loc, a, c); }
  Value ior(Value a, Value c) { return b.create<arith::OrIOp>(loc, a, c); }
  Value shl(Value a, Value c) { return b.create<arith::ShLIOp>(loc, a, c); }
  Value shr(Value a, Value c) { return b.create<arith::ShRUIOp>(loc, a, c); }
  Value shl(Value a, unsigned k) { return shl(a, i(k)); }
  Value shr(Value a, unsigned k) { return shr(a, i(k)); }
  Value iand(Value a, uint32_t m) { return iand(a, i(m)); }
  Value iadd(Value a, uint32_t k) { return k ? iadd(a, i(k)) : a; }
  Value remsi(Value a, Value c) { return b.create<arith::RemSIOp>(loc, a, c); }
  Value cmpi(arith::CmpIPredicate p, Value a, Value c) {
    return b.create<arith::CmpIOp>(loc, p, a, c);
  }
  /// (a & mask) != 0
  Value test(Value a, uint32_t mask) {
    return cmpi(arith::CmpIPredicate::ne, iand(a, mask), i(0));
  }
  Value ult(Value a, uint32_t k) {
    return cmpi(arith::CmpIPredicate::ult, a, i(k));
  }
  Value eq(Value a, uint32_t k) {
    return cmpi(arith::CmpIPredicate::eq, a, i(k));
  }

  // Booleans.
  Value band(Value a, Value c) { return b.create<arith::AndIOp>(loc, a, c); }
  Value bor(Value a, Value c) { return b.create<arith::OrIOp>(loc, a, c); }
  Value bnot(Value a) {
    if (!trueConst)
      trueConst = constant(bty, b.getIntegerAttr(b.getI1Type(), 1));
    return b.create<arith::XOrIOp>(loc, a, trueConst);
  }
  Value select(Value c, Value t, Value e) {
    return b.create<arith::SelectOp>(loc, c, t, e);
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

  // Conversions.
  Value sitofp(Value a) { return b.create<arith::SIToFPOp>(loc, fty, a); }
  Value uitofp(Value a) { return b.create<arith::UIToFPOp>(loc, fty, a); }
  Value bitsOf(Value a) { return b.create<arith::BitcastOp>(loc, ity, a); }
  /// 0/1 as i32 from an i1.
  Value zext(Value cond) { return b.create<arith::ExtUIOp>(loc, ity, cond); }

  //===--------------------------------------------------------------------===//
  // Shared noise pieces
  //===--------------------------------------------------------------------===//

  Value rotl(Value x, unsigned k) { return ior(shl(x, k), shr(x, 32 - k)); }

  void bjmix(Value &a, Value &bb, Value &c) {
    a = isub(a, c); a = ixor(a, rotl(c, 4));  c = iadd(c, bb);
    bb = isub(bb, a); bb = ixor(bb, rotl(a, 6));  a = iadd(a, c);
    c = isub(c, bb); c = ixor(c, rotl(bb, 8));  bb = iadd(bb, a);
    a = isub(a, c); a = ixor(a, rotl(c, 16)); c = iadd(c, bb);
    bb = isub(bb, a); bb = ixor(bb, rotl(a, 19)); a = iadd(a, c);
    c = isub(c, bb); c = ixor(c, rotl(bb, 4));  bb = iadd(bb, a);
  }

  Value bjfinal(Value a, Value bb, Value c) {
    c = ixor(c, bb); c = isub(c, rotl(bb, 14));
    a = ixor(a, c); a = isub(a, rotl(c, 11));
    bb = ixor(bb, a); bb = isub(bb, rotl(a, 25));
    c = ixor(c, bb); c = isub(c, rotl(bb, 16));
    a = ixor(a, c); a = isub(a, rotl(c, 4));
    bb = ixor(bb, a); bb = isub(bb, rotl(a, 14));
    c = ixor(c, bb); c = isub(c, rotl(bb, 24));
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

  OpBuilder &b;
  Location loc;
  Type fty, ity, bty;

private:
  llvm::DenseMap<uint32_t, Value> floatConsts, intConsts;
  Value trueConst;
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

#endif // OSLTRANSFORMS_NOISEEMITTER_H
