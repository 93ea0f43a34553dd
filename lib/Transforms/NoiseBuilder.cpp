//===- NoiseBuilder.cpp - Emit OSL noise as arith ops ---------------------===//
//
// OSL's noise functions built from `arith` ops (and `math.floor`), for f32 or
// vector<W x f32> operands. Every value below mirrors osl::ref
// (lib/Reference/Noise.cpp) operation for operation, in the same order and
// association, so the result is bit-identical to the scalar reference, and
// through it to OSL 1.13's scalar testshade, at every width. No FMA and no
// fast-math flags are ever set; a change here needs the same change there.
//
// The algorithms:
//
//  * Lattice hash: Bob Jenkins' lookup3 (bjmix, bjfinal) on i32 with
//    wrap-around add/sub, xor and rotates (shl | shrui); start value
//    0xdeadbeef + (nkeys << 2) + 13.
//  * floorfrac: i = fptosi(floor(x)), or INT_MIN when floor(x) is outside
//    the int32 range or NaN (x86 behaviour, made explicit so no lane depends
//    on a poison conversion); f = x - sitofp(i).
//  * Perlin: fade(t) = t*t*t * (t*(t*6 - 15) + 10); one hash per lattice
//    corner; branch-free gradients (arith.select) dotted with the corner
//    offsets; lerp(a, b, t) = a*(1-t) + b*t; 3D interpolates along z, then
//    x, then y (OSL's SIMD path), 4D does that for w = 0 and w = 1 and lerps
//    by w last; scales 0.25, 0.6616, 0.982, 0.8344 for 1D-4D. Unsigned
//    noise is 0.5 * (n + 1). Triples reuse the corner hashes, channel c
//    taking its gradient from hash >> 8c.
//  * Cell / hash noise: lookup3 of floor(coords) / of the coords' bit
//    patterns, mapped to [0, 1] by uitofp(h) * 2^-32. Triples hash one more
//    key (0, 1, 2).
//  * Simplex (Gustavson's sdnoise as adapted by OSL): skew, pick the simplex
//    by comparisons, per corner t = 0.5 - |d|^2 and t^4 * dot(grad, d) when
//    t >= 0 (else 0). Gradient tables are packed into i32 constants, two
//    bits per entry holding value + 1, and read with shifts.
//
//===----------------------------------------------------------------------===//

#include "OslTransforms/NoiseBuilder.h"
#include "OslTransforms/LaneMath.h"

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

using namespace mlir;

