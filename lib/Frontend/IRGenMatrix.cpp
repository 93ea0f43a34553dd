//===- IRGenMatrix.cpp - The matrix type: 16 floats, row-major ------------===//
//
// A matrix lives in the front end only: 16 f32 values, row-major, whose
// operations become ordinary lane arithmetic, so the IR needs no matrix
// type and every width computes the same bits. Conventions are Imath's (as
// OSL uses it): points are row vectors, p' = p * M, so a product A * B
// applies A first.
//
// Constants fold as they are built (in float, one operation at a time, as
// the ops compute), so the matrices of named spaces, literals and their
// inverses cost nothing at run time.
//
//===----------------------------------------------------------------------===//
#include "IRGen.h"

#include "mlir/Dialect/Arith/IR/Arith.h"

#include <cfloat>
#include <cmath>

using namespace osl::frontend;
using namespace mlir;
using namespace mlir::osl;

namespace {
std::optional<float> constF32(Value v) {
  if (auto c = v.getDefiningOp<arith::ConstantOp>())
    if (auto fa = dyn_cast<FloatAttr>(c.getValue()))
      return float(fa.getValueAsDouble());
  return std::nullopt;
}

/// Element (i, j).
inline int at(int i, int j) { return 4 * i + j; }
} // namespace

//===----------------------------------------------------------------------===//
// Lane arithmetic that folds constants
//===----------------------------------------------------------------------===//

Value IRGen::fAdd(Value x, Value y, SrcLoc l) {
  auto a = constF32(x), c = constF32(y);
  if (a && c)
    return constFloat(*a + *c, l);
  return b.create<AddOp>(loc(l), x, y);
}

Value IRGen::fSub(Value x, Value y, SrcLoc l) {
  auto a = constF32(x), c = constF32(y);
  if (a && c)
    return constFloat(*a - *c, l);
  return b.create<SubOp>(loc(l), x, y);
}

Value IRGen::fMul(Value x, Value y, SrcLoc l) {
  auto a = constF32(x), c = constF32(y);
  if (a && c)
    return constFloat(*a * *c, l);
  // Matrix code is OSL's C++: x * 0 keeps its sign.
  auto product = b.create<MulOp>(loc(l), x, y);
  product->setAttr(kIeeeProductAttr, b.getUnitAttr());
  return product;
}

Value IRGen::fDiv(Value x, Value y, SrcLoc l) {
  auto a = constF32(x), c = constF32(y);
  if (a && c)
    return constFloat(*c == 0 ? 0.0f : *a / *c, l);
  return b.create<DivOp>(loc(l), x, y);
}

Value IRGen::fNeg(Value x, SrcLoc l) {
  if (auto a = constF32(x))
    return constFloat(-*a, l);
  return b.create<NegOp>(loc(l), x);
}

Value IRGen::fAbs(Value x, SrcLoc l) {
  if (auto a = constF32(x))
    return constFloat(std::fabs(*a), l);
  return b.create<AbsOp>(loc(l), x);
}

Value IRGen::cmp(StringRef pred, Value x, Value y, SrcLoc l, bool unordered) {
  auto a = getConstScalar(x), c = getConstScalar(y);
  if (a && c) {
    bool r = (unordered && (std::isnan(*a) || std::isnan(*c))) ? true
             : pred == "eq" ? *a == *c
             : pred == "ne" ? *a != *c
             : pred == "lt" ? *a < *c
             : pred == "le" ? *a <= *c
             : pred == "gt" ? *a > *c
                            : *a >= *c;
    return constBool(r, l);
  }
  return b.create<CmpOp>(loc(l), pred, x, y, unordered);
}

Value IRGen::select(Value c, Value x, Value y, SrcLoc l) {
  if (auto k = getConstBool(c))
    return *k ? x : y;
  if (x == y)
    return x;
  return b.create<SelectOp>(loc(l), c, x, y);
}

Value IRGen::boolAnd(Value x, Value y, SrcLoc l) {
  if (auto k = getConstBool(x))
    return *k ? y : x;
  if (auto k = getConstBool(y))
    return *k ? x : y;
  return b.create<AndOp>(loc(l), x, y);
}

Value IRGen::boolOr(Value x, Value y, SrcLoc l) {
  if (auto k = getConstBool(x))
    return *k ? x : y;
  if (auto k = getConstBool(y))
    return *k ? y : x;
  return b.create<OrOp>(loc(l), x, y);
}

Value IRGen::boolNot(Value x, SrcLoc l) {
  if (auto k = getConstBool(x))
    return constBool(!*k, l);
  return b.create<NotOp>(loc(l), x);
}

//===----------------------------------------------------------------------===//
// Construction
//===----------------------------------------------------------------------===//

