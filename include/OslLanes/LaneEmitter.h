//===- LaneEmitter.h - arith/math ops on one lane shape ---------*- C++ -*-===//
//
// The op helper the lane builders (noise, Gabor noise, colors) are written
// with: plain IEEE float ops, wrap-around i32 ops and i1 ops, on one lane
// shape: f32 / i32 / i1 for a uniform value, or vectors of W of them for a
// varying one. Each builder adds its own pieces by deriving from it.
//
//===----------------------------------------------------------------------===//
#ifndef OSLLANES_LANEEMITTER_H
#define OSLLANES_LANEEMITTER_H

#include "OslLanes/LaneMath.h"

#include "mlir/Dialect/Arith/IR/Arith.h"
#include "mlir/Dialect/Math/IR/Math.h"
#include "mlir/Dialect/Vector/IR/VectorOps.h"
#include "mlir/IR/Builders.h"
#include "mlir/IR/BuiltinAttributes.h"
#include "mlir/IR/BuiltinTypes.h"
#include "llvm/ADT/DenseMap.h"

#include <array>
#include <cstdint>
#include <cstring>

namespace mlir::osl {

class LaneEmitter {
public:
  /// Whether f() and i() reuse one constant per value: right for code
  /// built in one block, wrong where the builder moves in and out of loop
  /// bodies (a cached constant would not dominate its later uses).
  enum class Constants { Cached, Fresh };

  /// `floatType` is f32 or vector<W x f32> and fixes the lanes' shape; a
  /// null type leaves it open (constants then take the shape of a value,
  /// cst()).
  LaneEmitter(OpBuilder &b, Location loc, Type floatType = Type(),
              Constants constants = Constants::Fresh)
      : b(b), loc(loc), fty(floatType), cacheConstants(constants == Constants::Cached) {
    if (fty) {
      ity = withElement(b.getI32Type());
      bty = withElement(b.getI1Type());
    }
  }

  /// `element` in the lanes' shape.
  Type withElement(Type element) const {
    if (auto vt = dyn_cast_or_null<VectorType>(fty))
      return VectorType::get(vt.getShape(), element, vt.getScalableDims());
    return element;
  }
  bool isVector() const { return isa_and_nonnull<VectorType>(fty); }

  //--- Constants ---------------------------------------------------------===//

  /// `scalar` as a constant of `type`, splat if `type` is a vector.
  Value constant(Type type, TypedAttr scalar) {
    if (auto vt = dyn_cast<VectorType>(type)) {
      Attribute elt = scalar;
      return b.create<arith::ConstantOp>(loc, DenseElementsAttr::get(vt, ArrayRef(elt)));
    }
    return b.create<arith::ConstantOp>(loc, scalar);
  }
  Value f(float v) {
    uint32_t bits;
    std::memcpy(&bits, &v, sizeof bits);
    return cached(floatConsts, bits, [&] { return constant(fty, b.getF32FloatAttr(v)); });
  }
  Value i(uint32_t v) {
    return cached(intConsts, v, [&] {
      return constant(ity, IntegerAttr::get(b.getI32Type(), APInt(32, v)));
    });
  }
  /// `v` in the shape and element type of `like`.
  Value cst(Value like, double v) { return lane::constantLike(b, loc, like, v); }
  /// A uniform (scalar) value spread over the lanes.
  Value splat(Value uniform) {
    if (auto vt = dyn_cast_or_null<VectorType>(fty))
      if (!isa<VectorType>(uniform.getType()))
        return b.create<vector::BroadcastOp>(
            loc, VectorType::get(vt.getShape(), uniform.getType()), uniform);
    return uniform;
  }

  //--- Floats: plain IEEE ops, no fastmath flags ---------------------------===//

  Value add(Value x, Value y) { return b.create<arith::AddFOp>(loc, x, y); }
  Value sub(Value x, Value y) { return b.create<arith::SubFOp>(loc, x, y); }
  Value mul(Value x, Value y) { return b.create<arith::MulFOp>(loc, x, y); }
  Value div(Value x, Value y) { return b.create<arith::DivFOp>(loc, x, y); }
  Value neg(Value x) { return b.create<arith::NegFOp>(loc, x); }
  Value floor(Value x) { return b.create<math::FloorOp>(loc, x); }
  Value sqrt(Value x) { return b.create<math::SqrtOp>(loc, x); }
  Value exp(Value x) { return b.create<math::ExpOp>(loc, x); }
  Value cos(Value x) { return b.create<math::CosOp>(loc, x); }
  Value sin(Value x) { return b.create<math::SinOp>(loc, x); }
  Value abs(Value x) { return b.create<math::AbsFOp>(loc, x); }
  Value cmpf(arith::CmpFPredicate p, Value x, Value y) {
    return b.create<arith::CmpFOp>(loc, p, x, y);
  }
  Value lt(Value x, Value y) { return cmpf(arith::CmpFPredicate::OLT, x, y); }
  Value le(Value x, Value y) { return cmpf(arith::CmpFPredicate::OLE, x, y); }
  Value ge(Value x, Value y) { return cmpf(arith::CmpFPredicate::OGE, x, y); }
  Value feq(Value x, Value y) { return cmpf(arith::CmpFPredicate::OEQ, x, y); }
  /// x < y ? x : y, and the other way: the second operand where either is
  /// NaN.
  Value min(Value x, Value y) { return select(lt(x, y), x, y); }
  Value max(Value x, Value y) { return select(lt(y, x), x, y); }

