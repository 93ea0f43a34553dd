//===- NoiseBuiltins.cpp - noise, snoise, cellnoise, pnoise, gabor ----------===//
//
// The noise family by name (a compile-time string, or one chosen per
// point), with Gabor noise's options (osl-lane-group-filter splits per-point ones).
//
//===----------------------------------------------------------------------===//
#include "IRGen.h"

#include "mlir/IR/Matchers.h"

using namespace mlir;
using namespace mlir::osl;

namespace osl::frontend {
namespace {

/// The values of noise("gabor", ..., "name", value, ...)'s options (null
/// where not given).
struct NoiseOptionValues {
  Value anisotropic, direction, bandwidth, impulses, doFilter;
};

/// Reads (name, value) option pairs from args[at] on: names are constant
/// strings; values may differ per point (osl-lane-group-filter runs the
/// noise once per group of lanes that agree); anisotropic and do_filter are ints, direction a
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
    if (name.str == "anisotropic" || name.str == "do_filter") {
      // A comparison is an int in OSL (`"do_filter", a != 1`).
      if (!v.type.isInt() && v.type.base != BaseType::Bool)
        return bad("an int");
      auto asInt = g.coerce(v, OslType(BaseType::Int), valueLoc,
                            "for noise option '" + name.str + "'");
      if (!asInt)
        return std::nullopt;
      (name.str == "anisotropic" ? out.anisotropic : out.doFilter) = asInt->value;
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
      g.valueError(nameLoc, "unknown noise option '" + name.str +
                                "' (known: anisotropic, direction, bandwidth, impulses, "
                                "do_filter)");
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

} // namespace

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
      g.valueError(call.args[0]->loc, "'" + name + "' takes no noise type name; use noise(\"" +
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
    std::optional<NoiseKind> kind = noiseKindFromName(k);
    // Simplex noise has no periodic form: OSL reports it as an unknown
    // periodic noise type where the point runs.
    if (kind && periodic && (*kind == NoiseKind::simplex || *kind == NoiseKind::usimplex))
      kind.reset();
    if (!kind) {
      // OSL's renderer reports an unknown name where the point runs, and
      // the noise is 0.
      g.reportAtRunTime(std::string(periodic ? "periodic " : "") + "noise type \"" + k +
                            "\" is unknown, called from (" + g.fileLine(call.loc) + ")",
                        call.loc);
      return std::optional<RValue>(g.zeroValue(resultType, call.loc));
    }
    if (*kind != NoiseKind::gabor) { // other noises ignore the options, as in OSL
      Value v = g.builder().create<NoiseOp>(g.loc(call.loc), t, *kind, coords, periodic);
      return std::optional<RValue>(RValue::num(resultType, v));
    }
    Value v = g.builder().create<NoiseOp>(
        g.loc(call.loc), t, *kind, coords, periodic,
        gaborFilterDerivs(g, call.loc, pointCoords, *options), options->anisotropic,
        options->direction, options->bandwidth, options->impulses, options->doFilter);
    return std::optional<RValue>(RValue::num(resultType, v));
  });
}

} // namespace osl::frontend