RValue IRGen::matrixValue(MatrixElems elems) {
  RValue r;
  r.type = OslType(BaseType::Matrix);
  r.elems = std::move(elems);
  return r;
}

RValue IRGen::scaledIdentity(Value f, SrcLoc l) {
  f = convert(f, b.getF32Type(), l);
  Value zero = constFloat(0, l);
  MatrixElems m(16, zero);
  for (int i = 0; i < 4; ++i)
    m[at(i, i)] = f;
  return matrixValue(m);
}

RValue IRGen::constMatrix(const Matrix44 &m, SrcLoc l) {
  MatrixElems e;
  for (double d : m)
    e.push_back(constFloat(float(d), l));
  return matrixValue(e);
}

RValue IRGen::namedMatrix(StringRef from, StringRef to, SrcLoc l, bool &known) {
  // OSL multiplies from->common by common->to; a lookup that fails gives
  // the identity for its half (and the call reports failure).
  const Matrix44 identity{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  if (auto direct = namedSpaceTransform(from, to, options.camera)) {
    known = true;
    return constMatrix(*direct, l);
  }
  auto fromCommon = namedSpaceTransform(from, "common", options.camera);
  auto toSpace = namedSpaceTransform("common", to, options.camera);
  known = false;
  knownSpaces(*this, from, to, l); // reports the unknown names
  RValue a = constMatrix(fromCommon ? *fromCommon : identity, l);
  RValue c = constMatrix(toSpace ? *toSpace : identity, l);
  return matrixValue(matrixMultiply(a.elems, c.elems, l));
}

//===----------------------------------------------------------------------===//
// Arithmetic
//===----------------------------------------------------------------------===//

IRGen::MatrixElems IRGen::matrixMultiply(const MatrixElems &a, const MatrixElems &m,
                                         SrcLoc l) {
  MatrixElems r(16);
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) {
      Value sum = fMul(a[at(i, 0)], m[at(0, j)], l);
      for (int k = 1; k < 4; ++k)
        sum = fAdd(sum, fMul(a[at(i, k)], m[at(k, j)], l), l);
      r[at(i, j)] = sum;
    }
  return r;
}

IRGen::MatrixElems IRGen::matrixScale(const MatrixElems &a, Value f, SrcLoc l) {
  f = convert(f, b.getF32Type(), l);
  MatrixElems r;
  for (Value x : a)
    r.push_back(fMul(x, f, l));
  return r;
}

IRGen::MatrixElems IRGen::matrixTranspose(const MatrixElems &a) {
  MatrixElems r(16);
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      r[at(j, i)] = a[at(i, j)];
  return r;
}

Value IRGen::matrixDeterminant(const MatrixElems &m, SrcLoc l) {
  // Cofactor expansion along the first row, as OSL's det4x4.
  auto det2 = [&](Value a, Value bb, Value c, Value d) {
    return fSub(fMul(a, d, l), fMul(bb, c, l), l);
  };
  // | a1 b1 c1 ; a2 b2 c2 ; a3 b3 c3 | with the arguments given column by column.
  auto det3 = [&](Value a1, Value a2, Value a3, Value b1, Value b2, Value b3, Value c1,
                  Value c2, Value c3) {
    Value t = fMul(a1, det2(b2, b3, c2, c3), l);
    t = fSub(t, fMul(b1, det2(a2, a3, c2, c3), l), l);
    return fAdd(t, fMul(c1, det2(a2, a3, b2, b3), l), l);
  };
  auto e = [&](int i, int j) { return m[at(i, j)]; };
  // Row r of the matrix is (a, b, c, d) r+1 in det4x4's naming.
  Value a2 = e(1, 0), b2 = e(1, 1), c2 = e(1, 2), d2 = e(1, 3);
  Value a3 = e(2, 0), b3 = e(2, 1), c3 = e(2, 2), d3 = e(2, 3);
  Value a4 = e(3, 0), b4 = e(3, 1), c4 = e(3, 2), d4 = e(3, 3);
  Value r = fMul(e(0, 0), det3(b2, b3, b4, c2, c3, c4, d2, d3, d4), l);
  r = fSub(r, fMul(e(0, 1), det3(a2, a3, a4, c2, c3, c4, d2, d3, d4), l), l);
  r = fAdd(r, fMul(e(0, 2), det3(a2, a3, a4, b2, b3, b4, d2, d3, d4), l), l);
  return fSub(r, fMul(e(0, 3), det3(a2, a3, a4, b2, b3, b4, c2, c3, c4), l), l);
}

//===----------------------------------------------------------------------===//
// Inverse
//===----------------------------------------------------------------------===//

namespace {
/// A 4x4 of lane values with row operations, for Gauss-Jordan.
struct Rows {
  IRGen::MatrixElems v;
  Value &operator()(int i, int j) { return v[4 * i + j]; }
};
} // namespace