namespace mlir::osl {
namespace {

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

//===----------------------------------------------------------------------===//
// Perlin
//===----------------------------------------------------------------------===//

/// Maps the integer lattice coordinates of a corner to its 32 hash bits.
using LatticeHashFn = llvm::function_ref<Value(ArrayRef<Value>)>;

Value grad1(Emitter &e, Value hash, Value x) {
  Value h = e.iand(hash, 15u);
  Value g = e.sitofp(e.iadd(e.iand(h, 7u), 1u));
  g = e.negateIfBit(g, h, 3);
  return e.mul(g, x);
}

Value grad2(Emitter &e, Value hash, Value x, Value y) {
  Value h = e.iand(hash, 7u);
  Value lt4 = e.ult(h, 4);
  Value u = e.select(lt4, x, y);
  Value v = e.mul(e.f(2.0f), e.select(lt4, y, x));
  return e.add(e.negateIfBit(u, h, 0), e.negateIfBit(v, h, 1));
}

Value grad3(Emitter &e, Value hash, Value x, Value y, Value z) {
  Value h = e.iand(hash, 15u);
  Value u = e.select(e.ult(h, 8), x, y);
  // h == 12 || h == 14  <=>  (h | 2) == 14 for h in [0, 15].
  Value is12or14 = e.eq(e.ior(h, e.i(2)), 14);
  Value v = e.select(e.ult(h, 4), y, e.select(is12or14, x, z));
  return e.add(e.negateIfBit(u, h, 0), e.negateIfBit(v, h, 1));
}

Value grad4(Emitter &e, Value hash, Value x, Value y, Value z, Value w) {
  Value h = e.iand(hash, 31u);
  Value u = e.select(e.ult(h, 24), x, y);
  Value v = e.select(e.ult(h, 16), y, z);
  Value s = e.select(e.ult(h, 8), z, w);
  return e.add(e.add(e.negateIfBit(u, h, 0), e.negateIfBit(v, h, 1)),
               e.negateIfBit(s, h, 2));
}

/// The lattice cell around a point and the hashes of its 2^dims corners.
/// Corner c has offset (c >> a) & 1 along axis a.
struct PerlinCell {
  unsigned dims = 0;
  SmallVector<Value, 4> frac, frac1, fade; // per axis: f, f - 1, fade(f)
  SmallVector<Value, 16> cornerHash;
};

PerlinCell perlinCell(Emitter &e, ValueRange coords, LatticeHashFn hash) {
  PerlinCell cell;
  cell.dims = coords.size();
  SmallVector<Value, 4> lat, lat1;
  for (Value x : coords) {
    Value fx;
    Value xi = e.floorSplit(x, fx);
    lat.push_back(xi);
    lat1.push_back(e.iadd(xi, 1u));
    cell.frac.push_back(fx);
  }
  for (Value fx : cell.frac)
    cell.fade.push_back(e.fade(fx));
  for (Value fx : cell.frac)
    cell.frac1.push_back(e.sub(fx, e.f(1.0f)));
  for (unsigned c = 0; c < (1u << cell.dims); ++c) {
    SmallVector<Value, 4> key;
    for (unsigned a = 0; a < cell.dims; ++a)
      key.push_back((c >> a) & 1 ? lat1[a] : lat[a]);
    cell.cornerHash.push_back(hash(key));
  }
  return cell;
}

/// Interpolates a 3D cube of corner gradients g[0..7] (index x + 2y + 4z)
/// along z, then x, then y.
Value cubeLerp(Emitter &e, ArrayRef<Value> g, Value u, Value v, Value w) {
  Value xy[4];
  for (int c = 0; c < 4; ++c)
    xy[c] = e.lerp(g[c], g[c + 4], w);
  return e.lerp(e.lerp(xy[0], xy[1], u), e.lerp(xy[2], xy[3], u), v);
}

/// Signed, scaled Perlin noise of one channel; `shift` picks the hash byte
/// (0 for float results and channel 0 of triples, 8 and 16 for the others).
Value perlinChannel(Emitter &e, const PerlinCell &cell, unsigned shift) {
  unsigned dims = cell.dims;
  SmallVector<Value, 16> g;
  for (unsigned c = 0; c < (1u << dims); ++c) {
    Value h = cell.cornerHash[c];
    if (shift)
      h = e.shr(h, shift);
    auto rem = [&](unsigned a) {
      return (c >> a) & 1 ? cell.frac1[a] : cell.frac[a];
    };
    switch (dims) {
    case 1: g.push_back(grad1(e, h, rem(0))); break;
    case 2: g.push_back(grad2(e, h, rem(0), rem(1))); break;
    case 3: g.push_back(grad3(e, h, rem(0), rem(1), rem(2))); break;
    default: g.push_back(grad4(e, h, rem(0), rem(1), rem(2), rem(3))); break;
    }
  }
  const auto &fd = cell.fade;
  switch (dims) {
  case 1:
    return e.mul(e.f(0.25f), e.lerp(g[0], g[1], fd[0]));
  case 2: {
    Value r = e.lerp(e.lerp(g[0], g[1], fd[0]), e.lerp(g[2], g[3], fd[0]),
                     fd[1]);
    return e.mul(e.f(0.6616f), r);
  }
  case 3:
    return e.mul(e.f(0.9820f), cubeLerp(e, g, fd[0], fd[1], fd[2]));
  default: {
    Value w0 = cubeLerp(e, ArrayRef<Value>(g).take_front(8), fd[0], fd[1],
                        fd[2]);
    Value w1 = cubeLerp(e, ArrayRef<Value>(g).drop_front(8), fd[0], fd[1],
                        fd[2]);
    return e.mul(e.f(0.8344f), e.lerp(w0, w1, fd[3]));
  }
  }
}

//===----------------------------------------------------------------------===//
// Cell / hash noise
//===----------------------------------------------------------------------===//

/// The three channels of a triple-valued cell/hash noise of `keys`: the
/// hash of keys + (channel index) as an extra key.
std::array<Value, 3> hashTriple(Emitter &e, ArrayRef<Value> k) {
  std::array<Value, 3> out;
  switch (k.size()) {
  case 1:
  case 2:
    for (uint32_t c = 0; c < 3; ++c) {
      SmallVector<Value, 3> key(k.begin(), k.end());
      key.push_back(e.i(c));
      out[c] = e.bitsTo01(e.inthash(key));
    }
    return out;
  case 3: {
    // inthash(k0, k1, k2, c) with the bjmix of the first three shared.
    Value s = e.i(Emitter::startValue(4));
    Value a = e.iadd(s, k[0]), bb = e.iadd(s, k[1]), cc = e.iadd(s, k[2]);
    e.bjmix(a, bb, cc);
    for (uint32_t c = 0; c < 3; ++c)
      out[c] = e.bitsTo01(e.bjfinal(e.iadd(a, c), bb, cc));
    return out;
  }
  default: {
    // inthash(k0, k1, k2, k3, c).
    Value s = e.i(Emitter::startValue(5));
    Value a = e.iadd(s, k[0]), bb = e.iadd(s, k[1]), cc = e.iadd(s, k[2]);
    e.bjmix(a, bb, cc);
    a = e.iadd(a, k[3]);
    for (uint32_t c = 0; c < 3; ++c)
      out[c] = e.bitsTo01(e.bjfinal(a, e.iadd(bb, c), cc));
    return out;
  }
  }
}

SmallVector<Value, 4> cellKeys(Emitter &e, ValueRange coords) {
  SmallVector<Value, 4> k;
  for (Value x : coords)
    k.push_back(e.ifloor(x));
  return k;
}

SmallVector<Value, 4> hashKeys(Emitter &e, ValueRange coords) {
  SmallVector<Value, 4> k;
  for (Value x : coords)
    k.push_back(e.bitsOf(x));
  return k;
}

//===----------------------------------------------------------------------===//
// Simplex
//===----------------------------------------------------------------------===//

/// OSL's `scramble`: bjfinal(v0, v1, v2 ^ 0xdeadbeef).
Value scramble(Emitter &e, Value v0, Value v1, Value v2) {
  return e.bjfinal(v0, v1, e.ixor(v2, e.i(0xdeadbeefu)));
}

// Gradient tables (OSL's simplexnoise.cpp), packed two bits per entry as
// value + 1 so that a lane reads entry h with ((table >> 2h) & 3) - 1.
constexpr int8_t kGrad2[8][2] = {{-1, -1}, {1, 0},  {-1, 0}, {1, 1},
                                 {-1, 1},  {0, -1}, {0, 1},  {1, -1}};
constexpr int8_t kGrad3[16][3] = {
    {1, 0, 1},  {0, 1, 1},  {-1, 0, 1},  {0, -1, 1},
    {1, 0, -1}, {0, 1, -1}, {-1, 0, -1}, {0, -1, -1},
    {1, -1, 0}, {1, 1, 0},  {-1, 1, 0},  {-1, -1, 0},
    {1, 0, 1},  {-1, 0, 1}, {0, 1, -1},  {0, -1, -1}};
/// 4D: the 32 tesseract edges; entry h is zero in component h >> 3 and has
/// signs from bits 2, 1, 0 (set = negative) on the other three in order.
constexpr int8_t grad4Entry(unsigned h, unsigned comp) {
  unsigned zeroAt = h >> 3;
  if (comp == zeroAt)
    return 0;
  unsigned slot = comp < zeroAt ? comp : comp - 1;
  return (h >> (2 - slot)) & 1 ? -1 : 1;
}

template <size_t N, size_t D>
constexpr uint32_t packColumn(const int8_t (&table)[N][D], unsigned comp,
                              unsigned first) {
  uint32_t packed = 0;
  for (unsigned h = 0; h < 16 && first + h < N; ++h)
    packed |= uint32_t(table[first + h][comp] + 1) << (2 * h);
  return packed;
}
constexpr uint32_t packGrad4(unsigned comp, unsigned first) {
  uint32_t packed = 0;
  for (unsigned h = 0; h < 16; ++h)
    packed |= uint32_t(grad4Entry(first + h, comp) + 1) << (2 * h);
  return packed;
}

/// Reads entry `idx` (< 16) of a packed table as a float in {-1, 0, 1}.
Value unpack(Emitter &e, Value packed, Value idx) {
  Value field = e.iand(e.shr(packed, e.shl(idx, 1)), 3u);
  return e.sitofp(e.isub(field, e.i(1)));
}

/// One simplex corner: t = 0.5 - |d|^2; t^4 * dot(g, d) if t >= 0, else 0.
/// `grad` gives component a of the corner's gradient.
Value simplexCorner(Emitter &e, ArrayRef<Value> d,
                    llvm::function_ref<Value(unsigned)> grad) {
  Value t = e.f(0.5f);
  for (Value di : d)
    t = e.sub(t, e.mul(di, di));
  Value t2 = e.mul(t, t);
  Value t4 = e.mul(t2, t2);
  Value dot = e.mul(grad(0), d[0]);
  for (unsigned a = 1; a < d.size(); ++a)
    dot = e.add(dot, e.mul(grad(a), d[a]));
  Value n = e.mul(t4, dot);
  return e.select(e.cmpf(arith::CmpFPredicate::OGE, t, e.f(0.0f)), n,
                  e.f(0.0f));
}

Value simplex1(Emitter &e, Value x, uint32_t seed) {
  Value x0;
  Value i0 = e.floorSplit(x, x0);
  Value i1 = e.iadd(i0, 1u);
  Value x1 = e.sub(x0, e.f(1.0f));
  auto corner = [&](Value ci, Value d) {
    Value t = e.sub(e.f(1.0f), e.mul(d, d));
    Value t2 = e.mul(t, t);
    Value t4 = e.mul(t2, t2);
    Value h = scramble(e, ci, e.i(seed), e.i(0));
    Value g = e.add(e.f(1.0f), e.sitofp(e.iand(h, 7u)));
    g = e.negateIfBit(g, h, 3);
    return e.mul(e.mul(t4, g), d);
  };
  Value n0 = corner(i0, x0);
  Value n1 = corner(i1, x1);
  return e.mul(e.f(0.36f), e.add(n0, n1));
}

/// Skewed simplex cell of a 2-4D point: lattice origin, distance to it, and
/// the unskew factor G.
struct SimplexCell {
  SmallVector<Value, 4> lat, d0;
};

SimplexCell simplexCell(Emitter &e, ValueRange p, float F, float G) {
  SimplexCell cell;
  Value sum = p[0];
  for (unsigned a = 1; a < p.size(); ++a)
    sum = e.add(sum, p[a]);
  Value s = e.mul(sum, e.f(F));
  for (Value x : p)
    cell.lat.push_back(e.ifloor(e.add(x, s)));
  Value latSum = cell.lat[0];
  for (unsigned a = 1; a < p.size(); ++a)
    latSum = e.iadd(latSum, cell.lat[a]);
  Value t = e.mul(e.sitofp(latSum), e.f(G));
  for (unsigned a = 0; a < p.size(); ++a)
    cell.d0.push_back(e.sub(p[a], e.sub(e.sitofp(cell.lat[a]), t)));
  return cell;
}

/// Corner n of a simplex with integer offset `off` (0/1 per axis as i1):
/// distance d0 - off + n*G, lattice point lat + off.
void simplexCorner(Emitter &e, const SimplexCell &cell, ArrayRef<Value> off,
                   float nG, SmallVectorImpl<Value> &d,
                   SmallVectorImpl<Value> &lat) {
  for (unsigned a = 0; a < cell.d0.size(); ++a) {
    Value offF = e.select(off[a], e.f(1.0f), e.f(0.0f));
    d.push_back(e.add(e.sub(cell.d0[a], offF), e.f(nG)));
    lat.push_back(e.iadd(cell.lat[a], e.zext(off[a])));
  }
}

/// The last corner, offset 1 on every axis: d0 - 1 + n*G.
void simplexLastCorner(Emitter &e, const SimplexCell &cell, float nG,
                       SmallVectorImpl<Value> &d,
                       SmallVectorImpl<Value> &lat) {
  for (unsigned a = 0; a < cell.d0.size(); ++a) {
    d.push_back(e.add(e.sub(cell.d0[a], e.f(1.0f)), e.f(nG)));
    lat.push_back(e.iadd(cell.lat[a], 1u));
  }
}

/// All corners of the simplex containing a 2-4D point: distance vectors
/// and lattice points, in OSL's order.
struct SimplexCorners {
  SmallVector<SmallVector<Value, 4>, 5> d, lat;
};

SimplexCorners simplexCorners(Emitter &e, ValueRange p) {
  using P = arith::CmpFPredicate;
  unsigned dims = p.size();
  // Skew factors are double literals in OSL, rounded to float.
  const float F[] = {0, 0, static_cast<float>(0.366025403),
                     static_cast<float>(0.333333333),
                     static_cast<float>(0.309016994)};
  const float G[] = {0, 0, static_cast<float>(0.211324865),
                     static_cast<float>(0.166666667),
                     static_cast<float>(0.138196601)};
  float g = G[dims];
  SimplexCell cell = simplexCell(e, p, F[dims], g);
  const auto &d0 = cell.d0;
  SimplexCorners sc;
  sc.d.emplace_back(d0.begin(), d0.end());
  sc.lat.emplace_back(cell.lat.begin(), cell.lat.end());

  // Offsets of the middle corners (as i1 per axis).
  SmallVector<SmallVector<Value, 4>, 3> offs;
  if (dims == 2) {
    Value xGtY = e.cmpf(P::OGT, d0[0], d0[1]);
    offs.push_back({xGtY, e.bnot(xGtY)});
  } else if (dims == 3) {
    // OSL's branches: x>=y ? (y>=z ? XYZ : x>=z ? XZY : ZXY)
    //                      : (y<z ? ZYX : x<z ? YZX : YXZ)
    Value A = e.cmpf(P::OGE, d0[0], d0[1]);
    Value B = e.cmpf(P::OGE, d0[1], d0[2]);
    Value C = e.cmpf(P::OGE, d0[0], d0[2]);
    Value D = e.cmpf(P::OLT, d0[1], d0[2]);
    Value E = e.cmpf(P::OLT, d0[0], d0[2]);
    Value nA = e.bnot(A), nB = e.bnot(B), nC = e.bnot(C), nD = e.bnot(D),
          nE = e.bnot(E);
    Value i1 = e.band(A, e.bor(B, C));
    Value j1 = e.band(nA, nD);
    Value k1 = e.select(A, e.band(nB, nC), D);
    Value i2 = e.bor(A, e.band(nD, nE));
    Value j2 = e.bor(nA, B);
    Value k2 = e.select(A, nB, e.bor(D, E));
    offs.push_back({i1, j1, k1});
    offs.push_back({i2, j2, k2});
  } else {
    // OSL looks the traversal up in a 64-entry table indexed by the six
    // pairwise comparisons; each valid entry holds the rank of each
    // coordinate, i.e. how many comparisons it wins. Corner n (1..3) is
    // offset along the axes of rank >= 4 - n. (Invalid entries need a NaN
    // coordinate, which zeroes every corner anyway.)
    Value gt[4][4];
    for (unsigned a = 0; a < 4; ++a)
      for (unsigned c = a + 1; c < 4; ++c)
        gt[a][c] = e.cmpf(P::OGT, d0[a], d0[c]);
    SmallVector<Value, 4> rank;
    for (unsigned a = 0; a < 4; ++a) {
      Value r = e.i(0);
      for (unsigned c = 0; c < 4; ++c) {
        if (c == a)
          continue;
        Value wins = a < c ? gt[a][c] : e.bnot(gt[c][a]);
        r = e.iadd(r, e.zext(wins));
      }
      rank.push_back(r);
    }
    for (uint32_t n = 1; n <= 3; ++n) {
      SmallVector<Value, 4> o;
      for (unsigned a = 0; a < 4; ++a)
        o.push_back(e.cmpi(arith::CmpIPredicate::uge, rank[a], e.i(4 - n)));
      offs.push_back(o);
    }
  }
  for (unsigned n = 0; n < offs.size(); ++n) {
    sc.d.emplace_back();
    sc.lat.emplace_back();
    simplexCorner(e, cell, offs[n], float(n + 1) * g, sc.d.back(),
                  sc.lat.back());
  }
  sc.d.emplace_back();
  sc.lat.emplace_back();
  simplexLastCorner(e, cell, float(dims) * g, sc.d.back(), sc.lat.back());
  return sc;
}

/// Signed simplex noise of a 2-4D point for one seed.
Value simplexN(Emitter &e, const SimplexCorners &sc, uint32_t seed) {
  unsigned dims = sc.d[0].size();
  Value sum;
  for (unsigned n = 0; n < sc.d.size(); ++n) {
    const auto &lat = sc.lat[n];
    Value contrib;
    if (dims == 2) {
      Value h = e.iand(scramble(e, lat[0], lat[1], e.i(seed)), 7u);
      contrib = simplexCorner(e, sc.d[n], [&](unsigned a) {
        return unpack(e, e.i(packColumn(kGrad2, a, 0)), h);
      });
    } else if (dims == 3) {
      Value inner = scramble(e, lat[2], e.i(seed), e.i(0));
      Value h = e.iand(scramble(e, lat[0], lat[1], inner), 15u);
      contrib = simplexCorner(e, sc.d[n], [&](unsigned a) {
        return unpack(e, e.i(packColumn(kGrad3, a, 0)), h);
      });
    } else {
      Value inner = scramble(e, lat[2], lat[3], e.i(seed));
      Value h = e.iand(scramble(e, lat[0], lat[1], inner), 31u);
      Value hi = e.test(h, 16);
      Value idx = e.iand(h, 15u);
      contrib = simplexCorner(e, sc.d[n], [&](unsigned a) {
        Value packed =
            e.select(hi, e.i(packGrad4(a, 16)), e.i(packGrad4(a, 0)));
        return unpack(e, packed, idx);
      });
    }
    sum = sum ? e.add(sum, contrib) : contrib;
  }
  const float scale[] = {0, 0, 64.0f, 68.0f, 54.0f};
  return e.mul(e.f(scale[dims]), sum);
}

//===----------------------------------------------------------------------===//
// Entry points
//===----------------------------------------------------------------------===//

Type checkOperands(ValueRange coords, ValueRange periods = {}) {
  assert(!coords.empty() && coords.size() <= 4 && "noise takes 1-4 coords");
  Type t = coords[0].getType();
  assert(llvm::all_of(coords, [&](Value v) { return v.getType() == t; }) &&
         "noise coords must share one type");
  assert(llvm::all_of(periods, [&](Value v) { return v.getType() == t; }) &&
         "noise periods must match the coords' type");
  (void)periods;
  return t;
}

/// p = max(ifloor(period), 1), OSL's periodic lattice hash setup.
SmallVector<Value, 4> latticePeriods(Emitter &e, ValueRange periods) {
  SmallVector<Value, 4> out;
  for (Value p : periods) {
    Value pi = e.ifloor(p);
    out.push_back(e.select(e.cmpi(arith::CmpIPredicate::slt, pi, e.i(1)),
                           e.i(1), pi));
  }
  return out;
}

/// Coordinate wrap of periodic cell/hash noise: s - p * floor(s / p) with
/// p = floor(period), raised to 1 if below.
SmallVector<Value, 4> wrapCoords(Emitter &e, ValueRange coords,
                                 ValueRange periods) {
  SmallVector<Value, 4> out;
  for (auto [s, period] : llvm::zip(coords, periods)) {
    Value p = e.floor(period);
    p = e.select(e.cmpf(arith::CmpFPredicate::OLT, p, e.f(1.0f)), e.f(1.0f),
                 p);
    out.push_back(e.sub(s, e.mul(p, e.floor(e.div(s, p)))));
  }
  return out;
}

/// Perlin for float or triple results with a given lattice hash.
SmallVector<Value, 3> perlinResults(Emitter &e, ValueRange coords,
                                    LatticeHashFn hash, unsigned channels,
                                    bool isUnsigned) {
  PerlinCell cell = perlinCell(e, coords, hash);
  SmallVector<Value, 3> out;
  for (unsigned c = 0; c < channels; ++c) {
    Value n = perlinChannel(e, cell, 8 * c);
    out.push_back(isUnsigned ? e.unsignedOf(n) : n);
  }
  return out;
}

SmallVector<Value, 3> simplexResults(Emitter &e, ValueRange coords,
                                     unsigned channels, bool isUnsigned) {
  SmallVector<Value, 3> out;
  if (coords.size() == 1) {
    for (uint32_t c = 0; c < channels; ++c) {
      Value n = simplex1(e, coords[0], c);
      out.push_back(isUnsigned ? e.unsignedOf(n) : n);
    }
    return out;
  }
  SimplexCorners sc = simplexCorners(e, coords);
  for (uint32_t c = 0; c < channels; ++c) {
    Value n = simplexN(e, sc, c);
    out.push_back(isUnsigned ? e.unsignedOf(n) : n);
  }
  return out;
}

SmallVector<Value, 3> noiseResults(Emitter &e, NoiseKind kind,
                                   ValueRange coords, unsigned channels) {
  switch (kind) {
  case NoiseKind::Perlin:
  case NoiseKind::UPerlin: {
    auto hash = [&](ArrayRef<Value> key) { return e.inthash(key); };
    return perlinResults(e, coords, hash, channels,
                         kind == NoiseKind::UPerlin);
  }
  case NoiseKind::Cell:
  case NoiseKind::Hash: {
    SmallVector<Value, 4> keys =
        kind == NoiseKind::Cell ? cellKeys(e, coords) : hashKeys(e, coords);
    if (channels == 1)
      return {e.bitsTo01(e.inthash(keys))};
    std::array<Value, 3> t = hashTriple(e, keys);
    return {t[0], t[1], t[2]};
  }
  case NoiseKind::Simplex:
  case NoiseKind::USimplex:
    return simplexResults(e, coords, channels, kind == NoiseKind::USimplex);
  }
  llvm_unreachable("unknown noise kind");
}

SmallVector<Value, 3> periodicResults(Emitter &e, NoiseKind kind,
                                      ValueRange coords, ValueRange periods,
                                      unsigned channels) {
  assert(periods.size() == coords.size() && "one period per coordinate");
  switch (kind) {
  case NoiseKind::Perlin:
  case NoiseKind::UPerlin: {
    SmallVector<Value, 4> per = latticePeriods(e, periods);
    auto hash = [&](ArrayRef<Value> key) {
      SmallVector<Value, 4> wrapped;
      for (auto [k, p] : llvm::zip(key, per)) {
        // imod: remainder in [0, p) (p >= 1, so no division trap).
        Value r = e.remsi(k, p);
        Value neg = e.cmpi(arith::CmpIPredicate::slt, r, e.i(0));
        wrapped.push_back(e.select(neg, e.iadd(r, p), r));
      }
      return e.inthash(wrapped);
    };
    return perlinResults(e, coords, hash, channels,
                         kind == NoiseKind::UPerlin);
  }
  case NoiseKind::Cell:
  case NoiseKind::Hash: {
    SmallVector<Value, 4> w = wrapCoords(e, coords, periods);
    return noiseResults(e, kind, w, channels);
  }
  case NoiseKind::Simplex:
  case NoiseKind::USimplex:
    return {};
  }
  llvm_unreachable("unknown noise kind");
}

std::array<Value, 3> toTriple(ArrayRef<Value> v) {
  if (v.size() != 3)
    return {Value(), Value(), Value()};
  return {v[0], v[1], v[2]};
}

} // namespace

Value buildNoiseFloat(OpBuilder &b, Location loc, NoiseKind kind,
                      ValueRange coords) {
  Emitter e(b, loc, checkOperands(coords));
  return noiseResults(e, kind, coords, 1).front();
}

std::array<Value, 3> buildNoiseTriple(OpBuilder &b, Location loc,
                                      NoiseKind kind, ValueRange coords) {
  Emitter e(b, loc, checkOperands(coords));
  return toTriple(noiseResults(e, kind, coords, 3));
}

Value buildPeriodicNoiseFloat(OpBuilder &b, Location loc, NoiseKind kind,
                              ValueRange coords, ValueRange periods) {
  Emitter e(b, loc, checkOperands(coords, periods));
  SmallVector<Value, 3> r = periodicResults(e, kind, coords, periods, 1);
  return r.empty() ? Value() : r.front();
}

std::array<Value, 3> buildPeriodicNoiseTriple(OpBuilder &b, Location loc,
                                              NoiseKind kind,
                                              ValueRange coords,
                                              ValueRange periods) {
  Emitter e(b, loc, checkOperands(coords, periods));
  return toTriple(periodicResults(e, kind, coords, periods, 3));
}

Value buildIntHash(OpBuilder &b, Location loc, ArrayRef<Value> keys) {
  assert(!keys.empty() && "inthash needs a key");
  Type keyType = keys.front().getType();
  Type floatType = b.getF32Type();
  if (auto vt = dyn_cast<VectorType>(keyType))
    floatType = VectorType::get(vt.getShape(), floatType);
  Emitter e(b, loc, floatType);
  // Float keys hash by their bits, as hashnoise's coordinates do.
  SmallVector<Value, 5> bits;
  for (Value k : keys)
    bits.push_back(isa<FloatType>(getElementTypeOrSelf(k.getType())) ? e.bitsOf(k) : k);
  return e.inthash(bits);
}

std::optional<NoiseKind> parseNoiseName(llvm::StringRef name) {
  return llvm::StringSwitch<std::optional<NoiseKind>>(name)
      .Cases("perlin", "snoise", NoiseKind::Perlin)
      .Cases("uperlin", "noise", NoiseKind::UPerlin)
      .Cases("cell", "cellnoise", NoiseKind::Cell)
      .Cases("hash", "hashnoise", NoiseKind::Hash)
      .Case("simplex", NoiseKind::Simplex)
      .Case("usimplex", NoiseKind::USimplex)
      .Default(std::nullopt);
}

} // namespace mlir::osl
