//===- IRGenExpr.cpp - Expressions -----------------------------------------===//
//
// Lvalues, components and array elements are IRGenAccess.cpp's.
//
//===----------------------------------------------------------------------===//
#include "IRGen.h"

#include "mlir/Dialect/Arith/IR/Arith.h"
#include "llvm/ADT/STLExtras.h"
#include "llvm/ADT/StringSwitch.h"

#include <algorithm>

using namespace osl::frontend;
using namespace mlir;
using namespace mlir::osl;

namespace {
constexpr unsigned kMaxExprDepth = 1000;
} // namespace

//===----------------------------------------------------------------------===//
// Expressions
//===----------------------------------------------------------------------===//

std::optional<RValue> IRGen::emitExpr(const Expr &e, const OslType *expected) {
  if (exprDepth >= kMaxExprDepth) {
    error(e.loc, "expression is nested too deeply");
    return std::nullopt;
  }
  struct DepthGuard {
    unsigned &d;
    DepthGuard(unsigned &d) : d(d) { ++d; }
    ~DepthGuard() { --d; }
  } guard(exprDepth);
  if (!checkSize(e.loc))
    return std::nullopt;
  if (!preEvaluated.empty())
    if (auto it = preEvaluated.find(&e); it != preEvaluated.end())
      return it->second;

  switch (e.kind) {
  case ExprKind::IntLit:
    return RValue::num(OslType(BaseType::Int), constInt(int32_t(e.intValue), e.loc));
  case ExprKind::FloatLit:
    return RValue::num(OslType(BaseType::Float), constFloat(float(e.floatValue), e.loc));
  case ExprKind::StringLit:
    return RValue::string(e.name);
  case ExprKind::Ident:
    return emitIdent(e);
  case ExprKind::Unary:
    return emitUnary(e, expected);
  case ExprKind::Binary: {
    if (e.name == "&&" || e.name == "||")
      return emitLogical(e);
    // As in oslc, the type the context expects flows into the operands of
    // arithmetic, so `color c = k * noise(p)` calls the color noise.
    bool arithmetic = e.name == "+" || e.name == "-" || e.name == "*" || e.name == "/";
    const OslType *operandExpected = arithmetic ? expected : nullptr;
    // A variable operand is read where the operator runs (OSL's ops take
    // the variable itself): in a + f(a), after f may have changed a.
    bool readLeftAfter = isVariableRead(*e.args[0]) && mayHaveSideEffects(*e.args[1]);
    std::optional<RValue> l, r;
    if (readLeftAfter && !(r = emitExpr(*e.args[1], operandExpected)))
      return std::nullopt;
    if (!(l = emitExpr(*e.args[0], operandExpected)))
      return std::nullopt;
    if (!r && !(r = emitExpr(*e.args[1], operandExpected)))
      return std::nullopt;
    std::optional<RValue> overloaded;
    if (tryOverloadedOperator(e.name, e, {*l, *r}, overloaded))
      return overloaded;
    return emitBinaryOp(e.name, *l, *r, e.loc);
  }
  case ExprKind::Assign:
    return emitAssign(e);
  case ExprKind::IncDec:
    return emitIncDec(e);
  case ExprKind::Ternary:
    return emitTernary(e, expected);
  case ExprKind::Call:
    return emitCall(e, expected);
  case ExprKind::Index:
  case ExprKind::Member:
    return emitIndexOrMember(e);
  case ExprKind::Cast: {
    auto v = emitExpr(*e.args[0], &e.castType);
    if (!v)
      return std::nullopt;
    if (e.castType.base == BaseType::Closure || e.castType.isVoid() ||
        (e.castType.base == BaseType::Matrix && e.castType.isArray())) {
      error(e.loc, "casts to '" + e.castType.str() + "' are not supported");
      return std::nullopt;
    }
    return cast(*v, e.castType, e.loc);
  }
  case ExprKind::Comma: {
    for (size_t k = 0; k + 1 < e.args.size(); ++k)
      if (!emitExpr(*e.args[k]))
        return std::nullopt;
    return emitExpr(*e.args.back(), expected);
  }
  case ExprKind::InitList: {
    // `{...}` takes its type from where it goes (an assignment, a return).
    if (!expected) {
      error(e.loc, "an initializer list needs a type from its context here");
      return std::nullopt;
    }
    OslType type = *expected;
    return emitInitializer(e, type, "the initializer list", e.begin);
  }
  }
  return std::nullopt;
}