IRGen::MatrixElems IRGen::matrixInverse(const MatrixElems &m, SrcLoc l) {
  Value zero = constFloat(0, l), one = constFloat(1, l);
  MatrixElems identity = scaledIdentity(one, l).elems;

  // Imath: the affine shortcut when the last column is (0, 0, 0, 1).
  Value affine = cmp("eq", m[at(0, 3)], zero, l);
  affine = boolAnd(affine, cmp("eq", m[at(1, 3)], zero, l), l);
  affine = boolAnd(affine, cmp("eq", m[at(2, 3)], zero, l), l);
  affine = boolAnd(affine, cmp("eq", m[at(3, 3)], one, l), l);

  auto affineInverse = [&]() -> std::optional<RValue> {
    auto x = [&](int i, int j) { return m[at(i, j)]; };
    auto cross = [&](Value a, Value c, Value d, Value e) {
      return fSub(fMul(a, c, l), fMul(d, e, l), l);
    };
    // The adjugate of the upper 3x3.
    Value s[3][3] = {
        {cross(x(1, 1), x(2, 2), x(2, 1), x(1, 2)), cross(x(2, 1), x(0, 2), x(0, 1), x(2, 2)),
         cross(x(0, 1), x(1, 2), x(1, 1), x(0, 2))},
        {cross(x(2, 0), x(1, 2), x(1, 0), x(2, 2)), cross(x(0, 0), x(2, 2), x(2, 0), x(0, 2)),
         cross(x(1, 0), x(0, 2), x(0, 0), x(1, 2))},
        {cross(x(1, 0), x(2, 1), x(2, 0), x(1, 1)), cross(x(2, 0), x(0, 1), x(0, 0), x(2, 1)),
         cross(x(0, 0), x(1, 1), x(1, 0), x(0, 1))}};
    Value det = fMul(x(0, 0), s[0][0], l);
    det = fAdd(det, fMul(x(0, 1), s[1][0], l), l);
    det = fAdd(det, fMul(x(0, 2), s[2][0], l), l);
    // |det| >= 1 always divides; below, an entry too large for the
    // quotient to be representable makes the matrix singular.
    Value absDet = fAbs(det, l);
    Value big = cmp("ge", absDet, one, l);
    Value scaledDet = fDiv(absDet, constFloat(FLT_MIN, l), l);
    Value overflow = constBool(false, l);
    for (auto &row : s)
      for (Value &e : row) {
        overflow = boolOr(overflow, boolNot(cmp("gt", scaledDet, fAbs(e, l), l), l), l);
        e = fDiv(e, det, l);
      }
    Value singular = boolAnd(boolNot(big, l), overflow, l);
    MatrixElems r(16, zero);
    r[at(3, 3)] = one;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        r[at(i, j)] = s[i][j];
    for (int j = 0; j < 3; ++j) {
      Value t = fMul(fNeg(x(3, 0), l), s[0][j], l);
      t = fSub(t, fMul(x(3, 1), s[1][j], l), l);
      r[at(3, j)] = fSub(t, fMul(x(3, 2), s[2][j], l), l);
    }
    for (int k = 0; k < 16; ++k)
      r[k] = select(singular, identity[k], r[k], l);
    return matrixValue(r);
  };

  auto gaussJordan = [&]() -> std::optional<RValue> {
    Rows t{m}, s{identity};
    Value singular = constBool(false, l);
    // Forward elimination with partial pivoting (the first of equal
    // magnitudes wins); rows are swapped per lane by selects.
    for (int i = 0; i < 3; ++i) {
      Value pivot = constInt(i, l);
      Value size = fAbs(t(i, i), l);
      for (int j = i + 1; j < 4; ++j) {
        Value mag = fAbs(t(j, i), l);
        Value larger = cmp("gt", mag, size, l);
        pivot = select(larger, constInt(j, l), pivot, l);
        size = select(larger, mag, size, l);
      }
      singular = boolOr(singular, cmp("eq", size, zero, l), l);
      for (Rows *r : {&t, &s}) {
        Rows old = *r;
        for (int j = i + 1; j < 4; ++j) {
          Value isPivot = cmp("eq", pivot, constInt(j, l), l);
          for (int k = 0; k < 4; ++k) {
            (*r)(i, k) = select(isPivot, old(j, k), (*r)(i, k), l);
            (*r)(j, k) = select(isPivot, old(i, k), old(j, k), l);
          }
        }
      }
      for (int j = i + 1; j < 4; ++j) {
        Value f = fDiv(t(j, i), t(i, i), l);
        for (int k = 0; k < 4; ++k) {
          t(j, k) = fSub(t(j, k), fMul(f, t(i, k), l), l);
          s(j, k) = fSub(s(j, k), fMul(f, s(i, k), l), l);
        }
      }
    }
    // Backward substitution.
    for (int i = 3; i >= 0; --i) {
      Value f = t(i, i);
      singular = boolOr(singular, cmp("eq", f, zero, l), l);
      for (int k = 0; k < 4; ++k) {
        t(i, k) = fDiv(t(i, k), f, l);
        s(i, k) = fDiv(s(i, k), f, l);
      }
      for (int j = 0; j < i; ++j) {
        Value g = t(j, i);
        for (int k = 0; k < 4; ++k) {
          t(j, k) = fSub(t(j, k), fMul(g, t(i, k), l), l);
          s(j, k) = fSub(s(j, k), fMul(g, s(i, k), l), l);
        }
      }
    }
    MatrixElems r(16);
    for (int k = 0; k < 16; ++k)
      r[k] = select(singular, identity[k], s.v[k], l);
    return matrixValue(r);
  };

  // Lanes with a general matrix are rare: the mask stack skips that arm
  // when no lane takes it.
  auto r = emitIfRegion(affine, l, {}, affineInverse, gaussJordan, /*wantValue=*/true);
  return r->elems;
}

