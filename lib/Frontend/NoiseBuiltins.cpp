//===- NoiseBuiltins.cpp - noise, snoise, cellnoise, pnoise, gabor ----------===//
//
// The noise family by name (a compile-time string, or one chosen per
// point: one osl.noise_by_kind), with Gabor noise's options
// (osl-lane-group-filter splits per-point ones).
//
//===----------------------------------------------------------------------===//
#include "IRGen.h"

#include "mlir/Dialect/Arith/IR/Arith.h"
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

/// The kinds a noise name may be, in the order of `choices`; none if a
/// name is unknown (for periodic noise, simplex is: OSL reports it where
/// the point runs, which the per-name expansion does).
std::optional<std::vector<NoiseKind>> knownKinds(const std::vector<std::string> &choices,
                                                 bool periodic) {
  std::vector<NoiseKind> kinds;
  for (const std::string &name : choices) {
    std::optional<NoiseKind> kind = noiseKindFromName(name);
    if (!kind || (periodic && (*kind == NoiseKind::simplex || *kind == NoiseKind::usimplex)))
      return std::nullopt;
    kinds.push_back(*kind);
  }
  return kinds;
}

/// noise(name, ...) whose name is one of several strings (`kindName`, a
/// string choice) naming at least two kinds, without Gabor options: one
/// osl.noise_by_kind on the kind the choice picks (null otherwise, and the
/// noise is expanded per name).
Value emitNoiseByKind(IRGen &g, const Expr &call, const RValue &kindName,
                      const NoiseOptionValues &options, llvm::ArrayRef<Value> coords,
                      llvm::ArrayRef<Value> pointCoords, bool periodic, Type resultType) {
  if (!kindName.isStringChoice() || options.anisotropic || options.direction ||
      options.bandwidth || options.impulses || options.doFilter)
    return {};
  std::optional<std::vector<NoiseKind>> kinds = knownKinds(kindName.choices, periodic);
  if (!kinds || llvm::all_equal(*kinds))
    return {};
  OpBuilder &b = g.builder();
  Location loc = g.loc(call.loc);
  // The kind of each choice, as the per-name expansion picks it: choice 0,
  // else choice 1, ..., else the last.
  Value kind;
  int32_t last = int32_t(kinds->size()) - 1;
  if (kinds->size() >= size_t(IRGen::kTableMinLength)) {
    SmallVector<int32_t> table;
    for (NoiseKind k : *kinds)
      table.push_back(int32_t(k));
    Value index = b.create<ClampOp>(loc, kindName.value, g.constInt(0, call.loc),
                                    g.constInt(last, call.loc));
    kind = b.create<TableReadOp>(
        loc, withUniformity(b.getI32Type(), isVarying(index.getType())),
        DenseElementsAttr::get(RankedTensorType::get({int64_t(table.size())}, b.getI32Type()),
                               ArrayRef<int32_t>(table)),
        index);
  } else {
    kind = g.constInt(int32_t(kinds->back()), call.loc);
    for (int32_t k = last; k-- > 0;) {
      Value isK = b.create<CmpOp>(loc, "eq", kindName.value, g.constInt(k, call.loc));
      kind = b.create<SelectOp>(loc, isK, g.constInt(int32_t((*kinds)[k]), call.loc), kind);
    }
  }
  // Gabor's filter reads the point's derivatives; zeros stand in where no
  // name is "gabor" (the routine never reads them then).
  bool gabor = llvm::is_contained(*kinds, NoiseKind::gabor);
  std::vector<Value> derivs;
  if (pointCoords.size() > 1 || isTriple(getUniformType(pointCoords[0].getType()))) {
    for (char axis : {'x', 'y'})
      for (Value c : pointCoords)
        derivs.push_back(gabor ? derivOf(g, call.loc, c, axis)
                               : b.create<arith::ConstantOp>(
                                     loc, b.getZeroAttr(getUniformType(c.getType()))));
  }
  // A kind chosen per point makes the noise vary even at a uniform point.
  Type type = withUniformity(getUniformType(resultType),
                             isVarying(resultType) || isVarying(kind.getType()));
  return b.create<NoiseByKindOp>(loc, type, kind, coords, periodic, derivs);
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
  if (Value v = emitNoiseByKind(g, call, kindName, *options, coords, pointCoords, periodic, t))
    return RValue::num(resultType, v);
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
