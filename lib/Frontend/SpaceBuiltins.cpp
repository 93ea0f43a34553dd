//===- SpaceBuiltins.cpp - transform, transformc ----------------------------===//
//
// Points, vectors and normals between named coordinate spaces, matrices
// aside (MatrixBuiltins.cpp), and colors between color spaces. A space the
// renderer does not know is reported when the point runs, and the value is
// left as it is, as in OSL.
//
//===----------------------------------------------------------------------===//
#include "IRGen.h"
#include "OslLanes/ColorBuilder.h"

using namespace mlir;
using namespace mlir::osl;

namespace osl::frontend {

/// Whether the renderer knows `from` as a source space and `to` as a
/// destination (testshade's knows "camera" and the projection spaces only
/// as destinations); each unknown one is reported when the point runs (the
/// transform is then the identity, as in OSL).
bool knownSpaces(IRGen &g, llvm::StringRef from, llvm::StringRef to, SrcLoc l) {
  bool fromKnown = bool(namedSpaceTransform(from, "common", g.cameraImage()));
  bool toKnown = bool(namedSpaceTransform("common", to, g.cameraImage()));
  for (auto [name, known] : {std::pair(from, fromKnown), std::pair(to, toKnown)})
    if (!known)
      g.reportAtRunTime("Unknown transformation \"" + name.str() + "\"", l);
  return fromKnown && toKnown;
}

/// Whether transformc(from, to, ...) can convert; if not, the color stays as
/// it is and the renderer reports it when the point runs, as OSL's does.
bool knownColorTransform(IRGen &g, const std::string &from, const std::string &to,
                         SrcLoc l, bool constructor) {
  // A constructor, color("space", ...), knows OSL's own spaces only: the
  // names OSL's transformc takes from OpenColorIO ("sRGB", "linear") are
  // unknown there, as testshade reports them.
  bool fromOcio = constructor && (from == "sRGB" || from == "linear");
  if (!fromOcio && isColorSpaceName(from, g.workingColorSpace()) &&
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

std::optional<RValue> emitTransform(IRGen &g, const Expr &call) {
  // The last argument is a point, vector or normal: a noise() there is the
  // vector noise, as oslc resolves it.
  static const OslType vectorType(BaseType::Vector);
  std::vector<const OslType *> expected(call.args.size(), nullptr);
  if (!expected.empty())
    expected.back() = &vectorType;
  auto args = emitArgs(g, call, expected);
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
  // An empty name is unknown like any other, reported where a point takes
  // it (among names chosen per point it is often one none takes: a string
  // function's return value before its returns).
  auto between = [&](const std::string &from, const std::string &to) -> std::optional<RValue> {
    if (from.empty() || to.empty())
      return knownSpaces(g, from, to, call.loc), std::optional<RValue>(p);
    if (from == to)
      return p;
    // An unknown space (reported) leaves the point as it is, as in OSL.
    if (!knownSpaces(g, from, to, call.loc))
      return p;
    if (isProjectionSpace(to)) {
      // The camera's projection depends on the image size the front end was
      // given: a constant matrix, applied with the w divide.
      bool known = true;
      RValue m = g.namedMatrix(from, to, call.loc, known);
      return RValue::num(p.type, g.transformByMatrix(m.elems, p.value, p.type.base, call.loc));
    }
    Value v = g.builder().create<TransformOp>(g.loc(call.loc), p.value.getType(), from, to,
                                              transformKindOf(p.type.base), p.value);
    return RValue::num(p.type, v);
  };
  RValue from = n == 3 ? (*args)[0] : RValue::string("common");
  const RValue &to = (*args)[n - 2];
  return g.forEachStringChoice(from, call.loc, [&](const std::string &f) {
    return g.forEachStringChoice(to, call.loc, [&](const std::string &t) { return between(f, t); });
  });
}

} // namespace osl::frontend