  //--- i32 lanes: wrap-around, like C unsigned ---------------------------===//

  Value iadd(Value x, Value y) { return b.create<arith::AddIOp>(loc, x, y); }
  Value iadd(Value x, uint32_t k) { return k ? iadd(x, i(k)) : x; }
  Value isub(Value x, Value y) { return b.create<arith::SubIOp>(loc, x, y); }
  Value imul(Value x, Value y) { return b.create<arith::MulIOp>(loc, x, y); }
  Value ixor(Value x, Value y) { return b.create<arith::XOrIOp>(loc, x, y); }
  Value iand(Value x, Value y) { return b.create<arith::AndIOp>(loc, x, y); }
  Value iand(Value x, uint32_t mask) { return iand(x, i(mask)); }
  Value ior(Value x, Value y) { return b.create<arith::OrIOp>(loc, x, y); }
  Value shl(Value x, Value y) { return b.create<arith::ShLIOp>(loc, x, y); }
  Value shr(Value x, Value y) { return b.create<arith::ShRUIOp>(loc, x, y); }
  Value shl(Value x, unsigned k) { return shl(x, i(k)); }
  Value shr(Value x, unsigned k) { return shr(x, i(k)); }
  Value remsi(Value x, Value y) { return b.create<arith::RemSIOp>(loc, x, y); }
  Value cmpi(arith::CmpIPredicate p, Value x, Value y) {
    return b.create<arith::CmpIOp>(loc, p, x, y);
  }
  /// (x & mask) != 0
  Value test(Value x, uint32_t mask) {
    return cmpi(arith::CmpIPredicate::ne, iand(x, mask), i(0));
  }
  Value ult(Value x, uint32_t k) { return cmpi(arith::CmpIPredicate::ult, x, i(k)); }
  Value ieq(Value x, uint32_t k) { return cmpi(arith::CmpIPredicate::eq, x, i(k)); }

  //--- Booleans and selects ----------------------------------------------===//

  Value band(Value x, Value y) { return b.create<arith::AndIOp>(loc, x, y); }
  Value bor(Value x, Value y) { return b.create<arith::OrIOp>(loc, x, y); }
  Value bnot(Value x) {
    Value one = cached(boolConsts, 1, [&] {
      return constant(bty, b.getIntegerAttr(b.getI1Type(), 1));
    });
    return b.create<arith::XOrIOp>(loc, x, one);
  }
  Value select(Value c, Value t, Value e) { return b.create<arith::SelectOp>(loc, c, t, e); }
  std::array<Value, 3> select(Value c, const std::array<Value, 3> &t,
                              const std::array<Value, 3> &e) {
    return {select(c, t[0], e[0]), select(c, t[1], e[1]), select(c, t[2], e[2])};
  }
  /// True if any lane of `mask` is (a scalar mask is its own answer).
  Value any(Value mask) { return lane::any(b, loc, mask); }

  //--- Conversions --------------------------------------------------------===//

  Value sitofp(Value x) { return b.create<arith::SIToFPOp>(loc, fty, x); }
  Value uitofp(Value x) { return b.create<arith::UIToFPOp>(loc, fty, x); }
  Value bitsOf(Value x) { return b.create<arith::BitcastOp>(loc, ity, x); }
  /// 0/1 as i32 from an i1.
  Value zext(Value cond) { return b.create<arith::ExtUIOp>(loc, ity, cond); }

  OpBuilder &b;
  Location loc;
  Type fty, ity, bty;

private:
  template <typename Make>
  Value cached(llvm::DenseMap<uint32_t, Value> &cache, uint32_t key, Make make) {
    if (!cacheConstants)
      return make();
    Value &slot = cache[key];
    if (!slot)
      slot = make();
    return slot;
  }

  bool cacheConstants;
  llvm::DenseMap<uint32_t, Value> floatConsts, intConsts, boolConsts;
};

} // namespace mlir::osl

#endif // OSLLANES_LANEEMITTER_H
