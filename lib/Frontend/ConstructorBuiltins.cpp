//===- ConstructorBuiltins.cpp - int(), float(), color(), point()... -------===//
//
// Type constructors: conversions of one value, triples from one or three
// numbers, and triples in a named space (transformed to "common") or color
// space (converted to the working RGB space).
//
//===----------------------------------------------------------------------===//
#include "IRGen.h"

#include "mlir/Dialect/Arith/IR/Arith.h"

using namespace mlir;
using namespace mlir::osl;

namespace osl::frontend {

std::optional<RValue> emitTypeConstructor(IRGen &g, OslType t,
                                          const std::vector<ExprPtr> &callArgs, SrcLoc callLoc) {
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
        if (!knownColorTransform(g, space, "RGB", call.loc, /*constructor=*/true))
          return RValue::num(t, value);
        return RValue::num(t, g.builder().create<TransformcOp>(
                                  g.loc(call.loc), value.getType(), space, "rgb",
                                  g.workingColorSpace(), value));
      }
      if (space.empty()) {
        g.valueError(call.args[0]->loc, "empty space name");
        return std::nullopt;
      }
      if (space == "common" || !knownSpaces(g, space, "common", call.loc))
        return RValue::num(t, value);
      return RValue::num(t, g.builder().create<TransformOp>(g.loc(call.loc), value.getType(),
                                                            space, "common",
                                                            transformKindOf(t.base), value));
    };
    auto r = g.forEachStringChoice(args[0], call.loc, inSpace);
    if (!r)
      return std::nullopt;
    value = r->value;
  }
  return RValue::num(t, value);
}

} // namespace osl::frontend
