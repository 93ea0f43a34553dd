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

#include "NoiseEmitter.h"

using namespace mlir;

namespace mlir::osl {
using namespace noise;
namespace {

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
  Value is12or14 = e.ieq(e.ior(h, e.i(2)), 14);
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
  case NoiseKind::perlin:
  case NoiseKind::uperlin: {
    auto hash = [&](ArrayRef<Value> key) { return e.inthash(key); };
    return perlinResults(e, coords, hash, channels,
                         kind == NoiseKind::uperlin);
  }
  case NoiseKind::cell:
  case NoiseKind::hash: {
    SmallVector<Value, 4> keys =
        kind == NoiseKind::cell ? cellKeys(e, coords) : hashKeys(e, coords);
    if (channels == 1)
      return {e.bitsTo01(e.inthash(keys))};
    std::array<Value, 3> t = hashTriple(e, keys);
    return {t[0], t[1], t[2]};
  }
  case NoiseKind::simplex:
  case NoiseKind::usimplex:
    return simplexResults(e, coords, channels, kind == NoiseKind::usimplex);
  case NoiseKind::gabor:
    break; // GaborBuilder.h builds it
  }
  llvm_unreachable("not a lattice noise");
}

SmallVector<Value, 3> periodicResults(Emitter &e, NoiseKind kind,
                                      ValueRange coords, ValueRange periods,
                                      unsigned channels) {
  assert(periods.size() == coords.size() && "one period per coordinate");
  switch (kind) {
  case NoiseKind::perlin:
  case NoiseKind::uperlin: {
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
                         kind == NoiseKind::uperlin);
  }
  case NoiseKind::cell:
  case NoiseKind::hash: {
    SmallVector<Value, 4> w = wrapCoords(e, coords, periods);
    return noiseResults(e, kind, w, channels);
  }
  case NoiseKind::simplex:
  case NoiseKind::usimplex:
  case NoiseKind::gabor: // OSL defines no periodic simplex or Gabor noise
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


} // namespace mlir::osl
