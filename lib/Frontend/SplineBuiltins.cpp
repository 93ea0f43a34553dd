//===- SplineBuiltins.cpp - spline, splineinverse ---------------------------===//
#include "IRGen.h"

using namespace mlir;
using namespace mlir::osl;

namespace osl::frontend {

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
  // OSL evaluates a basis it does not know as linear; say so.
  for (const std::string &basis : *knownBases)
    if (!splineBasisFromName(basis) &&
        !g.diagnostics().warning(call.args[0]->loc,
                                 "unknown spline basis '" + basis +
                                     "' is linear (known: catmull-rom, bezier, bspline, "
                                     "hermite, linear, constant)"))
      return std::nullopt;
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
      // Fewer than 4 make no whole segment, and OSL reads knots before
      // the array (LaneSpline reads the first there); more than the array
      // holds would read past it.
      if (k && (*k < 0 || size_t(*k) > arr.elems.size())) {
        g.error(call.args[2]->loc, "knot count " + llvm::Twine(*k) +
                                       " is out of range for '" + arr.type.str() + "' (0 to " +
                                       llvm::Twine(arr.elems.size()) + ")");
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
  if (knots.empty()) {
    g.error(knotLoc, "'" + fn + "' needs at least 4 knots, got none");
    return std::nullopt;
  }
  if (knots.size() < 4) {
    // oslc accepts it and OSL reads past the knots; here the last knot
    // repeats, so a spline of one knot is that knot.
    if (!g.diagnostics().warning(knotLoc, ("'" + fn + "' needs at least 4 knots, got " +
                                              std::to_string(knots.size()) +
                                              "; the last one is repeated").str()))
      return std::nullopt;
    while (knots.size() < 4)
      knots.push_back(knots.back());
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
    SplineBasis kind = splineBasisFromName(basis).value_or(SplineBasis::linear);
    Value v =
        inverse
            ? g.builder().create<SplineInverseOp>(g.loc(call.loc), t, kind, xv, count, kv)
                  .getResult()
            : g.builder().create<SplineOp>(g.loc(call.loc), t, kind, xv, count, kv)
                  .getResult();
    return std::optional<RValue>(RValue::num(knotType, v));
  });
}

} // namespace osl::frontend