bool ::osl::frontend::mayHaveSideEffects(const Expr &e) {
  if (e.kind == ExprKind::Assign || e.kind == ExprKind::IncDec ||
      (e.kind == ExprKind::Call && !e.isCtor))
    return true;
  return llvm::any_of(e.args, [](const ExprPtr &a) { return a && mayHaveSideEffects(*a); });
}

std::optional<RValue> IRGen::emitIdent(const Expr &e) {
  if (Var *v = lookupVar(e.name))
    return readVar(v, e.loc);
  if (auto c = lookupFloatConstant(e.name))
    return RValue::num(OslType(BaseType::Float), constFloat(float(*c), e.loc));
  if (allFunctions.count(e.name) || isBuiltinName(e.name))
    error(e.loc, "'" + e.name + "' is a function; call it with '" + e.name + "(...)'");
  else
    error(e.loc, "unknown identifier '" + e.name + "'");
  return std::nullopt;
}

std::optional<RValue> IRGen::emitUnary(const Expr &e, const OslType *expected) {
  bool arithmetic = e.name == "-" || e.name == "+";
  auto v = emitExpr(*e.args[0], arithmetic ? expected : nullptr);
  if (!v)
    return std::nullopt;
  const std::string &op = e.name;
  std::optional<RValue> overloaded;
  if (tryOverloadedOperator(op, e, {*v}, overloaded))
    return overloaded;
  if (op == "!") {
    auto c = toBool(*v, e.args[0]->loc);
    if (!c)
      return std::nullopt;
    if (auto k = getConstBool(*c))
      return RValue::num(OslType(BaseType::Bool), constBool(!*k, e.loc));
    return RValue::num(OslType(BaseType::Bool), b.create<NotOp>(loc(e.loc), *c));
  }
  if (v->type.isMatrix() && (op == "-" || op == "+")) {
    if (op == "+")
      return v;
    MatrixElems m;
    for (Value x : v->elems)
      m.push_back(fNeg(x, e.loc));
    return matrixValue(m);
  }
  if (!v->type.isNumeric()) {
    error(e.loc, "invalid operand to unary '" + op + "': '" + v->type.str() + "'");
    return std::nullopt;
  }
  if (v->type.isBool())
    v = RValue::num(OslType(BaseType::Int), convert(v->value, b.getI32Type(), e.loc));
  if (op == "+")
    return v;
  if (op == "~") {
    if (!v->type.isInt()) {
      error(e.loc, "operator '~' needs an int operand, got '" + v->type.str() + "'");
      return std::nullopt;
    }
    return RValue::num(v->type, b.create<BitNotOp>(loc(e.loc), v->value));
  }
  // Negation; fold literals so `-1` stays a constant. A literal's negation
  // is a constant of oslc's .oso, where -0 reads back as 0: OSL prints
  // `-0.0` as 0 (a variable's negation, folded at run time, stays -0).
  if (auto c = v->value.getDefiningOp<arith::ConstantOp>()) {
    if (auto ia = dyn_cast<IntegerAttr>(c.getValue()))
      return RValue::num(v->type, constInt(int32_t(0u - uint32_t(ia.getInt())), e.loc));
    bool literal = e.args[0]->kind == ExprKind::FloatLit || e.args[0]->kind == ExprKind::IntLit;
    if (auto fa = dyn_cast<FloatAttr>(c.getValue()))
      return RValue::num(v->type, constFloat(literal && fa.getValue().isZero()
                                                 ? 0.0f
                                                 : -float(fa.getValueAsDouble()),
                                             e.loc));
  }
  return RValue::num(v->type, b.create<NegOp>(loc(e.loc), v->value));
}

