//===- DebugNan.cpp - testshade's --debugnan --------------------------------===//
//
// With FrontendOptions::debugNan, every value stored into a named variable
// (assignment, compound assignment, initialized declaration) is checked
// where it is stored: a point whose value has a NaN (or else an infinity)
// in a float, triple, matrix or array component reports, as OSL's debugnan
// mode does,
//   ERROR: Detected nan value in Cout at test.osl:9 (op texture)
// naming the variable, the statement's place and the operation that made
// the value (the call, operator or assignment, through casts).
//
//===----------------------------------------------------------------------===//
#include "IRGen.h"

#include <cmath>

using namespace mlir;
using namespace mlir::osl;

namespace osl::frontend {

namespace {

/// OSL's op code for an arithmetic operator ("+" or "+="), or "".
const char *arithmeticOp(llvm::StringRef symbol) {
  static const std::pair<const char *, const char *> kOps[] = {
      {"+", "add"}, {"-", "sub"}, {"*", "mul"}, {"/", "div"}, {"%", "mod"}};
  for (auto [s, op] : kOps)
    if (symbol == s || symbol == std::string(s) + "=")
      return op;
  return "";
}

/// OSL's name for the operation that stores `e` into a variable with
/// `assignOp` ("=", "+=", ... or "" for an initializer): add, sub, mul, div,
/// mod, neg, the function's name, assign for a plain copy.
std::string opName(const Expr &e, llvm::StringRef assignOp) {
  if (*arithmeticOp(assignOp))
    return arithmeticOp(assignOp);
  const Expr *x = &e;
  while (x->kind == ExprKind::Cast || (x->kind == ExprKind::Unary && x->name == "+"))
    x = x->args[0].get();
  switch (x->kind) {
  case ExprKind::Call:
    return x->name;
  case ExprKind::Unary:
    return x->name == "-" ? "neg" : "assign";
  case ExprKind::Binary:
    return *arithmeticOp(x->name) ? arithmeticOp(x->name) : "assign";
  default:
    return "assign";
  }
}

/// The float components of `v` (none for ints, strings and closures).
void floatComponents(IRGen &g, const RValue &v, SrcLoc l, std::vector<Value> &out) {
  OpBuilder &b = g.builder();
  auto add = [&](Value x) {
    Type t = getUniformType(x.getType());
    if (t.isF32()) {
      out.push_back(x);
    } else if (isTriple(t)) {
      for (int j = 0; j < 3; ++j)
        out.push_back(b.create<ExtractOp>(g.loc(l),
                                          withUniformity(b.getF32Type(), isVarying(x.getType())),
                                          x, b.getI64IntegerAttr(j)));
    }
  };
  if (v.type.hasElems()) {
    for (Value e : v.elems)
      add(e);
  } else if (!v.fields.empty()) {
    for (const RValue &f : v.fields)
      floatComponents(g, f, l, out);
  } else if (v.value && !v.type.isString() && v.type.base != BaseType::Closure) {
    add(v.value);
  }
}

} // namespace

bool IRGen::checkNotNan(const std::string &name, const RValue &v, const Expr &source,
                        llvm::StringRef assignOp, SrcLoc l) {
  if (!options.debugNan)
    return true;
  std::vector<Value> comps;
  floatComponents(*this, v, l, comps);
  if (comps.empty())
    return true;
  Value anyNan, anyInf;
  for (Value c : comps) {
    Value nan = b.create<CmpOp>(loc(l), "ne", c, c);
    Value inf = b.create<CmpOp>(loc(l), "eq", b.create<AbsOp>(loc(l), c),
                                constFloat(INFINITY, l));
    anyNan = anyNan ? b.create<OrOp>(loc(l), anyNan, nan).getResult() : nan;
    anyInf = anyInf ? b.create<OrOp>(loc(l), anyInf, inf).getResult() : inf;
  }
  std::string where = " value in " + name + " at " + fileLine(l) + " (op " + opName(source, assignOp) + ")";
  auto report = [&](const char *what) {
    return [&, what]() -> std::optional<RValue> {
      reportAtRunTime(std::string("Detected ") + what + where, l);
      return RValue::voidValue();
    };
  };
  auto nothing = []() -> std::optional<RValue> { return RValue::voidValue(); };
  // A NaN is reported; an infinity where there is none.
  auto reported = emitIfRegion(
      anyNan, l, {}, report("nan"),
      [&]() { return emitIfRegion(anyInf, l, {}, report("inf"), nothing, false); }, false);
  return reported.has_value();
}

} // namespace osl::frontend