//===----------------------------------------------------------------------===//
// Transforms and operators
//===----------------------------------------------------------------------===//

Value IRGen::transformByMatrix(const MatrixElems &matrix, Value x, BaseType kind,
                               SrcLoc l) {
  MatrixElems m = matrix;
  if (kind == BaseType::Normal)
    m = matrixTranspose(matrixInverse(matrix, l));
  bool varying = isVarying(x.getType());
  Type f32 = withUniformity(b.getF32Type(), varying);
  Value p[3];
  for (int i = 0; i < 3; ++i)
    p[i] = b.create<ExtractOp>(loc(l), f32, x, b.getI64IntegerAttr(i));
  // Column j of the row vector (p, 1) * M; only points take the last row.
  auto column = [&](int j) {
    Value sum = fMul(p[0], m[at(0, j)], l);
    sum = fAdd(sum, fMul(p[1], m[at(1, j)], l), l);
    sum = fAdd(sum, fMul(p[2], m[at(2, j)], l), l);
    return kind == BaseType::Point ? fAdd(sum, m[at(3, j)], l) : sum;
  };
  Value r[3] = {column(0), column(1), column(2)};
  if (kind == BaseType::Point) {
    // Projective: divide by w; w = 0 gives 0, which is what osl.div does.
    Value w = column(3);
    for (Value &c : r)
      c = fDiv(c, w, l);
  }
  return b.create<ConstructOp>(loc(l), r[0], r[1], r[2]);
}

std::optional<RValue> IRGen::emitMatrixBinaryOp(StringRef op, RValue lhs, RValue rhs,
                                                SrcLoc l) {
  auto invalid = [&]() -> std::optional<RValue> {
    error(l, "invalid operands to '" + op + "': '" + lhs.type.str() + "' and '" +
                 rhs.type.str() + "'");
    return std::nullopt;
  };
  bool lm = lhs.type.isMatrix(), rm = rhs.type.isMatrix();
  // The other operand may be a matrix or a number.
  if ((!lm && !lhs.type.isScalar()) || (!rm && !rhs.type.isScalar()))
    return invalid();
  if (op == "==" || op == "!=") {
    MatrixElems a = lm ? lhs.elems : scaledIdentity(lhs.value, l).elems;
    MatrixElems c = rm ? rhs.elems : scaledIdentity(rhs.value, l).elems;
    // As OSL: == and-s the elements' comparisons, != or-s them (both
    // unordered, so a NaN element makes both true).
    bool eq = op == "==";
    Value result = constBool(eq, l);
    for (int k = 0; k < 16; ++k) {
      Value e = cmp(eq ? "eq" : "ne", a[k], c[k], l, /*unordered=*/true);
      result = eq ? boolAnd(result, e, l) : boolOr(result, e, l);
    }
    return RValue::num(OslType(BaseType::Bool), result);
  }
  if (op == "*") {
    if (lm && rm)
      return matrixValue(matrixMultiply(lhs.elems, rhs.elems, l));
    return matrixValue(lm ? matrixScale(lhs.elems, rhs.value, l)
                          : matrixScale(rhs.elems, lhs.value, l));
  }
  if (op == "/") {
    if (lm && rm) // A / B = A * inverse(B)
      return matrixValue(matrixMultiply(lhs.elems, matrixInverse(rhs.elems, l), l));
    if (lm) {
      // OSL scales by 1/f (here a safe 1/f: dividing by 0 gives 0).
      Value f = convert(rhs.value, b.getF32Type(), l);
      return matrixValue(matrixScale(lhs.elems, fDiv(constFloat(1, l), f, l), l));
    }
    return matrixValue(matrixScale(matrixInverse(rhs.elems, l), lhs.value, l));
  }
  return invalid();
}