std::optional<RValue> IRGen::emitLogical(const Expr &e) {
  bool isAnd = e.name == "&&";
  auto l = emitExpr(*e.args[0]);
  if (!l)
    return std::nullopt;
  if (l->type.isStructLike()) {
    // A struct's && and || are its __operator__and__/or__ (no short
    // circuit: a function takes both operands).
    auto r = emitExpr(*e.args[1]);
    if (!r)
      return std::nullopt;
    std::optional<RValue> overloaded;
    if (tryOverloadedOperator(e.name, e, {*l, *r}, overloaded))
      return overloaded;
    error(e.loc, "invalid operands to '" + e.name + "': '" + l->type.str() + "' and '" +
                     r->type.str() + "' (no " + (isAnd ? "__operator__and__" : "__operator__or__") +
                     " for them)");
    return std::nullopt;
  }
  auto lc = toBool(*l, e.args[0]->loc);
  if (!lc)
    return std::nullopt;
  OslType boolType(BaseType::Bool);
  if (mustRunMasked(*e.args[1])) {
    // Short-circuit: the right side runs only when it decides the result.
    llvm::StringSet<> names;
    scanAssigned(*e.args[1], names);
    auto rhs = [&]() -> std::optional<RValue> {
      auto r = emitExpr(*e.args[1]);
      if (!r)
        return std::nullopt;
      auto rc = toBool(*r, e.args[1]->loc);
      if (!rc)
        return std::nullopt;
      return RValue::num(boolType, *rc);
    };
    auto fixed = [&]() -> std::optional<RValue> {
      return RValue::num(boolType, constBool(!isAnd, e.loc));
    };
    if (isAnd)
      return emitIfRegion(*lc, e.loc, names, rhs, fixed, true);
    return emitIfRegion(*lc, e.loc, names, fixed, rhs, true);
  }
  auto r = emitExpr(*e.args[1]);
  if (!r)
    return std::nullopt;
  auto rc = toBool(*r, e.args[1]->loc);
  if (!rc)
    return std::nullopt;
  Value v = isAnd ? b.create<AndOp>(loc(e.loc), *lc, *rc).getResult()
                  : b.create<OrOp>(loc(e.loc), *lc, *rc).getResult();
  return RValue::num(boolType, v);
}

std::optional<OslType> IRGen::unify(OslType a, OslType b2) {
  if (a == b2)
    return a;
  if (a.isMatrix() || b2.isMatrix())
    return (a.isMatrix() || a.isScalar()) && (b2.isMatrix() || b2.isScalar())
               ? std::optional<OslType>(OslType(BaseType::Matrix))
               : std::nullopt;
  if (a.isTriple() && b2.isTriple())
    return a;
  // `c ? diffuse(N) : 0`: the number must be 0 (coerce checks).
  if ((a.isClosure() && b2.isScalar()) || (a.isScalar() && b2.isClosure()))
    return OslType(BaseType::Closure);
  if (!a.isNumeric() || !b2.isNumeric())
    return std::nullopt;
  if (a.isTriple())
    return a;
  if (b2.isTriple())
    return b2;
  if (a.isFloat() || b2.isFloat())
    return OslType(BaseType::Float);
  return OslType(BaseType::Int);
}

std::optional<RValue> IRGen::selectFields(Value c, const RValue &a, const RValue &bv,
                                          SrcLoc l) {
  RValue r;
  r.type = a.type;
  if (a.type.isStructLike()) {
    for (size_t j = 0; j < a.fields.size(); ++j) {
      auto f = selectFields(c, a.fields[j], bv.fields[j], l);
      if (!f)
        return std::nullopt;
      r.fields.push_back(*f);
    }
    return r;
  }
  if (a.type.hasElems()) {
    for (size_t k = 0; k < a.elems.size(); ++k)
      r.elems.push_back(select(c, a.elems[k], bv.elems[k], l));
    return r;
  }
  if (!a.value || !bv.value || a.type.isString())
    return std::nullopt;
  r.value = select(c, a.value, bv.value, l);
  return r;
}

