//===- ClosureBuiltins.cpp - Closure calls and closure arithmetic ---------===//
//
// Every closure of OSL 1.13's standard library (OslAbi/Closures.h)
// becomes one osl.closure_component with its positional parameters then
// all its keyword parameters (absent ones 0 or ""); the stdosl.h overloads
// that forward to another signature (microfacet with one alpha,
// reflection without eta) are expanded here. Closures combine by
// closure * color, closure * float and closure + closure.
//
//===----------------------------------------------------------------------===//
#include "IRGen.h"
#include "OslAbi/Closures.h"

#include <map>

using namespace mlir;
using namespace mlir::osl;

namespace osl::frontend {
namespace {

OslType closureType() { return OslType(BaseType::Closure); }

OslType kindType(char kind) {
  switch (kind) {
  case 'n': return OslType(BaseType::Normal);
  case 'c': return OslType(BaseType::Color);
  case 'f': return OslType(BaseType::Float);
  case 'i': return OslType(BaseType::Int);
  case 's': return OslType(BaseType::String);
  default: return closureType();
  }
}

/// A positional parameter: its kind and array length (0: not an array).
struct ClosureParam {
  char kind;
  int32_t length;
};

std::vector<ClosureParam> positionalParams(int32_t id) {
  std::vector<ClosureParam> params;
  ::osl::forEachClosureParam(id, [&](char kind, int32_t length) {
    params.push_back({kind, length});
  });
  return params;
}

std::string signatureText(int32_t id) {
  std::string text = std::string("closure color ") + ::osl::kClosures[id].name + "(";
  bool first = true;
  for (ClosureParam p : positionalParams(id)) {
    text += (first ? "" : ", ") + kindType(p.kind).str();
    if (p.length)
      text += "[" + std::to_string(p.length) + "]";
    first = false;
  }
  ::osl::forEachClosureKeyword(id, [&](std::string_view name, char kind) {
    text += std::string(", [\"") + std::string(name) + "\", " + kindType(kind).str() + "]";
  });
  return text + ")";
}

/// The positional arguments stdosl.h's forwarding overloads pass on.
void expandOverloads(IRGen &g, int32_t id, std::vector<RValue> &args, SrcLoc l) {
  if (id == ::osl::kMicrofacet && args.size() == 5) {
    // microfacet(dist, N, alpha, eta, refr) = microfacet(dist, N, vector(0), alpha, alpha, eta, refr)
    RValue alpha = args[2];
    args.insert(args.begin() + 2, RValue::num(OslType(BaseType::Vector),
                                              g.constTriple(0, 0, 0, l)));
    args.insert(args.begin() + 4, alpha);
  } else if (id == ::osl::kReflection && args.size() == 1) {
    args.push_back(RValue::num(OslType(BaseType::Float), g.constFloat(0, l)));
  }
}

} // namespace

RValue emptyClosure(IRGen &g, SrcLoc l) {
  return RValue::num(closureType(), g.builder().create<ClosureEmptyOp>(
                                        g.loc(l), ClosureType::get(g.builder().getContext())));
}

std::optional<RValue> emitClosureBuiltin(IRGen &g, const Expr &call, bool &known) {
  int32_t id = ::osl::closureId(call.name);
  known = id >= 0;
  if (!known)
    return std::nullopt;
  std::vector<ClosureParam> params = positionalParams(id);
  std::vector<RValue> args;
  std::vector<const Expr *> argExprs;
  for (const ExprPtr &a : call.args) {
    auto v = g.emitExpr(*a);
    if (!v)
      return std::nullopt;
    args.push_back(*v);
    argExprs.push_back(a.get());
  }
  size_t given = args.size();
  expandOverloads(g, id, args, call.loc);
  size_t positional = params.size();
  auto wrong = [&](const llvm::Twine &why) -> std::optional<RValue> {
    g.error(call.loc, "wrong arguments to '" + call.name + "': " + why +
                          "; candidates: " + signatureText(id));
    return std::nullopt;
  };
  if (args.size() < positional)
    return wrong("expected " + llvm::Twine(positional) + " arguments, got " +
                 llvm::Twine(given));

  // Keyword pairs after the positional arguments.
  std::map<std::string, RValue> keywords;
  size_t firstKeyword = positional - (args.size() - given);
  std::vector<RValue> rest(args.begin() + positional, args.end());
  if (rest.size() % 2)
    return wrong("keyword arguments come in (\"name\", value) pairs");
  for (size_t k = 0; k < rest.size(); k += 2) {
    const RValue &key = rest[k];
    SrcLoc keyLoc = argExprs[firstKeyword + k]->loc;
    if (!key.isKnownString()) {
      g.error(keyLoc, "a keyword argument of '" + call.name +
                          "' must be named by a string literal");
      return std::nullopt;
    }
    bool accepted = false;
    ::osl::forEachClosureKeyword(id, [&](std::string_view name, char) {
      accepted |= name == key.str;
    });
    if (!accepted) {
      // OSL warns and ignores it (testshade's oren_nayar, for one, has no
      // "label").
      if (!g.diagnostics().warning(keyLoc, "unsupported closure keyword argument \"" +
                                               key.str + "\" for " + call.name + " (ignored)"))
        return std::nullopt;
      continue;
    }
    keywords[key.str] = rest[k + 1];
  }
  args.resize(positional);

  // Coerce each parameter to its kind; fill absent keywords.
  SmallVector<Value> operands;
  bool varying = false;
  auto addOperand = [&](RValue v, char kind, SrcLoc l, const std::string &what) -> bool {
    Value value;
    if (kind == 's') {
      if (!v.type.isString()) {
        g.error(l, "cannot convert '" + v.type.str() + "' to 'string' " + what);
        return false;
      }
      value = g.stringHandle(v, l);
    } else {
      auto c = g.coerce(v, kindType(kind), l, what);
      if (!c)
        return false;
      value = c->value;
    }
    varying |= isVarying(value.getType());
    operands.push_back(value);
    return true;
  };
  for (size_t k = 0; k < positional; ++k) {
    SrcLoc l = k < given ? argExprs[std::min(k, given - 1)]->begin : call.loc;
    std::string what = "for argument " + std::to_string(k + 1) + " of '" + call.name + "'";
    const RValue &arg = args[k];
    if (!params[k].length) {
      if (!addOperand(arg, params[k].kind, l, what))
        return std::nullopt;
      continue;
    }
    // An array parameter: one operand per element.
    OslType want = kindType(params[k].kind);
    want.arrayLen = params[k].length;
    if (!arg.type.isArray() || arg.type.arrayLen != params[k].length) {
      g.error(l, "cannot convert '" + arg.type.str() + "' to '" + want.str() + "' " + what);
      return std::nullopt;
    }
    for (int32_t e = 0; e < params[k].length; ++e) {
      RValue element = arg.type.base == BaseType::String
                           ? arg.fields[size_t(e)]
                           : RValue::num(arg.type.element(), arg.elems[size_t(e)]);
      if (!addOperand(element, params[k].kind, l, what))
        return std::nullopt;
    }
  }
  bool ok = true;
  ::osl::forEachClosureKeyword(id, [&](std::string_view name, char kind) {
    if (!ok)
      return;
    auto it = keywords.find(std::string(name));
    RValue v = it != keywords.end() ? it->second : g.zeroValue(kindType(kind), call.loc);
    ok = addOperand(v, kind, call.loc,
                    "for keyword '" + std::string(name) + "' of '" + call.name + "'");
  });
  if (!ok)
    return std::nullopt;
  Type result = withUniformity(ClosureType::get(g.builder().getContext()), varying);
  Value c = g.builder().create<ClosureComponentOp>(g.loc(call.loc), result, call.name, operands);
  return RValue::num(closureType(), c);
}

std::optional<RValue> emitClosureArith(IRGen &g, llvm::StringRef op, RValue l, RValue r,
                                       SrcLoc sl) {
  auto invalid = [&]() -> std::optional<RValue> {
    g.error(sl, "invalid operands to '" + op + "': '" + l.type.str() + "' and '" +
                    r.type.str() + "'");
    return std::nullopt;
  };
  OpBuilder &b = g.builder();
  Location loc = g.loc(sl);
  auto resultType = [&](Value x, Value y) {
    return withUniformity(ClosureType::get(b.getContext()),
                          isVarying(x.getType()) || isVarying(y.getType()));
  };
  bool lc = l.type.base == BaseType::Closure && !l.type.isArray();
  bool rc = r.type.base == BaseType::Closure && !r.type.isArray();
  if (op == "+" && lc && rc)
    return RValue::num(closureType(), b.create<ClosureAddOp>(loc, resultType(l.value, r.value),
                                                             l.value, r.value));
  if (op == "*" && lc != rc) {
    RValue &closure = lc ? l : r, &weight = lc ? r : l;
    if (!weight.type.isScalar() && !weight.type.isTriple())
      return invalid();
    auto color = g.coerce(weight, OslType(BaseType::Color), sl, "as a closure weight");
    if (!color)
      return std::nullopt;
    return RValue::num(closureType(),
                       b.create<ClosureMulOp>(loc, resultType(closure.value, color->value),
                                              closure.value, color->value));
  }
  return invalid();
}

std::optional<RValue> emitClosureMix(IRGen &g, RValue x, RValue y, RValue a, SrcLoc sl) {
  // stdosl.h's two: a float weight, or a color one (x*(1-a) + y*a).
  bool colorWeight = a.type.isTriple();
  if (y.type.base != BaseType::Closure || x.type.isArray() || y.type.isArray() ||
      !(a.type.isScalar() || colorWeight)) {
    g.error(sl, "wrong arguments to 'mix(" + x.type.str() + ", " + y.type.str() + ", " +
                    a.type.str() + ")'; candidates: closure color mix(closure color, "
                    "closure color, float); closure color mix(closure color, closure color, "
                    "color)");
    return std::nullopt;
  }
  OslType weightType(colorWeight ? BaseType::Color : BaseType::Float);
  auto weight = g.coerce(a, weightType, sl, "as mix's weight");
  if (!weight)
    return std::nullopt;
  Value one = colorWeight ? g.constTriple(1, 1, 1, sl) : g.constFloat(1, sl);
  Value rest = g.builder().create<SubOp>(g.loc(sl), one, weight->value);
  auto left = emitClosureArith(g, "*", x, RValue::num(weightType, rest), sl);
  auto right = left ? emitClosureArith(g, "*", y, *weight, sl) : std::nullopt;
  if (!right)
    return std::nullopt;
  return emitClosureArith(g, "+", *left, *right, sl);
}

} // namespace osl::frontend
