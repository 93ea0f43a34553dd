//===- Builtins.cpp - OSL library functions as osl ops ----------------------===//
//
// Most functions are described by an overload table: signatures in a
// compact code (f float, i int, s string, p/v/n/c point/vector/normal/
// color, T any triple, the same kind throughout one call) and an emitter.
// Overloads are ranked by the cost of the implicit conversions they need.
// Functions with string options, variable argument lists or a result type
// chosen by context are handled by hand: type constructors here, the rest
// in files of their own (NoiseBuiltins, SpaceBuiltins, SplineBuiltins,
// AttributeBuiltins, TextureBuiltins, StringBuiltins...).
//
//===----------------------------------------------------------------------===//
#include "IRGen.h"
#include "OslAbi/Closures.h"
#include "OslAbi/GlobalsLayout.h"
#include "OslAbi/Strings.h"
#include "OslLanes/ColorBuilder.h"

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
/// Where the renderer says the surface's handedness is flipped (the
/// flipHandedness global, 0 on osl-run's grid) the factors swap, as OSL's do.
Value emitCalculateNormal(IRGen &g, SrcLoc l, Vals a, OslType) {
  OpBuilder &b = g.builder();
  Location ml = g.loc(l);
  Value dx = derivOf(g, l, a[0], 'x'), dy = derivOf(g, l, a[0], 'y');
  Value flip = g.getGlobal("flipHandedness", b.getF32Type(), l);
  Value flipped = b.create<CmpOp>(ml, "ne", flip, g.constFloat(0, l));
  return b.create<SelectOp>(ml, flipped, b.create<CrossOp>(ml, dy, dx),
                            b.create<CrossOp>(ml, dx, dy));
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
    "random", "exit", "arraylength", "spline", "noise",
    "snoise", "cellnoise", "hashnoise", "transform", "ptransform", "vtransform",
    "ntransform", "displace", "bump", "fmin", "fmax", "nsnoise",
    "gabor", "pgabor", "sincos", "transformc", "fresnel", "getattribute", "artistic_ior",
    "isconstant", "pnoise", "psnoise", "getmatrix", "pointcloud_get", "pointcloud_search",
    "pointcloud_write",
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



std::optional<RValue> emitTableCall(IRGen &g, const Builtin &fn, const Expr &call,
                                    const OslType *callExpected) {
  // As oslc: where the context expects a triple and a signature returns
  // one, that signature's triple arguments expect the same type (`vector c
  // = normalize(snoise(p))` calls the vector snoise); elsewhere a
  // polymorphic argument is a float, promoted (`length(noise(p))`).
  std::vector<const OslType *> expected(call.args.size(), nullptr);
  if (callExpected && callExpected->isTriple() && !callExpected->isArray())
    for (const Sig &s : fn.sigs)
      if (std::strlen(s.args) == call.args.size() && s.ret[0] == 'T') {
        for (size_t k = 0; k < call.args.size(); ++k)
          if (s.args[k] == 'T')
            expected[k] = callExpected;
        break;
      }
  auto args = emitArgs(g, call, expected);
  if (!args)
    return std::nullopt;
  if (llvm::StringRef(fn.name) == "mix" && args->size() == 3 &&
      (*args)[0].type.base == BaseType::Closure)
    return emitClosureMix(g, (*args)[0], (*args)[1], (*args)[2], call.loc);
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
    // No triple argument: a float promotes to a vector, as oslc's chosen
    // candidate (`length(noise(p))`, `dot(noise(p), v)`).
    if (tKind == BaseType::Void && std::strchr(s.args, 'T'))
      tKind = BaseType::Vector;
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


std::optional<RValue> emitConstructor(IRGen &g, const Expr &call) {
  return emitTypeConstructor(g, call.castType, call.args, call.loc);
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

} // namespace

namespace osl::frontend {

std::optional<std::vector<RValue>> emitArgs(IRGen &g, const Expr &call) {
  return emitArgs(g, call, {});
}

std::optional<std::vector<RValue>> emitArgs(IRGen &g, const Expr &call,
                                            llvm::ArrayRef<const OslType *> expected) {
  std::vector<RValue> args;
  for (size_t k = 0; k < call.args.size(); ++k) {
    auto v = g.emitExpr(*call.args[k], k < expected.size() ? expected[k] : nullptr);
    if (!v)
      return std::nullopt;
    args.push_back(*v);
  }
  return args;
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
  bool pointCloudBuiltin = true;
  auto pointCloud = emitPointCloudBuiltin(g, call, pointCloudBuiltin);
  if (pointCloudBuiltin)
    return pointCloud;
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
      g.valueError(call.args[0]->begin, "'raytype' needs the ray type known when the shader is "
                                        "compiled; this string is computed at run time");
      return std::nullopt;
    }
    // A name chosen per point answers for each choice. Without a ray type
    // (a renderer's shaders), the "raytype" row holds each point's bits.
    return g.forEachStringChoice((*args)[0], call.loc, [&](const std::string &name) {
      if (!g.rayType().empty() || !::osl::rayTypeBit(name))
        return std::optional<RValue>(RValue::num(
            OslType(BaseType::Int), g.constInt(name == g.rayType() ? 1 : 0, call.loc)));
      OpBuilder &b = g.builder();
      Value bits = g.convert(g.getGlobal("raytype", b.getF32Type(), call.loc), b.getI32Type(),
                             call.loc);
      Value bit = g.constInt(::osl::rayTypeBit(name), call.loc);
      Value set = b.create<BitAndOp>(g.loc(call.loc), bits, bit);
      Value isSet = b.create<CmpOp>(g.loc(call.loc), "ne", set, g.constInt(0, call.loc));
      return std::optional<RValue>(RValue::num(OslType(BaseType::Int),
                                               classifyResult(g, call.loc, isSet)));
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
  if (name == "artistic_ior")
    return emitArtisticIor(g, call);
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
      return emitTableCall(g, b, call, expected);
  for (const char *u : kUnsupported)
    if (name == u) {
      g.error(call.loc, "function '" + name + "' is not supported yet");
      return std::nullopt;
    }
  known = false;
  return std::nullopt;
}

std::string argTypesText(const std::vector<RValue> &args) {
  std::string t;
  for (size_t k = 0; k < args.size(); ++k)
    t += (k ? ", " : "") + args[k].type.str();
  return t;
}

/// A compile-time string argument.
bool stringArg(IRGen &g, const RValue &v, const Expr &e, llvm::StringRef fn,
               llvm::StringRef what, std::string &out) {
  if (!v.type.isString())
    return g.error(e.loc, "'" + fn + "' expects " + what + " (a string) here, got '" +
                              v.type.str() + "'");
  if (v.isStringChoice())
    return g.valueError(e.loc, "'" + fn + "' needs " + what +
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

mlir::Value derivOf(IRGen &g, SrcLoc l, mlir::Value v, char axis) {
  DerivAxis which = axis == 'x' ? DerivAxis::x : axis == 'y' ? DerivAxis::y : DerivAxis::z;
  return g.builder().create<DerivOp>(g.loc(l), v.getType(), v, which);
}

} // namespace osl::frontend