std::optional<RValue> IRGen::emitTernary(const Expr &e, const OslType *expected) {
  auto c = emitExpr(*e.args[0]);
  if (!c)
    return std::nullopt;
  auto cb = toBool(*c, e.args[0]->loc);
  if (!cb)
    return std::nullopt;
  // oslc's ?: takes no structs ("Cannot initialize struct S z = unknown").
  auto structArm = [&](const RValue &v) {
    if (!v.type.isStructLike())
      return false;
    error(e.loc, "'?:' does not take structs in OSL (oslc rejects '" + v.type.str() +
                     "' arms); choose with if/else");
    return true;
  };
  if (mustRunMasked(*e.args[1]) || mustRunMasked(*e.args[2])) {
    llvm::StringSet<> names;
    scanAssigned(*e.args[1], names);
    scanAssigned(*e.args[2], names);
    auto merged = emitIfRegion(
        *cb, e.loc, names, [&]() { return emitExpr(*e.args[1], expected); },
        [&]() { return emitExpr(*e.args[2], expected); }, true);
    if (merged && structArm(*merged))
      return std::nullopt;
    return merged;
  }
  auto a = emitExpr(*e.args[1], expected);
  if (!a)
    return std::nullopt;
  auto bv = emitExpr(*e.args[2], expected);
  if (!bv || structArm(*a) || structArm(*bv))
    return std::nullopt;
  if (a->type.isString() && bv->type.isString()) {
    if (auto k = getConstBool(*cb))
      return *k ? a : bv;
    if (a->isRuntimeString() || bv->isRuntimeString())
      return RValue::runtimeString(b.create<SelectOp>(
          loc(e.loc), *cb, stringHandle(*a, e.loc), stringHandle(*bv, e.loc)));
    if (!a->isStringChoice() && !bv->isStringChoice() && a->str == bv->str)
      return a;
    // choice 0 is the then-string, 1 the else-string
    Value index = b.create<SelectOp>(loc(e.loc), *cb, constInt(0, e.loc), constInt(1, e.loc));
    return stringChoice({*a, *bv}, index, e.loc);
  }
  auto t = unify(a->type, bv->type);
  if (t && t->isMatrix()) {
    auto ca = coerce(*a, *t, e.args[1]->begin, "");
    auto cbv = coerce(*bv, *t, e.args[2]->begin, "");
    if (!ca || !cbv)
      return std::nullopt;
    return selectFields(*cb, *ca, *cbv, e.loc);
  }
  if (!t || !(t->isNumeric() || t->isClosure())) {
    error(e.loc, "incompatible types in conditional expression: '" + a->type.str() +
                     "' and '" + bv->type.str() + "'");
    return std::nullopt;
  }
  auto ca = coerce(*a, *t, e.args[1]->begin, "");
  auto cbv = coerce(*bv, *t, e.args[2]->begin, "");
  if (!ca || !cbv)
    return std::nullopt;
  return RValue::num(*t, b.create<SelectOp>(loc(e.loc), *cb, ca->value, cbv->value));
}

