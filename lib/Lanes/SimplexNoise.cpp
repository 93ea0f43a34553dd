//===- SimplexNoise.cpp - OSL's simplex noise as lane ops -----------------===//
//
// OSL's simplex noise (simplexnoise.cpp's algorithm): the simplex around a
// point, its corners' gradients from packed tables, and their falloff sum.
//
//===----------------------------------------------------------------------===//
#include "NoiseEmitter.h"

using namespace mlir;

namespace mlir::osl::noise {

//===----------------------------------------------------------------------===//
// Simplex
//===----------------------------------------------------------------------===//

/// OSL's `scramble`: bjfinal(v0, v1, v2 ^ 0xdeadbeef).
static Value scramble(Emitter &e, Value v0, Value v1, Value v2) {
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
static Value unpack(Emitter &e, Value packed, Value idx) {
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

static SimplexCell simplexCell(Emitter &e, ValueRange p, float F, float G) {
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

} // namespace mlir::osl::noise
