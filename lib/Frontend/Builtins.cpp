//===- Builtins.cpp - OSL library functions as osl ops ----------------------===//
//
// Most functions are described by an overload table: signatures in a
// compact code (f float, i int, s string, p/v/n/c point/vector/normal/
// color, T any triple, the same kind throughout one call) and an emitter.
// Overloads are ranked by the cost of the implicit conversions they need.
// Functions with string options, variable argument lists or a result type
// chosen by context (noise, transform, spline, type constructors) are
// handled by hand.
//
//===----------------------------------------------------------------------===//
#include "IRGen.h"
#include "OslRuntime/ClosureCall.h"
#include "OslRuntime/StringCall.h"
#include "OslTransforms/ColorBuilder.h"

#include "mlir/Dialect/Arith/IR/Arith.h"
#include "mlir/IR/Matchers.h"
#include "llvm/ADT/StringSwitch.h"

#include <cmath>

using namespace osl::frontend;
using namespace mlir;
using namespace mlir::osl;

namespace {

using Vals = llvm::ArrayRef<Value>;
using EmitFn = Value (*)(IRGen &, SrcLoc, Vals, OslType);

struct Sig {
  const char *ret;
  const char *args;
};

struct Builtin {
  const char *name;
  std::vector<Sig> sigs;
  EmitFn emit;
};

/// Scalars promoted to the result's triple type, so same-typed ops apply
/// to e.g. pow(color, float).
Value promote(IRGen &g, Value v, OslType result, SrcLoc l) {
  if (!result.isTriple())
    return v;
  return g.convert(v, irType(g.builder(), result), l);
}

template <typename OpT>
Value unary(IRGen &g, SrcLoc l, Vals a, OslType r) {
  return g.builder().create<OpT>(g.loc(l), promote(g, a[0], r, l));
}
template <typename OpT>
Value binary(IRGen &g, SrcLoc l, Vals a, OslType r) {
  return g.builder().create<OpT>(g.loc(l), promote(g, a[0], r, l), promote(g, a[1], r, l));
}
template <typename OpT>
Value ternary(IRGen &g, SrcLoc l, Vals a, OslType r) {
  return g.builder().create<OpT>(g.loc(l), promote(g, a[0], r, l), promote(g, a[1], r, l),
                                 promote(g, a[2], r, l));
}
/// Ops whose operands are triples and whose result is not (dot, length).
template <typename OpT>
Value geometric1(IRGen &g, SrcLoc l, Vals a, OslType) {
  return g.builder().create<OpT>(g.loc(l), a[0]);
}
template <typename OpT>
Value geometric2(IRGen &g, SrcLoc l, Vals a, OslType) {
  return g.builder().create<OpT>(g.loc(l), a[0], a[1]);
}

Value emitLog(IRGen &g, SrcLoc l, Vals a, OslType r) {
  OpBuilder &b = g.builder();
  Value x = promote(g, a[0], r, l);
  Value lx = b.create<LogOp>(g.loc(l), x);
  if (a.size() == 1)
    return lx;
  Value lb = b.create<LogOp>(g.loc(l), promote(g, a[1], r, l));
  return b.create<DivOp>(g.loc(l), lx, lb);
}

/// mod(a, b) = a - b * floor(a / b) (floats); a - b * (a / b) for ints.
Value emitMod(IRGen &g, SrcLoc l, Vals a, OslType r) {
  OpBuilder &b = g.builder();
  Location ml = g.loc(l);
  Value x = promote(g, a[0], r, l), y = promote(g, a[1], r, l);
  Value q = b.create<DivOp>(ml, x, y);
  if (!r.isInt())
    q = b.create<FloorOp>(ml, q);
  return b.create<SubOp>(ml, x, b.create<MulOp>(ml, y, q));
}

Value scaleBy(IRGen &g, SrcLoc l, Value x, OslType r, double factor) {
  Value k = promote(g, g.constFloat(float(factor), l), r, l);
  return g.builder().create<MulOp>(g.loc(l), x, k);
}
// stdosl.h's x*(180.0/M_PI) and x*(M_PI/180.0), whose constant oslc folds
// in float from M_PI as a float.
constexpr float kFloatPi = 3.14159265358979323846f;
Value emitRadians(IRGen &g, SrcLoc l, Vals a, OslType r) {
  return scaleBy(g, l, a[0], r, kFloatPi / 180.0f);
}
Value emitDegrees(IRGen &g, SrcLoc l, Vals a, OslType r) {
  return scaleBy(g, l, a[0], r, 180.0f / kFloatPi);
}

/// isnan/isinf/isfinite as IEEE comparisons (x != x only for NaN;
/// |x| == inf; |x| < inf is false for NaN), giving OSL's int.
Value classifyResult(IRGen &g, SrcLoc l, Value flag) {
  Type i32 = g.builder().getI32Type();
  return g.builder().create<ConvertOp>(g.loc(l), withUniformity(i32, isVarying(flag.getType())),
                                       flag);
}
Value emitIsNan(IRGen &g, SrcLoc l, Vals a, OslType) {
  return classifyResult(g, l, g.builder().create<CmpOp>(g.loc(l), "ne", a[0], a[0]));
}
Value emitIsInf(IRGen &g, SrcLoc l, Vals a, OslType) {
  Value mag = g.builder().create<AbsOp>(g.loc(l), a[0]);
  return classifyResult(g, l, g.builder().create<CmpOp>(g.loc(l), "eq", mag,
                                                        g.constFloat(INFINITY, l)));
}
Value emitIsFinite(IRGen &g, SrcLoc l, Vals a, OslType) {
  Value mag = g.builder().create<AbsOp>(g.loc(l), a[0]);
  return classifyResult(g, l, g.builder().create<CmpOp>(g.loc(l), "lt", mag,
                                                        g.constFloat(INFINITY, l)));
}

Value emitHypot(IRGen &g, SrcLoc l, Vals a, OslType) {
  OpBuilder &b = g.builder();
  Location ml = g.loc(l);
  Value sum = b.create<MulOp>(ml, a[0], a[0]);
  for (Value v : a.drop_front())
    sum = b.create<AddOp>(ml, sum, b.create<MulOp>(ml, v, v));
  return b.create<SqrtOp>(ml, sum);
}

/// select(a, b, cond): cond ? b : a, per component for a triple condition.
Value emitSelect(IRGen &g, SrcLoc l, Vals a, OslType r) {
  OpBuilder &b = g.builder();
  Location ml = g.loc(l);
  Value x = promote(g, a[0], r, l), y = promote(g, a[1], r, l), c = a[2];
  Type ct = getUniformType(c.getType());
  auto nonZero = [&](Value v) -> Value {
    Type t = getUniformType(v.getType());
    Value zero = t.isInteger(32) ? g.constInt(0, l) : g.constFloat(0, l);
    return b.create<CmpOp>(ml, "ne", v, zero);
  };
  if (!isTriple(ct))
    return b.create<SelectOp>(ml, nonZero(c), y, x);
  Value result = x;
  bool varying = isVarying(x.getType()) || isVarying(y.getType()) || isVarying(c.getType());
  for (int j = 0; j < 3; ++j) {
    auto extract = [&](Value v) -> Value {
      return b.create<ExtractOp>(ml, withUniformity(b.getF32Type(), isVarying(v.getType())),
                                 v, b.getI64IntegerAttr(j));
    };
    Value s = b.create<SelectOp>(ml, nonZero(extract(c)), extract(y), extract(x));
    result = b.create<InsertOp>(ml, withUniformity(irType(b, r), varying), s, result,
                                b.getI64IntegerAttr(j));
  }
  return result;
}

Value emitSurfaceArea(IRGen &g, SrcLoc l, Vals, OslType) {
  return g.getGlobal("surfacearea", g.builder().getF32Type(), l);
}
Value emitBackfacing(IRGen &g, SrcLoc l, Vals, OslType) {
  Value f = g.getGlobal("backfacing", g.builder().getF32Type(), l);
  return g.convert(f, g.builder().getI32Type(), l);
}

Value dotOf(IRGen &g, SrcLoc l, Value a, Value b) {
  return g.builder().create<DotOp>(g.loc(l), a, b);
}
Value splat(IRGen &g, SrcLoc l, Value f) {
  return g.convert(f, VectorType::get({3}, g.builder().getF32Type()), l);
}

/// distance(a, b), or from q to the segment [a, b]: the point at
/// t = clamp(dot(q - a, b - a) / dot(b - a, b - a), 0, 1) (0 if a == b).
Value emitDistance(IRGen &g, SrcLoc l, Vals a, OslType) {
  OpBuilder &b = g.builder();
  Location ml = g.loc(l);
  if (a.size() == 2)
    return b.create<DistanceOp>(ml, a[0], a[1]);
  Value d = b.create<SubOp>(ml, a[1], a[0]);
  Value t = b.create<DivOp>(ml, dotOf(g, l, b.create<SubOp>(ml, a[2], a[0]), d),
                            dotOf(g, l, d, d));
  t = b.create<ClampOp>(ml, t, g.constFloat(0, l), g.constFloat(1, l));
  Value closest = b.create<AddOp>(ml, a[0], b.create<MulOp>(ml, splat(g, l, t), d));
  return b.create<DistanceOp>(ml, a[2], closest);
}

/// reflect(I, N) = I - 2 dot(N, I) N.
Value emitReflect(IRGen &g, SrcLoc l, Vals a, OslType) {
  OpBuilder &b = g.builder();
  Location ml = g.loc(l);
  Value k = b.create<MulOp>(ml, g.constFloat(2, l), dotOf(g, l, a[1], a[0]));
  return b.create<SubOp>(ml, a[0], b.create<MulOp>(ml, splat(g, l, k), a[1]));
}

/// faceforward(N, I [, Nref = Ng]) = dot(I, Nref) > 0 ? -N : N.
Value emitFaceforward(IRGen &g, SrcLoc l, Vals a, OslType) {
  OpBuilder &b = g.builder();
  Location ml = g.loc(l);
  Value nref = a.size() == 3 ? a[2]
                             : g.getGlobal("Ng", VectorType::get({3}, b.getF32Type()), l);
  Value c = b.create<CmpOp>(ml, "gt", dotOf(g, l, a[1], nref), g.constFloat(0, l));
  return b.create<SelectOp>(ml, c, b.create<NegOp>(ml, a[0]), a[0]);
}

/// refract(I, N, eta): with c = dot(I, N), k = 1 - eta^2 (1 - c^2):
/// 0 if k < 0 (total internal reflection), else eta I - (eta c + sqrt k) N.
Value emitRefract(IRGen &g, SrcLoc l, Vals a, OslType) {
  OpBuilder &b = g.builder();
  Location ml = g.loc(l);
  Value eta = a[2];
  Value c = dotOf(g, l, a[0], a[1]);
  Value oneMinusC2 = b.create<SubOp>(ml, g.constFloat(1, l), b.create<MulOp>(ml, c, c));
  Value k = b.create<SubOp>(ml, g.constFloat(1, l),
                            b.create<MulOp>(ml, b.create<MulOp>(ml, eta, eta), oneMinusC2));
  Value s = b.create<AddOp>(ml, b.create<MulOp>(ml, eta, c), b.create<SqrtOp>(ml, k));
  Value r = b.create<SubOp>(ml, b.create<MulOp>(ml, splat(g, l, eta), a[0]),
                            b.create<MulOp>(ml, splat(g, l, s), a[1]));
  Value tir = b.create<CmpOp>(ml, "lt", k, g.constFloat(0, l));
  return b.create<SelectOp>(ml, tir, g.constTriple(0, 0, 0, l), r);
}

/// rotate(p, angle, axis) and rotate(p, angle, a, b) (axis b - a through
/// a): a right-handed rotation (Rodrigues' formula) about the normalized
/// axis.
Value emitRotate(IRGen &g, SrcLoc l, Vals a, OslType) {
  OpBuilder &b = g.builder();
  Location ml = g.loc(l);
  Value origin = a.size() == 4 ? a[2] : Value();
  Value axis = a.size() == 4 ? b.create<SubOp>(ml, a[3], a[2]).getResult() : a[2];
  Value k = b.create<NormalizeOp>(ml, axis);
  Value v = origin ? b.create<SubOp>(ml, a[0], origin).getResult() : a[0];
  Value cs = b.create<CosOp>(ml, a[1]);
  Value sn = b.create<SinOp>(ml, a[1]);
  Value oneMinusCos = b.create<SubOp>(ml, g.constFloat(1, l), cs);
  Value r = b.create<MulOp>(ml, v, splat(g, l, cs));
  r = b.create<AddOp>(ml, r, b.create<MulOp>(ml, b.create<CrossOp>(ml, k, v), splat(g, l, sn)));
  Value kd = b.create<MulOp>(ml, dotOf(g, l, k, v), oneMinusCos);
  r = b.create<AddOp>(ml, r, b.create<MulOp>(ml, k, splat(g, l, kd)));
  return origin ? b.create<AddOp>(ml, r, origin).getResult() : r;
}

/// Dx, Dy, Dz: the derivative is varying exactly when the value is.
Value derivOf(IRGen &g, SrcLoc l, Value v, char axis) {
  const char *name = axis == 'x' ? "x" : axis == 'y' ? "y" : "z";
  return g.builder().create<DerivOp>(g.loc(l), v.getType(), v, name);
}
template <char Axis>
Value emitDeriv(IRGen &g, SrcLoc l, Vals a, OslType) {
  return derivOf(g, l, a[0], Axis);
}
/// filterwidth(x) = sqrt(Dx(x)^2 + Dy(x)^2), per component for triples.
Value filterWidthOf(IRGen &g, SrcLoc l, Value x) {
  OpBuilder &b = g.builder();
  Location ml = g.loc(l);
  Value dx = derivOf(g, l, x, 'x'), dy = derivOf(g, l, x, 'y');
  return b.create<SqrtOp>(ml, b.create<AddOp>(ml, b.create<MulOp>(ml, dx, dx),
                                              b.create<MulOp>(ml, dy, dy)));
}
Value emitFilterWidth(IRGen &g, SrcLoc l, Vals a, OslType) {
  return filterWidthOf(g, l, a[0]);
}
/// area(p) = |Dx(p) x Dy(p)|; calculatenormal(p) = Dx(p) x Dy(p).
Value emitArea(IRGen &g, SrcLoc l, Vals a, OslType) {
  OpBuilder &b = g.builder();
  return b.create<LengthOp>(
      g.loc(l), b.create<CrossOp>(g.loc(l), derivOf(g, l, a[0], 'x'), derivOf(g, l, a[0], 'y')));
}
Value emitCalculateNormal(IRGen &g, SrcLoc l, Vals a, OslType) {
  return g.builder().create<CrossOp>(g.loc(l), derivOf(g, l, a[0], 'x'),
                                     derivOf(g, l, a[0], 'y'));
}
/// stdosl.h's aastep(edge, s [, ds | dedge, ds]): a box-filtered step,
/// 0 below edge - w/2, 1 above edge + w/2 and linear between, with
/// w = |dedge| + |ds| (filterwidths by default).
Value emitAaStep(IRGen &g, SrcLoc l, Vals a, OslType) {
  OpBuilder &b = g.builder();
  Location ml = g.loc(l);
  Value edge = a[0], s = a[1];
  Value dedge = a.size() == 4 ? a[2] : filterWidthOf(g, l, edge);
  Value ds = a.size() == 4 ? a[3] : a.size() == 3 ? a[2] : filterWidthOf(g, l, s);
  Value width = b.create<AddOp>(ml, b.create<AbsOp>(ml, dedge), b.create<AbsOp>(ml, ds));
  Value half = b.create<MulOp>(ml, g.constFloat(0.5f, l), width);
  Value lo = b.create<SubOp>(ml, edge, half), hi = b.create<AddOp>(ml, edge, half);
  Value ramp = b.create<DivOp>(ml, b.create<SubOp>(ml, s, lo), width);
  Value r = b.create<SelectOp>(ml, b.create<CmpOp>(ml, "ge", s, hi), g.constFloat(1, l), ramp);
  return b.create<SelectOp>(ml, b.create<CmpOp>(ml, "le", s, lo), g.constFloat(0, l), r);
}

/// stdosl.h's smooth_linearstep on floats: linear between the edges, with
/// quadratic ramps of half-width eps around each edge; a step when the
/// edges coincide.
Value smoothLinearStep1(IRGen &g, SrcLoc l, Value e0, Value e1, Value x, Value eps) {
  OpBuilder &b = g.builder();
  Location ml = g.loc(l);
  auto c = [&](float v) { return g.constFloat(v, l); };
  auto sub = [&](Value p, Value q) { return b.create<SubOp>(ml, p, q).getResult(); };
  auto mul = [&](Value p, Value q) { return b.create<MulOp>(ml, p, q).getResult(); };
  auto cmp = [&](const char *pred, Value p, Value q) {
    return b.create<CmpOp>(ml, pred, p, q).getResult();
  };
  auto sel = [&](Value cond, Value t, Value f) {
    return b.create<SelectOp>(ml, cond, t, f).getResult();
  };
  // rampup(x, r) = 0.5 / r * x * x
  auto rampup = [&](Value t, Value r) {
    return mul(mul(b.create<DivOp>(ml, c(0.5f), r), t), t);
  };
  Value widthInv = b.create<DivOp>(ml, c(1), sub(e1, e0));
  Value e = mul(eps, widthInv);
  Value t = mul(sub(x, e0), widthInv);
  Value twoE = mul(c(2), e);
  Value onePlusE = b.create<AddOp>(ml, c(1), e);
  Value r = sub(c(1), rampup(sub(onePlusE, t), twoE));
  r = sel(cmp("lt", t, e), rampup(b.create<AddOp>(ml, t, e), twoE), r);
  r = sel(cmp("ge", t, onePlusE), c(1), r);
  Value inside = b.create<AndOp>(ml, cmp("ge", t, e), cmp("le", t, sub(c(1), e)));
  r = sel(inside, t, r);
  r = sel(cmp("le", t, b.create<NegOp>(ml, e)), c(0), r);
  Value stepped = sel(cmp("lt", x, e0), c(0), c(1));
  return sel(cmp("ne", e0, e1), r, stepped);
}
/// The color functions, under the compile's working RGB space.
Value emitLuminance(IRGen &g, SrcLoc l, Vals a, OslType) {
  Type f32 = g.builder().getF32Type();
  return g.builder().create<LuminanceOp>(g.loc(l), withUniformity(f32, isVarying(a[0].getType())),
                                         g.workingColorSpace(), a[0]);
}
template <typename OpT>
Value emitSpectralColor(IRGen &g, SrcLoc l, Vals a, OslType r) {
  Type color = withUniformity(irType(g.builder(), r), isVarying(a[0].getType()));
  return g.builder().create<OpT>(g.loc(l), color, g.workingColorSpace(), a[0]);
}

Value emitSmoothLinearStep(IRGen &g, SrcLoc l, Vals a, OslType r) {
  if (!r.isTriple())
    return smoothLinearStep1(g, l, a[0], a[1], a[2], a[3]);
  OpBuilder &b = g.builder();
  Location ml = g.loc(l);
  bool varying = llvm::any_of(a, [](Value v) { return isVarying(v.getType()); });
  Value result = g.constTriple(0, 0, 0, l);
  for (int j = 0; j < 3; ++j) {
    SmallVector<Value> comps;
    for (Value v : a)
      comps.push_back(b.create<ExtractOp>(ml, withUniformity(b.getF32Type(), isVarying(v.getType())),
                                          v, b.getI64IntegerAttr(j)));
    Value s = smoothLinearStep1(g, l, comps[0], comps[1], comps[2], comps[3]);
    result = b.create<InsertOp>(ml, withUniformity(irType(b, r), varying), s, result,
                                b.getI64IntegerAttr(j));
  }
  return result;
}

const std::vector<Builtin> &builtinTable() {
  static const std::vector<Builtin> table = {
      {"abs", {{"f", "f"}, {"i", "i"}, {"T", "T"}}, unary<AbsOp>},
      {"fabs", {{"f", "f"}, {"i", "i"}, {"T", "T"}}, unary<AbsOp>},
      {"floor", {{"f", "f"}, {"T", "T"}}, unary<FloorOp>},
      {"ceil", {{"f", "f"}, {"T", "T"}}, unary<CeilOp>},
      {"round", {{"f", "f"}, {"T", "T"}}, unary<RoundOp>},
      {"trunc", {{"f", "f"}, {"T", "T"}}, unary<TruncOp>},
      {"sign", {{"f", "f"}, {"T", "T"}}, unary<SignOp>},
      {"sin", {{"f", "f"}, {"T", "T"}}, unary<SinOp>},
      {"cos", {{"f", "f"}, {"T", "T"}}, unary<CosOp>},
      {"tan", {{"f", "f"}, {"T", "T"}}, unary<TanOp>},
      {"asin", {{"f", "f"}, {"T", "T"}}, unary<AsinOp>},
      {"acos", {{"f", "f"}, {"T", "T"}}, unary<AcosOp>},
      {"atan", {{"f", "f"}, {"T", "T"}}, unary<AtanOp>},
      {"atan2", {{"f", "ff"}, {"T", "TT"}}, binary<Atan2Op>},
      {"exp", {{"f", "f"}, {"T", "T"}}, unary<ExpOp>},
      {"exp2", {{"f", "f"}, {"T", "T"}}, unary<Exp2Op>},
      {"sinh", {{"f", "f"}, {"T", "T"}}, unary<SinhOp>},
      {"cosh", {{"f", "f"}, {"T", "T"}}, unary<CoshOp>},
      {"tanh", {{"f", "f"}, {"T", "T"}}, unary<TanhOp>},
      {"expm1", {{"f", "f"}, {"T", "T"}}, unary<Expm1Op>},
      {"cbrt", {{"f", "f"}, {"T", "T"}}, unary<CbrtOp>},
      {"erf", {{"f", "f"}, {"T", "T"}}, unary<ErfOp>},
      {"erfc", {{"f", "f"}, {"T", "T"}}, unary<ErfcOp>},
      {"logb", {{"f", "f"}, {"T", "T"}}, unary<LogbOp>},
      {"linearstep", {{"f", "fff"}, {"T", "TTT"}}, ternary<LinearStepOp>},
      {"isnan", {{"i", "f"}}, emitIsNan},
      {"isinf", {{"i", "f"}}, emitIsInf},
      {"isfinite", {{"i", "f"}}, emitIsFinite},
      {"log", {{"f", "f"}, {"T", "T"}, {"f", "ff"}, {"T", "Tf"}}, emitLog},
      {"log2", {{"f", "f"}, {"T", "T"}}, unary<Log2Op>},
      {"log10", {{"f", "f"}, {"T", "T"}}, unary<Log10Op>},
      {"sqrt", {{"f", "f"}, {"T", "T"}}, unary<SqrtOp>},
      {"inversesqrt", {{"f", "f"}, {"T", "T"}}, unary<InverseSqrtOp>},
      {"pow", {{"f", "ff"}, {"T", "TT"}, {"T", "Tf"}}, binary<PowOp>},
      {"fmod", {{"f", "ff"}, {"T", "TT"}, {"T", "Tf"}}, binary<FmodOp>},
      {"mod", {{"i", "ii"}, {"f", "ff"}, {"T", "TT"}, {"T", "Tf"}}, emitMod},
      {"min", {{"i", "ii"}, {"f", "ff"}, {"T", "TT"}}, binary<MinOp>},
      {"max", {{"i", "ii"}, {"f", "ff"}, {"T", "TT"}}, binary<MaxOp>},
      {"clamp", {{"i", "iii"}, {"f", "fff"}, {"T", "TTT"}}, ternary<ClampOp>},
      {"mix", {{"f", "fff"}, {"T", "TTT"}, {"T", "TTf"}}, ternary<MixOp>},
      {"smoothstep", {{"f", "fff"}, {"T", "TTT"}}, ternary<SmoothStepOp>},
      {"step", {{"f", "ff"}, {"T", "TT"}}, binary<StepOp>},
      {"dot", {{"f", "TT"}}, geometric2<DotOp>},
      {"cross", {{"v", "TT"}}, geometric2<CrossOp>},
      {"length", {{"f", "T"}}, geometric1<LengthOp>},
      {"normalize", {{"T", "T"}}, geometric1<NormalizeOp>},
      {"distance", {{"f", "TT"}, {"f", "TTT"}}, emitDistance},
      {"reflect", {{"v", "TT"}}, emitReflect},
      {"faceforward", {{"v", "TTT"}, {"v", "TT"}}, emitFaceforward},
      {"refract", {{"v", "TTf"}}, emitRefract},
      {"rotate", {{"p", "TfT"}, {"p", "TfTT"}}, emitRotate},
      {"radians", {{"f", "f"}, {"T", "T"}}, emitRadians},
      {"degrees", {{"f", "f"}, {"T", "T"}}, emitDegrees},
      {"hypot", {{"f", "ff"}, {"f", "fff"}}, emitHypot},
      {"select", {{"i", "iii"}, {"f", "fff"}, {"T", "TTT"}, {"T", "TTf"}}, emitSelect},
      {"surfacearea", {{"f", ""}}, emitSurfaceArea},
      {"backfacing", {{"i", ""}}, emitBackfacing},
      {"Dx", {{"f", "f"}, {"T", "T"}}, emitDeriv<'x'>},
      {"Dy", {{"f", "f"}, {"T", "T"}}, emitDeriv<'y'>},
      {"Dz", {{"f", "f"}, {"T", "T"}}, emitDeriv<'z'>},
      {"filterwidth", {{"f", "f"}, {"v", "T"}}, emitFilterWidth},
      {"area", {{"f", "p"}}, emitArea},
      {"calculatenormal", {{"n", "p"}}, emitCalculateNormal},
      {"aastep", {{"f", "ff"}, {"f", "fff"}, {"f", "ffff"}}, emitAaStep},
      {"smooth_linearstep", {{"f", "ffff"}, {"T", "TTTT"}}, emitSmoothLinearStep},
      {"luminance", {{"f", "c"}}, emitLuminance},
      {"blackbody", {{"c", "f"}}, emitSpectralColor<BlackbodyOp>},
      {"wavelength_color", {{"c", "f"}}, emitSpectralColor<WavelengthColorOp>},
  };
  return table;
}

/// Every OSL library function name the front end knows: those not handled
/// above are reported as "not supported yet" rather than unknown.
const char *const kUnsupported[] = {
    "smooth_linearstep", "raytype",
    "setmessage", "getmessage", "trace", "transformu",
    "splineinverse",
    "pointcloud_search", "pointcloud_get", "pointcloud_write", "random", "exit", "arraylength", "spline", "noise",
    "snoise", "cellnoise", "hashnoise", "transform", "ptransform", "vtransform",
    "ntransform", "displace", "bump", "fmin", "fmax", "nsnoise",
    "gabor", "pgabor", "sincos",
};

OslType typeFromCode(char c, BaseType tKind) {
  switch (c) {
  case 'f': return OslType(BaseType::Float);
  case 'i': return OslType(BaseType::Int);
  case 's': return OslType(BaseType::String);
  case 'p': return OslType(BaseType::Point);
  case 'v': return OslType(BaseType::Vector);
  case 'n': return OslType(BaseType::Normal);
  case 'c': return OslType(BaseType::Color);
  default: return OslType(tKind);
  }
}

std::string sigText(const char *name, const Sig &s) {
  auto codeName = [](char c) -> std::string {
    return c == 'T' ? "triple" : typeFromCode(c, BaseType::Void).str();
  };
  std::string t = codeName(s.ret[0]) + " " + name + "(";
  for (const char *p = s.args; *p; ++p)
    t += (p == s.args ? "" : ", ") + codeName(*p);
  return t + ")";
}

std::string argTypesText(const std::vector<RValue> &args) {
  std::string t;
  for (size_t k = 0; k < args.size(); ++k)
    t += (k ? ", " : "") + args[k].type.str();
  return t;
}


std::optional<RValue> emitTableCall(IRGen &g, const Builtin &fn, const Expr &call) {
  auto args = emitArgs(g, call);
  if (!args)
    return std::nullopt;
  const Sig *best = nullptr;
  int bestCost = 0;
  BaseType bestKind = BaseType::Void;
  for (const Sig &s : fn.sigs) {
    size_t n = std::strlen(s.args);
    if (n != args->size())
      continue;
    BaseType tKind = BaseType::Void;
    for (size_t k = 0; k < n; ++k)
      if (s.args[k] == 'T' && (*args)[k].type.isTriple()) {
        tKind = (*args)[k].type.base;
        break;
      }
    if (tKind == BaseType::Void && std::strchr(s.args, 'T'))
      continue;
    int cost = 0;
    bool ok = true;
    for (size_t k = 0; k < n && ok; ++k) {
      int c = IRGen::conversionCost((*args)[k].type, typeFromCode(s.args[k], tKind));
      ok = c >= 0;
      cost += c;
    }
    if (ok && (!best || cost < bestCost)) {
      best = &s;
      bestCost = cost;
      bestKind = tKind;
    }
  }
  if (!best) {
    std::string cands;
    for (const Sig &s : fn.sigs)
      cands += (cands.empty() ? "" : "; ") + sigText(fn.name, s);
    g.error(call.loc, "wrong arguments to '" + call.name + "(" + argTypesText(*args) +
                          ")'; candidates: " + cands);
    return std::nullopt;
  }
  std::vector<Value> values;
  for (size_t k = 0; k < args->size(); ++k) {
    auto c = g.coerce((*args)[k], typeFromCode(best->args[k], bestKind),
                      call.args[k]->begin, "");
    if (!c)
      return std::nullopt;
    values.push_back(c->value);
  }
  OslType result = typeFromCode(best->ret[0], bestKind);
  return RValue::num(result, fn.emit(g, call.loc, values, result));
}

/// A compile-time string argument.
bool stringArg(IRGen &g, const RValue &v, const Expr &e, llvm::StringRef fn,
               llvm::StringRef what, std::string &out) {
  if (!v.type.isString())
    return g.error(e.loc, "'" + fn + "' expects " + what + " (a string) here, got '" +
                              v.type.str() + "'");
  if (v.isStringChoice())
    return g.error(e.loc, "'" + fn + "' needs " + what +
                              " known when the shader is compiled; this string is chosen "
                              "per point");
  if (!g.compileTimeStrings(v, e.loc, llvm::Twine(what) + " of '" + fn + "'"))
    return false;
  out = v.str;
  return true;
}

/// A string argument known when the shader is compiled, or chosen per
/// point among such strings (forEachStringChoice then runs each choice on
/// its lanes).
bool namesArg(IRGen &g, const RValue &v, const Expr &e, llvm::StringRef fn,
              llvm::StringRef what) {
  if (!v.type.isString())
    return g.error(e.loc, "'" + fn + "' expects " + what + " (a string) here, got '" +
                              v.type.str() + "'");
  return bool(g.compileTimeStrings(v, e.loc, llvm::Twine(what) + " of '" + fn + "'"));
}

/// Whether the renderer knows every space of a transform; each unknown one is
/// reported when the point runs (the transform is then the identity, as in
/// OSL).
bool knownSpaces(IRGen &g, std::initializer_list<llvm::StringRef> names, SrcLoc l) {
  bool known = true;
  for (llvm::StringRef name : names)
    if (!namedSpaceTransform(name, "common", g.cameraImage())) {
      g.reportAtRunTime("Unknown transformation \"" + name.str() + "\"", l);
      known = false;
    }
  return known;
}

/// Whether transformc(from, to, ...) can convert; if not, the color stays as
/// it is and the renderer reports it when the point runs, as OSL's does.
bool knownColorTransform(IRGen &g, const std::string &from, const std::string &to,
                         SrcLoc l) {
  if (isColorSpaceName(from, g.workingColorSpace()) &&
      isColorSpaceName(to, g.workingColorSpace()))
    return true;
  g.reportAtRunTime("Unknown color space transformation \"" + from + "\" -> \"" + to + "\"",
                    l);
  return false;
}

/// transformc([from,] to, C): from defaults to "rgb".
std::optional<RValue> emitTransformc(IRGen &g, const Expr &call) {
  auto args = emitArgs(g, call);
  if (!args)
    return std::nullopt;
  size_t n = args->size();
  if (n != 2 && n != 3) {
    g.error(call.loc, "wrong arguments to 'transformc(" + argTypesText(*args) +
                          ")'; candidates: color transformc(string to, color); "
                          "color transformc(string from, string to, color)");
    return std::nullopt;
  }
  RValue from = RValue::string("rgb");
  if (n == 3) {
    if (!namesArg(g, (*args)[0], *call.args[0], "transformc", "a color space name"))
      return std::nullopt;
    from = (*args)[0];
  }
  const RValue &to = (*args)[n - 2];
  if (!namesArg(g, to, *call.args[n - 2], "transformc", "a color space name"))
    return std::nullopt;
  OslType color(BaseType::Color);
  auto c = g.coerce((*args)[n - 1], color, call.args[n - 1]->begin, "in 'transformc'");
  if (!c)
    return std::nullopt;
  return g.forEachStringChoice(from, call.loc, [&](const std::string &f) {
    return g.forEachStringChoice(to, call.loc, [&](const std::string &t) {
      if (!knownColorTransform(g, f, t, call.loc))
        return std::optional<RValue>(*c);
      Value r = g.builder().create<TransformcOp>(g.loc(call.loc), c->value.getType(), f, t,
                                                 g.workingColorSpace(), c->value);
      return std::optional<RValue>(RValue::num(color, r));
    });
  });
}

/// The values of noise("gabor", ..., "name", value, ...)'s options (null
/// where not given).
struct NoiseOptionValues {
  Value anisotropic, direction, bandwidth, impulses, doFilter;
};

/// Reads (name, value) option pairs from args[at] on: names are constant
/// strings, values uniform; anisotropic and do_filter are ints, direction a
/// triple, bandwidth and impulses an int or a float (made float).
std::optional<NoiseOptionValues> parseNoiseOptions(IRGen &g, const Expr &call,
                                                   const std::vector<RValue> &args,
                                                   size_t at) {
  NoiseOptionValues out;
  for (size_t k = at; k < args.size(); k += 2) {
    const RValue &name = args[k];
    SrcLoc nameLoc = call.args[k]->loc;
    if (!name.type.isString() || name.isStringChoice()) {
      g.error(nameLoc, "expected a constant noise option name here (anisotropic, direction, "
                       "bandwidth, impulses, do_filter)");
      return std::nullopt;
    }
    if (k + 1 >= args.size()) {
      g.error(nameLoc, "noise option '" + name.str + "' has no value");
      return std::nullopt;
    }
    const RValue &v = args[k + 1];
    SrcLoc valueLoc = call.args[k + 1]->loc;
    auto bad = [&](const char *what) -> std::optional<NoiseOptionValues> {
      g.error(valueLoc, "noise option '" + name.str + "' takes " + what);
      return std::nullopt;
    };
    if (v.type.isNumeric() && isVarying(v.value.getType()))
      return bad("a uniform value (the same at every point)");
    if (name.str == "anisotropic" || name.str == "do_filter") {
      if (!v.type.isInt())
        return bad("an int");
      (name.str == "anisotropic" ? out.anisotropic : out.doFilter) = v.value;
    } else if (name.str == "direction") {
      if (!v.type.isTriple())
        return bad("a vector");
      out.direction = v.value;
    } else if (name.str == "bandwidth" || name.str == "impulses") {
      if (!v.type.isInt() && !v.type.isFloat())
        return bad("a float");
      (name.str == "bandwidth" ? out.bandwidth : out.impulses) =
          g.convert(v.value, g.builder().getF32Type(), valueLoc);
    } else {
      g.error(nameLoc, "unknown noise option '" + name.str +
                           "' (known: anisotropic, direction, bandwidth, impulses, do_filter)");
      return std::nullopt;
    }
  }
  return out;
}

/// Dx then Dy of Gabor's lookup point for its filter: the triple, or the
/// float coordinates of a 2D domain. None for a 1D domain (its derivatives
/// span no area, so OSL never filters it) or when do_filter is a constant 0.
std::vector<Value> gaborFilterDerivs(IRGen &g, SrcLoc l, llvm::ArrayRef<Value> point,
                                     const NoiseOptionValues &options) {
  APInt doFilter;
  if (options.doFilter && matchPattern(options.doFilter, m_ConstantInt(&doFilter)) &&
      doFilter.isZero())
    return {};
  if (point.size() == 1 && !isTriple(getUniformType(point[0].getType())))
    return {};
  std::vector<Value> derivs;
  for (char axis : {'x', 'y'})
    for (Value c : point)
      derivs.push_back(derivOf(g, l, c, axis));
  return derivs;
}

std::optional<RValue> emitNoise(IRGen &g, const Expr &call, const OslType *expected) {
  llvm::StringRef name = call.name;
  auto args = emitArgs(g, call);
  if (!args)
    return std::nullopt;
  std::string kind = llvm::StringSwitch<std::string>(name)
                         .Cases("noise", "pnoise", "uperlin")
                         .Cases("snoise", "psnoise", "perlin")
                         .Case("cellnoise", "cell")
                         .Default("hash");
  bool periodic = name == "pnoise" || name == "psnoise";
  size_t first = 0;
  RValue kindName = RValue::string(kind);
  if (!args->empty() && (*args)[0].type.isString()) {
    if (name != "noise" && name != "pnoise") {
      g.error(call.args[0]->loc, "'" + name + "' takes no noise type name; use noise(\"" +
                                     (*args)[0].str + "\", ...)");
      return std::nullopt;
    }
    kindName = (*args)[0];
    first = 1;
    if (!g.compileTimeStrings(kindName, call.args[0]->loc, "the noise type"))
      return std::nullopt;
  }
  // Trailing (string, value) pairs are noise options (Gabor's parameters).
  size_t optionsAt = first;
  while (optionsAt < args->size() && !(*args)[optionsAt].type.isString())
    ++optionsAt;
  std::optional<NoiseOptionValues> options =
      parseNoiseOptions(g, call, *args, optionsAt);
  if (!options)
    return std::nullopt;
  args->resize(optionsAt);
  size_t n = args->size() - first;
  auto wrong = [&]() -> std::optional<RValue> {
    std::string prefix = name == "noise" ? "[string name, ]" : "";
    g.error(call.loc, "wrong arguments to '" + name + "(" + argTypesText(*args) +
                          ")'; candidates: " + name + "(" + prefix + "float); " + name +
                          "(" + prefix + "float, float); " + name + "(" + prefix +
                          "point); " + name + "(" + prefix + "point, float)");
    return std::nullopt;
  };
  // pnoise: each coordinate is followed, after all of them, by its period.
  size_t ncoords = periodic ? n / 2 : n;
  if (ncoords < 1 || ncoords > 2 || (periodic && n % 2))
    return wrong();
  std::vector<Value> coords;
  for (size_t k = first; k < args->size(); ++k) {
    const RValue &a = (*args)[k];
    bool firstCoord = k == first || (periodic && k == first + ncoords);
    if (a.type.isTriple() && firstCoord) {
      coords.push_back(a.value);
      continue;
    }
    if (!a.type.isScalar())
      return wrong();
    coords.push_back(g.convert(a.value, g.builder().getF32Type(), call.args[k]->loc));
  }
  // The lookup point: a triple or the float coordinates (not w, not periods).
  llvm::ArrayRef<Value> pointCoords(coords);
  pointCoords = isTriple(getUniformType(coords[0].getType())) ? pointCoords.take_front(1)
                                                              : pointCoords.take_front(ncoords);
  bool triple = expected && expected->isTriple();
  OslType resultType = triple ? OslType(expected->base) : OslType(BaseType::Float);
  bool varying = llvm::any_of(coords, [](Value v) { return isVarying(v.getType()); });
  Type t = withUniformity(irType(g.builder(), resultType), varying);
  return g.forEachStringChoice(kindName, call.loc, [&](const std::string &k) {
    if (!isKnownNoiseName(k)) {
      // OSL's renderer reports an unknown name where the point runs, and
      // the noise is 0.
      g.reportAtRunTime(std::string(periodic ? "periodic " : "") + "noise type \"" + k +
                            "\" is unknown, called from (" + g.fileLine(call.loc) + ")",
                        call.loc);
      return std::optional<RValue>(g.zeroValue(resultType, call.loc));
    }
    if (k != "gabor") { // other noises ignore the options, as in OSL
      Value v = g.builder().create<NoiseOp>(g.loc(call.loc), t, k, coords, periodic);
      return std::optional<RValue>(RValue::num(resultType, v));
    }
    Value v = g.builder().create<NoiseOp>(
        g.loc(call.loc), t, k, coords, periodic,
        gaborFilterDerivs(g, call.loc, pointCoords, *options), options->anisotropic,
        options->direction, options->bandwidth, options->impulses, options->doFilter);
    return std::optional<RValue>(RValue::num(resultType, v));
  });
}

std::optional<RValue> emitTransform(IRGen &g, const Expr &call) {
  auto args = emitArgs(g, call);
  if (!args)
    return std::nullopt;
  size_t n = args->size();
  auto wrong = [&]() -> std::optional<RValue> {
    g.error(call.loc, "wrong arguments to 'transform(" + argTypesText(*args) +
                          ")'; candidates: triple transform(string to, triple); "
                          "triple transform(string from, string to, triple); "
                          "triple transform(matrix, triple) "
                          "(triple: point, vector or normal)");
    return std::nullopt;
  };
  if (n != 2 && n != 3)
    return wrong();
  const RValue &p = args->back();
  if (!p.type.isTriple())
    return wrong();
  if (n == 2 && (*args)[0].type.isMatrix()) {
    if (p.type.base == BaseType::Color) {
      g.error(call.args.back()->loc,
              "transform() applies to points, vectors and normals, not 'color'");
      return std::nullopt;
    }
    return RValue::num(p.type,
                       g.transformByMatrix((*args)[0].elems, p.value, p.type.base, call.loc));
  }
  for (size_t k = 0; k + 1 < n; ++k) {
    if (!(*args)[k].type.isString())
      return wrong();
    if (!namesArg(g, (*args)[k], *call.args[k], "transform", "a space name"))
      return std::nullopt;
  }
  if (p.type.base == BaseType::Color) {
    g.error(call.args.back()->loc,
            "transform() applies to points, vectors and normals, not 'color'");
    return std::nullopt;
  }
  // Names may be chosen per point: each pair of names runs on its lanes.
  auto between = [&](const std::string &from, const std::string &to) -> std::optional<RValue> {
    if (from.empty() || to.empty()) {
      g.error(call.loc, "transform() needs non-empty space names");
      return std::nullopt;
    }
    if (from == to)
      return p;
    if (isProjectionSpace(from)) {
      g.error(call.args[0]->loc, "the renderer knows '" + from +
                                     "' only as a destination space");
      return std::nullopt;
    }
    if (isProjectionSpace(to)) {
      // The camera's projection depends on the image size the front end was
      // given: a constant matrix, applied with the w divide.
      // (An unknown space is reported, and its half is the identity.)
      bool known = true;
      RValue m = g.namedMatrix(from, to, call.loc, known);
      return RValue::num(p.type, g.transformByMatrix(m.elems, p.value, p.type.base, call.loc));
    }
    if (!knownSpaces(g, {from, to}, call.loc))
      return p;
    std::string kind = baseTypeName(p.type.base).str();
    Value v = g.builder().create<TransformOp>(g.loc(call.loc), p.value.getType(), from, to,
                                              kind, p.value);
    return RValue::num(p.type, v);
  };
  RValue from = n == 3 ? (*args)[0] : RValue::string("common");
  const RValue &to = (*args)[n - 2];
  return g.forEachStringChoice(from, call.loc, [&](const std::string &f) {
    return g.forEachStringChoice(to, call.loc, [&](const std::string &t) { return between(f, t); });
  });
}

/// spline() and splineinverse(): (basis, x, knots...), (basis, x, knots[])
/// or (basis, x, nknots, knots[]); splineinverse takes float knots only.
std::optional<RValue> emitSpline(IRGen &g, const Expr &call, bool inverse) {
  auto args = emitArgs(g, call);
  if (!args)
    return std::nullopt;
  llvm::StringRef fn = inverse ? "splineinverse" : "spline";
  auto wrong = [&]() -> std::optional<RValue> {
    std::string T = inverse ? "float" : "T";
    g.error(call.loc, "wrong arguments to '" + fn + "(" + argTypesText(*args) +
                          ")'; candidates: " + fn + "(string basis, float x, " + T +
                          " knots...); " + fn + "(string basis, float x, " + T +
                          " knots[]); " + fn + "(string basis, float x, int nknots, " + T +
                          " knots[])" + (inverse ? "" : " (T: float or triple)"));
    return std::nullopt;
  };
  if (args->size() < 3)
    return wrong();
  const RValue &basisName = (*args)[0];
  if (!basisName.type.isString()) {
    g.error(call.args[0]->loc, "'" + fn + "' expects the basis name (a string) here, got '" +
                                   basisName.type.str() + "'");
    return std::nullopt;
  }
  auto knownBases = g.compileTimeStrings(basisName, call.args[0]->loc, "the spline basis");
  if (!knownBases)
    return std::nullopt;
  std::vector<std::string> bases = *knownBases;
  for (const std::string &basis : bases) {
    bool known = llvm::is_contained(
        {"catmull-rom", "bezier", "bspline", "hermite", "linear", "constant"}, basis);
    if (!known) {
      g.error(call.args[0]->loc, "unknown spline basis '" + basis +
                                     "' (expected catmull-rom, bezier, bspline, hermite, "
                                     "linear or constant)");
      return std::nullopt;
    }
  }
  const RValue &x = (*args)[1];
  if (!x.type.isScalar())
    return wrong();
  Value xv = g.convert(x.value, g.builder().getF32Type(), call.args[1]->loc);
  // The knots: one array, (count, array), or a list of values.
  std::vector<RValue> knots;
  Value count;
  SrcLoc knotLoc = call.args[2]->loc;
  if (args->size() <= 4 && args->back().type.isArray()) {
    const RValue &arr = args->back();
    if (args->size() == 4) {
      const RValue &c = (*args)[2];
      if (!c.type.isInt())
        return wrong();
      auto k = IRGen::getConstInt(c.value);
      if (k && (*k < 4 || size_t(*k) > arr.elems.size())) {
        g.error(call.args[2]->loc, "knot count " + llvm::Twine(*k) +
                                       " is out of range for '" + arr.type.str() +
                                       "' (at least 4)");
        return std::nullopt;
      }
      count = c.value; // may be a parameter or computed per point
    } else if (args->size() != 3) {
      return wrong();
    }
    for (Value e : arr.elems)
      knots.push_back(RValue::num(arr.type.element(), e));
    knotLoc = call.args.back()->loc;
  } else {
    for (size_t k = 2; k < args->size(); ++k) {
      if (!(*args)[k].type.isNumeric())
        return wrong();
      knots.push_back((*args)[k]);
    }
  }
  if (knots.size() < 4) {
    g.error(knotLoc, "'" + fn + "' needs at least 4 knots, got " +
                         llvm::Twine(knots.size()));
    return std::nullopt;
  }
  OslType knotType(BaseType::Float);
  for (const RValue &k : knots)
    if (k.type.isTriple()) {
      if (inverse)
        return wrong();
      knotType = k.type;
      break;
    }
  std::vector<Value> kv;
  bool varying = isVarying(xv.getType()) || (count && isVarying(count.getType()));
  for (const RValue &k : knots) {
    auto c = g.coerce(k, knotType, knotLoc, "in spline knots");
    if (!c)
      return std::nullopt;
    kv.push_back(c->value);
    varying |= isVarying(c->value.getType());
  }
  Type t = withUniformity(irType(g.builder(), knotType), varying);
  return g.forEachStringChoice(basisName, call.loc, [&](const std::string &basis) {
    Value v =
        inverse
            ? g.builder().create<SplineInverseOp>(g.loc(call.loc), t, basis, xv, count, kv)
                  .getResult()
            : g.builder().create<SplineOp>(g.loc(call.loc), t, basis, xv, count, kv)
                  .getResult();
    return std::optional<RValue>(RValue::num(knotType, v));
  });
}

std::optional<RValue> emitConstructor(IRGen &g, OslType t, const std::vector<ExprPtr> &callArgs,
                                      SrcLoc callLoc) {
  struct {
    const std::vector<ExprPtr> &args;
    SrcLoc loc;
  } call{callArgs, callLoc};
  size_t n = call.args.size();
  std::string name = t.str();
  if (t.isInt() || t.isFloat() || t.isString()) {
    if (n != 1) {
      g.error(call.loc, "'" + name + "(...)' takes one argument, got " + llvm::Twine(n));
      return std::nullopt;
    }
    auto v = g.emitExpr(*call.args[0], &t);
    if (!v)
      return std::nullopt;
    return g.cast(*v, t, call.loc);
  }
  // Triples: [space,] (value | x, y, z).
  std::vector<RValue> args;
  OslType floatType(BaseType::Float);
  for (size_t k = 0; k < n; ++k) {
    const OslType *expected = n == 1 || (n == 2 && k == 1) ? &t : &floatType;
    auto v = g.emitExpr(*call.args[k], expected);
    if (!v)
      return std::nullopt;
    args.push_back(*v);
  }
  auto wrong = [&]() -> std::optional<RValue> {
    g.error(call.loc, "wrong arguments to '" + name + "(" + argTypesText(args) +
                          ")'; candidates: " + name + "(float); " + name + "(" + name +
                          "); " + name + "(float, float, float); " + name +
                          "(string space, ...)");
    return std::nullopt;
  };
  size_t first = 0;
  if (!args.empty() && args[0].type.isString()) {
    if (!namesArg(g, args[0], *call.args[0], name, "the space name"))
      return std::nullopt;
    first = 1;
  }
  Value value;
  size_t m = n - first;
  if (m == 1) {
    auto c = g.coerce(args[first], t, call.args[first]->begin, "in '" + name + "(...)'");
    if (!c)
      return std::nullopt;
    value = c->value;
  } else if (m == 3) {
    std::vector<Value> xyz;
    for (size_t k = first; k < n; ++k) {
      if (!args[k].type.isScalar())
        return wrong();
      xyz.push_back(g.convert(args[k].value, g.builder().getF32Type(), call.args[k]->loc));
    }
    std::optional<double> cx, cy, cz;
    auto constOf = [](Value v) -> std::optional<double> {
      if (auto c = v.getDefiningOp<arith::ConstantOp>())
        if (auto fa = dyn_cast<FloatAttr>(c.getValue()))
          return fa.getValueAsDouble();
      return std::nullopt;
    };
    cx = constOf(xyz[0]);
    cy = constOf(xyz[1]);
    cz = constOf(xyz[2]);
    if (cx && cy && cz)
      value = g.constTriple(float(*cx), float(*cy), float(*cz), call.loc);
    else
      value = g.builder().create<ConstructOp>(g.loc(call.loc), xyz[0], xyz[1], xyz[2]);
  } else {
    return wrong();
  }
  if (first == 1) {
    auto inSpace = [&](const std::string &space) -> std::optional<RValue> {
      if (t.base == BaseType::Color) {
        // OSL names the destination "RGB" in its report.
        if (!knownColorTransform(g, space, "RGB", call.loc))
          return RValue::num(t, value);
        return RValue::num(t, g.builder().create<TransformcOp>(
                                  g.loc(call.loc), value.getType(), space, "rgb",
                                  g.workingColorSpace(), value));
      }
      if (space.empty()) {
        g.error(call.args[0]->loc, "empty space name");
        return std::nullopt;
      }
      if (space == "common" || !knownSpaces(g, {space}, call.loc))
        return RValue::num(t, value);
      return RValue::num(t, g.builder().create<TransformOp>(g.loc(call.loc), value.getType(),
                                                            space, "common",
                                                            baseTypeName(t.base), value));
    };
    auto r = g.forEachStringChoice(args[0], call.loc, inSpace);
    if (!r)
      return std::nullopt;
    value = r->value;
  }
  return RValue::num(t, value);
}

std::optional<RValue> emitConstructor(IRGen &g, const Expr &call) {
  return emitConstructor(g, call.castType, call.args, call.loc);
}

/// fresnel(I, N, eta, out Kr, out Kt, out R, out T): the unpolarized
/// Fresnel reflectance of a dielectric, computed as stdosl.h writes it
/// (operation for operation, so the results are OSL's): Kr, Kt = (1 - Kr)
/// eta^2, the reflected and the refracted directions; total internal
/// reflection gives Kr = 1, Kt = 0, T = 0.
std::optional<RValue> emitFresnel(IRGen &g, const Expr &call) {
  auto wrong = [&]() -> std::optional<RValue> {
    g.error(call.loc, "wrong arguments to 'fresnel'; candidates: void fresnel(vector I, "
                      "normal N, float eta, output float Kr, output float Kt, output "
                      "vector R, output vector T)");
    return std::nullopt;
  };
  if (call.args.size() != 7)
    return wrong();
  std::vector<RValue> in;
  for (int k = 0; k < 3; ++k) {
    auto v = g.emitExpr(*call.args[k]);
    if (!v)
      return std::nullopt;
    if (k < 2 ? !v->type.isTriple() : !v->type.isScalar())
      return wrong();
    in.push_back(*v);
  }
  SrcLoc l = call.loc;
  OpBuilder &b = g.builder();
  Location ml = g.loc(l);
  Value I = in[0].value, N = in[1].value;
  Value eta = g.convert(in[2].value, b.getF32Type(), call.args[2]->loc);
  Value one = g.constFloat(1, l);
  auto sqr = [&](Value x) { return b.create<MulOp>(ml, x, x).getResult(); };
  Value c = dotOf(g, l, I, N);
  c = b.create<SelectOp>(ml, b.create<CmpOp>(ml, "lt", c, g.constFloat(0, l)),
                         b.create<NegOp>(ml, c), c);
  Value R = emitReflect(g, l, {I, N}, OslType(BaseType::Vector));
  Value gg = b.create<AddOp>(ml, b.create<SubOp>(ml, b.create<DivOp>(ml, one, sqr(eta)), one),
                             b.create<MulOp>(ml, c, c));
  Value refracts = b.create<CmpOp>(ml, "ge", gg, g.constFloat(0, l));
  Value gs = b.create<SqrtOp>(ml, gg);
  Value beta = b.create<SubOp>(ml, gs, c);
  Value gPlusC = b.create<AddOp>(ml, gs, c);
  Value F = b.create<DivOp>(ml, b.create<SubOp>(ml, b.create<MulOp>(ml, c, gPlusC), one),
                            b.create<AddOp>(ml, b.create<MulOp>(ml, c, beta), one));
  F = b.create<MulOp>(ml, g.constFloat(0.5, l), b.create<AddOp>(ml, one, sqr(F)));
  F = b.create<MulOp>(ml, F, sqr(b.create<DivOp>(ml, beta, gPlusC)));
  Value Kt = b.create<MulOp>(ml, b.create<MulOp>(ml, b.create<SubOp>(ml, one, F), eta), eta);
  Value T = emitRefract(g, l, {I, N, eta}, OslType(BaseType::Vector));
  Value results[4] = {
      b.create<SelectOp>(ml, refracts, F, one),
      b.create<SelectOp>(ml, refracts, Kt, g.constFloat(0, l)),
      R,
      b.create<SelectOp>(ml, refracts, T, g.constTriple(0, 0, 0, l)),
  };
  for (int k = 0; k < 4; ++k) {
    auto lv = g.emitLValue(*call.args[3 + k]);
    if (!lv)
      return std::nullopt;
    OslType t = k < 2 ? OslType(BaseType::Float) : OslType(BaseType::Vector);
    auto v = g.coerce(RValue::num(t, results[k]), lv->type, call.args[3 + k]->loc,
                      "in output argument " + llvm::Twine(4 + k) + " of 'fresnel'");
    if (!v)
      return std::nullopt;
    g.storeLValue(*lv, *v, l);
  }
  return RValue::voidValue();
}

/// sincos(x, output s, output c).
std::optional<RValue> emitSincos(IRGen &g, const Expr &call) {
  if (call.args.size() != 3) {
    g.error(call.loc, "wrong arguments to 'sincos'; candidates: void sincos(float, output "
                      "float, output float); void sincos(triple, output triple, output "
                      "triple)");
    return std::nullopt;
  }
  auto x = g.emitExpr(*call.args[0]);
  if (!x)
    return std::nullopt;
  if (x->type.isInt() || x->type.isBool())
    x = RValue::num(OslType(BaseType::Float),
                    g.convert(x->value, g.builder().getF32Type(), call.args[0]->loc));
  if (!x->type.isFloat() && !x->type.isTriple()) {
    g.error(call.args[0]->loc, "'sincos' needs a float or a triple, got '" +
                                   x->type.str() + "'");
    return std::nullopt;
  }
  Value s = g.builder().create<SinOp>(g.loc(call.loc), x->value);
  Value c = g.builder().create<CosOp>(g.loc(call.loc), x->value);
  for (int k = 1; k <= 2; ++k) {
    auto lv = g.emitLValue(*call.args[k]);
    if (!lv)
      return std::nullopt;
    auto v = g.coerce(RValue::num(x->type, k == 1 ? s : c), lv->type, call.args[k]->loc,
                      "in output argument " + llvm::Twine(k + 1) + " of 'sincos'");
    if (!v)
      return std::nullopt;
    g.storeLValue(*lv, *v, call.loc);
  }
  return RValue::voidValue();
}

/// The attributes testshade's renderer answers: its camera (an image of
/// the grid's size, testshade's defaults otherwise). Numbers, or a string.
struct RendererAttribute {
  std::vector<double> numbers;
  bool isInt = false;
  bool isTriple = false; // three numbers for a color, point, vector or normal
  std::string text;
};

bool isTripleTypeName(llvm::StringRef type) {
  return type == "color" || type == "point" || type == "vector" || type == "normal";
}

/// A --userdata datum as an attribute (numbers, or a string).
RendererAttribute userDatumAttribute(const ::osl::UserDatum &d) {
  RendererAttribute a;
  if (d.type == "string") {
    a.text = d.value;
    return a;
  }
  llvm::SmallVector<llvm::StringRef> words;
  llvm::StringRef(d.value).split(words, ',', -1, /*KeepEmpty=*/false);
  for (llvm::StringRef w : words) {
    double x = 0;
    if (!w.trim().getAsDouble(x))
      a.numbers.push_back(x);
  }
  a.isInt = d.type == "int";
  a.isTriple = isTripleTypeName(d.type);
  if (a.isTriple && a.numbers.size() == 1)
    a.numbers.assign(3, a.numbers[0]);
  return a;
}

std::optional<RendererAttribute> testshadeAttribute(const IRGen &g, llvm::StringRef name,
                                                   bool nameIsConstant) {
  RendererAttribute a;
  if (name.starts_with("shader:")) {
    // OSL answers these while it optimizes the group, so only for a name
    // known then (its testsuite checks that a name picked per point finds
    // nothing).
    if (!nameIsConstant)
      return std::nullopt;
    if (name == "shader:shadername")
      a.text = g.shaderName().str();
    else if (name == "shader:layername")
      a.text = g.layerName();
    else if (name == "shader:groupname")
      a.text = g.groupName();
    else
      return std::nullopt;
  } else if (name == "osl:version") {
    // The ShadingSystem's own attribute: the version the preprocessor's
    // OSL_VERSION names.
    a.numbers = {double(::osl::kOslVersion)};
    a.isInt = true;
  } else if (name == "camera:resolution") {
    a.numbers = {double(g.cameraImage().xres), double(g.cameraImage().yres)};
    a.isInt = true;
  } else if (name == "camera:projection") {
    a.text = "perspective";
  } else if (name == "camera:fov") {
    a.numbers = {90};
  } else if (name == "camera:pixelaspect") {
    a.numbers = {1};
  } else if (name == "camera:clip_near") {
    a.numbers = {0.1};
  } else if (name == "camera:clip_far") {
    a.numbers = {1000};
  } else if (name == "camera:clip") {
    a.numbers = {0.1, 1000};
  } else if (name == "camera:shutter_open") {
    a.numbers = {0};
  } else if (name == "camera:shutter_close") {
    a.numbers = {1};
  } else if (name == "camera:shutter") {
    a.numbers = {0, 1};
  } else if (name == "camera:screen_window") {
    a.numbers = {-1, -1, 1, 1};
  } else if (const ::osl::UserDatum *d = g.userDatum(name)) {
    a = userDatumAttribute(*d);
  } else {
    return std::nullopt;
  }
  return a;
}

/// getattribute([object,] name, [index,] out dest): testshade's renderer
/// answers from constants, so a name known when the shader is compiled is
/// looked up then; dest is written only when the attribute exists and has
/// dest's type, and the result says whether it was.
std::pair<RValue, RValue> attributeValue(IRGen &g, const Expr &call, const std::string &object,
                                         const std::string &attribute, bool nameIsConstant,
                                         bool indexed, const LValue &dest);

std::optional<RValue> emitGetAttribute(IRGen &g, const Expr &call) {
  size_t n = call.args.size();
  if (n < 2 || n > 4) {
    g.error(call.loc, "wrong arguments to 'getattribute'; candidates: int getattribute(string "
                      "name, output T value); int getattribute(string object, string name, "
                      "output T value); with an int index before the value for arrays");
    return std::nullopt;
  }
  std::vector<RValue> names;
  for (size_t k = 0; k < n - 1; ++k) {
    auto v = g.emitExpr(*call.args[k]);
    if (!v)
      return std::nullopt;
    names.push_back(*v);
  }
  size_t nameCount = names.size() >= 2 && names[1].type.isString() ? 2 : 1;
  std::string object;
  if (nameCount == 2 && !stringArg(g, names[0], *call.args[0], "getattribute",
                                   "the object name", object))
    return std::nullopt;
  bool indexed = names.size() > nameCount;
  auto dest = g.emitLValue(*call.args[n - 1]);
  if (!dest)
    return std::nullopt;
  const RValue &attrName = names[nameCount - 1];
  if (!attrName.isStringChoice()) {
    std::string attribute;
    if (!stringArg(g, attrName, *call.args[nameCount - 1], "getattribute",
                   "the attribute name", attribute))
      return std::nullopt;
    auto [value, found] =
        attributeValue(g, call, object, attribute, /*nameIsConstant=*/true, indexed, *dest);
    g.storeLValue(*dest, value, call.loc);
    return found;
  }
  // A name chosen per point: every choice's answer (constants), then each
  // lane takes its own.
  std::vector<RValue> values, founds;
  for (const std::string &attribute : attrName.choices) {
    auto [value, found] =
        attributeValue(g, call, object, attribute, /*nameIsConstant=*/false, indexed, *dest);
    values.push_back(value);
    founds.push_back(found);
  }
  RValue value = values.back(), found = founds.back();
  if (dest->type.isString()) {
    value = g.stringChoice(values, attrName.value, call.loc);
  }
  for (size_t k = attrName.choices.size() - 1; k-- > 0;) {
    mlir::Value isK = g.cmp("eq", attrName.value, g.constInt(int(k), call.loc), call.loc);
    found.value = g.select(isK, founds[k].value, found.value, call.loc);
    if (dest->type.isString())
      continue;
    auto merged = g.selectFields(isK, values[k], value, call.loc);
    if (!merged)
      return std::nullopt;
    value = *merged;
  }
  g.storeLValue(*dest, value, call.loc);
  return found;
}

/// What getattribute(object, attribute, dest) leaves in dest (its current
/// value where testshade has no such attribute) and returns (1 or 0).
std::pair<RValue, RValue> attributeValue(IRGen &g, const Expr &call, const std::string &object,
                                         const std::string &attribute, bool nameIsConstant,
                                         bool indexed, const LValue &destRef) {
  const LValue *dest = &destRef;
  std::optional<RendererAttribute> found =
      object.empty() ? testshadeAttribute(g, attribute, nameIsConstant) : std::nullopt;
  OslType t = dest->type;
  OslType element = t.isArray() ? t.element() : t;
  bool fits = found && !indexed;
  if (fits && !found->text.empty())
    fits = t.isString();
  else if (fits && found->isTriple)
    fits = t.isTriple() && !t.isArray() && found->numbers.size() == 3;
  else if (fits)
    fits = (found->isInt ? element.isInt() : element.isFloat()) &&
           int(found->numbers.size()) == (t.isArray() ? t.arrayLen : 1);
  if (!fits)
    return {g.loadLValue(*dest, call.loc),
            RValue::num(OslType(BaseType::Int), g.constInt(0, call.loc))};
  RValue value;
  if (t.isString()) {
    value = RValue::string(found->text);
  } else {
    value = g.loadLValue(*dest, call.loc);
    auto constant = [&](double x) {
      return found->isInt ? g.constInt(int(x), call.loc) : g.constFloat(float(x), call.loc);
    };
    if (found->isTriple)
      value.value = g.constTriple(float(found->numbers[0]), float(found->numbers[1]),
                                  float(found->numbers[2]), call.loc);
    else if (t.isArray())
      for (size_t k = 0; k < found->numbers.size(); ++k)
        value.elems[k] = constant(found->numbers[k]);
    else
      value.value = constant(found->numbers[0]);
  }
  return {value, RValue::num(OslType(BaseType::Int), g.constInt(1, call.loc))};
}

} // namespace