std::optional<RValue> IRGen::emitBinaryOp(llvm::StringRef op, RValue l, RValue r,
                                          SrcLoc sl) {
  auto invalid = [&]() -> std::optional<RValue> {
    error(sl, "invalid operands to '" + op + "': '" + l.type.str() + "' and '" +
                  r.type.str() + "'");
    return std::nullopt;
  };
  if (l.type.base == BaseType::Closure || r.type.base == BaseType::Closure)
    return emitClosureArith(*this, op, l, r, sl);
  Location ml = loc(sl);
  bool isEq = op == "==" || op == "!=";
  if (l.type.isString() || r.type.isString()) {
    if (!isEq || !l.type.isString() || !r.type.isString())
      return invalid();
    if (l.isRuntimeString() || r.isRuntimeString()) {
      // Interned: equal strings have equal handles.
      Value eq = b.create<CmpOp>(ml, op == "==" ? "eq" : "ne", stringHandle(l, sl),
                                 stringHandle(r, sl));
      return RValue::num(OslType(BaseType::Bool), eq);
    }
    if (l.isStringChoice() || r.isStringChoice()) {
      // Equal where the chosen strings are: compare per pair of choices.
      const RValue &c = l.isStringChoice() ? l : r, &o = l.isStringChoice() ? r : l;
      Value eq = constBool(false, sl);
      for (size_t k = 0; k < c.choices.size(); ++k) {
        Value thisOne = b.create<CmpOp>(ml, "eq", c.value, constInt(int(k), sl));
        Value match;
        if (!o.isStringChoice()) {
          match = constBool(c.choices[k] == o.str, sl);
        } else {
          match = constBool(false, sl);
          for (size_t j = 0; j < o.choices.size(); ++j)
            if (o.choices[j] == c.choices[k])
              match = b.create<OrOp>(ml, match,
                                     b.create<CmpOp>(ml, "eq", o.value, constInt(int(j), sl)));
        }
        eq = b.create<OrOp>(ml, eq, b.create<AndOp>(ml, thisOne, match));
      }
      if (op == "!=")
        eq = b.create<NotOp>(ml, eq);
      return RValue::num(OslType(BaseType::Bool), eq);
    }
    return RValue::num(OslType(BaseType::Bool),
                       constBool((l.str == r.str) == (op == "=="), sl));
  }
  if (l.type.isMatrix() || r.type.isMatrix())
    return emitMatrixBinaryOp(op, l, r, sl);
  if (!l.type.isNumeric() || !r.type.isNumeric())
    return invalid();
  if (isEq && l.type.isBool() && r.type.isBool())
    return RValue::num(OslType(BaseType::Bool),
                       b.create<CmpOp>(ml, op == "==" ? "eq" : "ne", l.value, r.value));
  // Booleans are ints in arithmetic.
  for (RValue *v : {&l, &r})
    if (v->type.isBool())
      *v = RValue::num(OslType(BaseType::Int), convert(v->value, b.getI32Type(), sl));

  bool isBitwise = op == "&" || op == "|" || op == "^" || op == "<<" || op == ">>" ||
                   op == "%";
  if (isBitwise) {
    if (!l.type.isInt() || !r.type.isInt()) {
      error(sl, "operator '" + op + "' needs int operands, got '" + l.type.str() +
                    "' and '" + r.type.str() + "'");
      return std::nullopt;
    }
    Value v;
    if (op == "&") v = b.create<BitAndOp>(ml, l.value, r.value);
    else if (op == "|") v = b.create<BitOrOp>(ml, l.value, r.value);
    else if (op == "^") v = b.create<BitXorOp>(ml, l.value, r.value);
    else if (op == "<<") v = b.create<ShlOp>(ml, l.value, r.value);
    else if (op == ">>") v = b.create<ShrOp>(ml, l.value, r.value);
    else v = b.create<ModOp>(ml, l.value, r.value);
    return RValue::num(l.type, v);
  }

  bool isRel = op == "<" || op == "<=" || op == ">" || op == ">=";
  if (isRel && (l.type.isTriple() || r.type.isTriple())) {
    error(sl, "operator '" + op + "' cannot compare '" + l.type.str() + "' and '" +
                  r.type.str() + "'");
    return std::nullopt;
  }
  // Promote to a common type: triple > float > int.
  OslType common;
  if (l.type.isTriple() || r.type.isTriple()) {
    common = l.type.isTriple() ? l.type : r.type;
  } else if (l.type.isFloat() || r.type.isFloat()) {
    common = OslType(BaseType::Float);
  } else {
    common = OslType(BaseType::Int);
  }
  auto cl = coerce(l, common, sl, "");
  auto cr = coerce(r, common, sl, "");
  if (!cl || !cr)
    return std::nullopt;
  Value a = cl->value, c = cr->value;
  if (isEq || isRel) {
    llvm::StringRef pred = llvm::StringSwitch<llvm::StringRef>(op)
                               .Case("==", "eq")
                               .Case("!=", "ne")
                               .Case("<", "lt")
                               .Case("<=", "le")
                               .Case(">", "gt")
                               .Default("ge");
    // Unordered as OSL's JIT compares; constant scalars fold (so constant
    // conditions pick their branch at compile time).
    return RValue::num(OslType(BaseType::Bool), cmp(pred, a, c, sl, /*unordered=*/true));
  }
  OslType resultType = common;
  if (common.isTriple() && l.type.isTriple() && r.type.isTriple()) {
    // point - point is a vector; point +/- vector stays a point.
    if (op == "-" && l.type.base == BaseType::Point && r.type.base == BaseType::Point)
      resultType = OslType(BaseType::Vector);
    else if ((op == "+" || op == "-") && r.type.base == BaseType::Point)
      resultType = OslType(BaseType::Point);
  }
  Value v;
  if (op == "+") v = b.create<AddOp>(ml, a, c);
  else if (op == "-") v = b.create<SubOp>(ml, a, c);
  else if (op == "*") v = b.create<MulOp>(ml, a, c);
  else if (op == "/") v = b.create<DivOp>(ml, a, c);
  else return invalid();
  return RValue::num(resultType, v);
}