namespace osl::frontend {

std::optional<std::vector<RValue>> emitArgs(IRGen &g, const Expr &call) {
  std::vector<RValue> args;
  for (const ExprPtr &a : call.args) {
    auto v = g.emitExpr(*a);
    if (!v)
      return std::nullopt;
    args.push_back(*v);
  }
  return args;
}

std::optional<std::pair<Value, Value>> testshadeUserdata(IRGen &g, llvm::StringRef name,
                                                         const OslType &type, SrcLoc l) {
  // Data given on the command line (--userdata) is the same on every point.
  if (const ::osl::UserDatum *d = g.userDatum(name)) {
    RendererAttribute a = userDatumAttribute(*d);
    bool fits = a.text.empty() && (a.isTriple ? type.isTriple() && a.numbers.size() == 3
                                              : a.numbers.size() == 1 &&
                                                    (a.isInt ? type.isInt() : type.isFloat()));
    if (fits && !type.isArray()) {
      Value value = a.isTriple ? g.constTriple(float(a.numbers[0]), float(a.numbers[1]),
                                               float(a.numbers[2]), l)
                    : a.isInt  ? g.constInt(int(a.numbers[0]), l)
                               : g.constFloat(float(a.numbers[0]), l);
      return std::make_pair(g.constBool(true, l), value);
    }
  }
  // testshade's renderer has float user data "s" = u and "t" = v on every
  // point, "red" = u where u > 0.5, "green" = v where u < 0.5, and "blue" =
  // 1 - u on the rows where int(v * 12) is even (as testshade answers).
  if (!type.isFloat() || !llvm::is_contained({"s", "t", "red", "green", "blue"}, name))
    return std::nullopt;
  OpBuilder &b = g.builder();
  Location ml = g.loc(l);
  Type f32 = b.getF32Type();
  Value u = g.getGlobal("u", f32, l), v = g.getGlobal("v", f32, l);
  Value half = g.constFloat(0.5f, l);
  Value value = name == "t" || name == "green" ? v : u;
  Value found = g.constBool(true, l);
  if (name == "red")
    found = b.create<CmpOp>(ml, "gt", u, half);
  else if (name == "green")
    found = b.create<CmpOp>(ml, "lt", u, half);
  if (name == "blue") {
    value = b.create<SubOp>(ml, g.constFloat(1, l), u);
    Value row = g.convert(b.create<MulOp>(ml, v, g.constFloat(12, l)), b.getI32Type(), l);
    Value odd = b.create<ModOp>(ml, row, g.constInt(2, l));
    found = b.create<CmpOp>(ml, "eq", odd, g.constInt(0, l));
  }
  return std::make_pair(found, value);
}

std::optional<RValue> emitTypeConstructor(IRGen &g, OslType type,
                                          const std::vector<ExprPtr> &args, SrcLoc loc) {
  return emitConstructor(g, type, args, loc);
}

std::optional<double> lookupFloatConstant(llvm::StringRef name) {
  static const std::pair<const char *, double> constants[] = {
      {"M_PI", 3.14159265358979323846},   {"M_PI_2", 1.57079632679489661923},
      {"M_PI_4", 0.78539816339744830962}, {"M_2_PI", 0.63661977236758134308},
      {"M_2PI", 6.28318530717958647692},  {"M_4PI", 12.56637061435917295384},
      {"M_2_SQRTPI", 1.12837916709551257390}, {"M_E", 2.71828182845904523536},
      {"M_LN2", 0.69314718055994530942},  {"M_LN10", 2.30258509299404568402},
      {"M_LOG2E", 1.44269504088896340736}, {"M_LOG10E", 0.43429448190325182765},
      {"M_SQRT2", 1.41421356237309504880}, {"M_SQRT1_2", 0.70710678118654752440},
  };
  for (auto &[n, v] : constants)
    if (name == n)
      return v;
  return std::nullopt;
}

bool isBuiltinName(llvm::StringRef name) {
  if (name == "determinant" || name == "transpose" || name == "getmatrix" ||
      name == "texture" || name == "texture3d" || name == "environment" ||
      name == "gettextureinfo" || name == "isconnected" || name == "split" ||
      ::osl::stringFunctionCode(name) >= 0 || ::osl::closureId(name) >= 0)
    return true;
  for (const Builtin &b : builtinTable())
    if (name == b.name)
      return true;
  for (const char *u : kUnsupported)
    if (name == u)
      return true;
  return false;
}

std::optional<RValue> emitBuiltinCall(IRGen &g, const Expr &call,
                                      const OslType *expected, bool &known) {
  known = true;
  bool matrixBuiltin = true;
  auto m = emitMatrixBuiltin(g, call, matrixBuiltin);
  if (matrixBuiltin)
    return m;
  if (call.isCtor)
    return emitConstructor(g, call);
  bool textureBuiltin = true;
  auto texture = emitTextureBuiltin(g, call, expected, textureBuiltin);
  if (textureBuiltin)
    return texture;
  bool closureBuiltin = true;
  auto closure = emitClosureBuiltin(g, call, closureBuiltin);
  if (closureBuiltin)
    return closure;
  bool stringBuiltin = true;
  auto string = emitStringBuiltin(g, call, stringBuiltin);
  if (stringBuiltin)
    return string;
  bool connectionBuiltin = true;
  auto connection = emitConnectionBuiltin(g, call, connectionBuiltin);
  if (connectionBuiltin)
    return connection;
  bool messageBuiltin = true;
  auto message = emitMessageBuiltin(g, call, messageBuiltin);
  if (messageBuiltin)
    return message;
  llvm::StringRef name = call.name;
  if (name == "noise" || name == "snoise" || name == "cellnoise" || name == "hashnoise" ||
      name == "pnoise" || name == "psnoise")
    return emitNoise(g, call, expected);
  if (name == "transform")
    return emitTransform(g, call);
  if (name == "transformc")
    return emitTransformc(g, call);
  if (name == "spline" || name == "splineinverse")
    return emitSpline(g, call, name == "splineinverse");
  if (name == "raytype") {
    // testshade shades camera rays.
    auto args = emitArgs(g, call);
    if (!args)
      return std::nullopt;
    if (args->size() != 1 || !(*args)[0].type.isString()) {
      g.error(call.loc, "wrong arguments to 'raytype'; candidates: int raytype(string name)");
      return std::nullopt;
    }
    if ((*args)[0].isRuntimeString()) {
      g.error(call.args[0]->begin, "'raytype' needs the ray type known when the shader is "
                                   "compiled; this string is computed at run time");
      return std::nullopt;
    }
    // A name chosen per point answers for each choice.
    return g.forEachStringChoice((*args)[0], call.loc, [&](const std::string &name) {
      return std::optional<RValue>(RValue::num(
          OslType(BaseType::Int), g.constInt(name == g.rayType() ? 1 : 0, call.loc)));
    });
  }
  if (name == "getattribute")
    return emitGetAttribute(g, call);
  if (name == "exit") {
    if (!call.args.empty()) {
      g.error(call.loc, "'exit' takes no arguments");
      return std::nullopt;
    }
    g.emitExit(call.loc);
    return RValue::voidValue();
  }
  if (name == "sincos")
    return emitSincos(g, call);
  if (name == "fresnel")
    return emitFresnel(g, call);
  if (name == "isconstant") {
    auto args = emitArgs(g, call);
    if (!args)
      return std::nullopt;
    if (args->size() != 1) {
      g.error(call.loc, "wrong arguments to 'isconstant'; candidates: int isconstant(T)");
      return std::nullopt;
    }
    const RValue &a = (*args)[0];
    // A string is constant unless chosen or computed per point.
    if (a.type.isString())
      return RValue::num(OslType(BaseType::Int), g.constInt(a.isKnownString(), call.loc));
    if (!a.value) {
      g.error(call.args[0]->loc, "'isconstant' takes a number, triple or string, got '" +
                                     a.type.str() + "'");
      return std::nullopt;
    }
    return RValue::num(OslType(BaseType::Int),
                       g.builder().create<IsConstantOp>(g.loc(call.loc), g.builder().getI32Type(), a.value));
  }
  if (name == "arraylength") {
    auto args = emitArgs(g, call);
    if (!args)
      return std::nullopt;
    if (args->size() != 1 || !(*args)[0].type.isArray()) {
      g.error(call.loc, "wrong arguments to 'arraylength(" + argTypesText(*args) +
                            ")'; candidates: int arraylength(T[])");
      return std::nullopt;
    }
    return RValue::num(OslType(BaseType::Int),
                       g.constInt((*args)[0].type.arrayLen, call.loc));
  }
  for (const Builtin &b : builtinTable())
    if (name == b.name)
      return emitTableCall(g, b, call);
  for (const char *u : kUnsupported)
    if (name == u) {
      g.error(call.loc, "function '" + name + "' is not supported yet");
      return std::nullopt;
    }
  known = false;
  return std::nullopt;
}

} // namespace osl::frontend
