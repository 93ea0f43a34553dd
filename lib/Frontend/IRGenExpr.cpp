//===- IRGenExpr.cpp - Expressions, components and array elements ---------===//
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
    auto l = emitExpr(*e.args[0], operandExpected);
    if (!l)
      return std::nullopt;
    auto r = emitExpr(*e.args[1], operandExpected);
    if (!r)
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
  // Negation; fold literals so `-1` stays a constant.
  if (auto c = v->value.getDefiningOp<arith::ConstantOp>()) {
    if (auto ia = dyn_cast<IntegerAttr>(c.getValue()))
      return RValue::num(v->type, constInt(int32_t(0u - uint32_t(ia.getInt())), e.loc));
    if (auto fa = dyn_cast<FloatAttr>(c.getValue()))
      return RValue::num(v->type, constFloat(-float(fa.getValueAsDouble()), e.loc));
  }
  return RValue::num(v->type, b.create<NegOp>(loc(e.loc), v->value));
}

std::optional<RValue> IRGen::emitLogical(const Expr &e) {
  bool isAnd = e.name == "&&";
  auto l = emitExpr(*e.args[0]);
  if (!l)
    return std::nullopt;
  auto lc = toBool(*l, e.args[0]->loc);
  if (!lc)
    return std::nullopt;
  OslType boolType(BaseType::Bool);
  if (hasSideEffects(*e.args[1])) {
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
  if (hasSideEffects(*e.args[1]) || hasSideEffects(*e.args[2])) {
    llvm::StringSet<> names;
    scanAssigned(*e.args[1], names);
    scanAssigned(*e.args[2], names);
    return emitIfRegion(
        *cb, e.loc, names, [&]() { return emitExpr(*e.args[1], expected); },
        [&]() { return emitExpr(*e.args[2], expected); }, true);
  }
  auto a = emitExpr(*e.args[1], expected);
  if (!a)
    return std::nullopt;
  auto bv = emitExpr(*e.args[2], expected);
  if (!bv)
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
  if (t && t->isStructLike() && !t->isArray()) {
    if (auto v = selectFields(*cb, *a, *bv, e.loc))
      return v;
    error(e.loc, "conditional expressions on struct '" + t->str() +
                     "' with string fields are not supported yet");
    return std::nullopt;
  }
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

//===----------------------------------------------------------------------===//
// Lvalues, components and array elements
//===----------------------------------------------------------------------===//

static int componentIndex(llvm::StringRef name) {
  if (name == "x" || name == "r") return 0;
  if (name == "y" || name == "g") return 1;
  if (name == "z" || name == "b") return 2;
  return -1;
}

std::optional<Access> IRGen::makeAccess(OslType baseType, const Expr &e,
                                        OslType &elemType) {
  Access a;
  a.loc = e.loc;
  if (e.kind == ExprKind::Member && baseType.isStructLike()) {
    if (baseType.isArray()) {
      error(e.loc, "index the array of '" + baseType.structDecl->name +
                       "' before selecting field '" + e.name + "'");
      return std::nullopt;
    }
    a.field = baseType.structDecl->fieldIndex(e.name);
    if (a.field < 0) {
      error(e.loc, "struct '" + baseType.structDecl->name + "' has no field '" + e.name +
                       "'");
      return std::nullopt;
    }
    elemType = fieldType(baseType, a.field);
    return a;
  }
  if (e.kind == ExprKind::Member) {
    if (!baseType.isTriple()) {
      error(e.loc, "type '" + baseType.str() + "' has no component '" + e.name + "'");
      return std::nullopt;
    }
    int c = componentIndex(e.name);
    if (c < 0) {
      error(e.loc, "'" + e.name + "' is not a component of '" + baseType.str() +
                       "' (use x, y, z or r, g, b)");
      return std::nullopt;
    }
    a.component = true;
    a.length = 3;
    a.constIndex = c;
    elemType = OslType(BaseType::Float);
    return a;
  }
  // Index.
  if (baseType.isMatrix()) {
    // M[i] is a row (four floats) only as the base of M[i][j].
    if (rowAccessOK != &e) {
      error(e.loc, "a matrix element needs two indices, as in M[row][column]");
      return std::nullopt;
    }
    a.length = 4;
    elemType = OslType(BaseType::Float, 4);
  } else if (baseType.isArray()) {
    a.length = baseType.arrayLen;
    elemType = baseType.element();
  } else if (baseType.isTriple()) {
    a.component = true;
    a.length = 3;
    elemType = OslType(BaseType::Float);
  } else {
    error(e.loc, "cannot index a value of type '" + baseType.str() + "'");
    return std::nullopt;
  }
  auto idx = emitExpr(*e.args[1]);
  if (!idx)
    return std::nullopt;
  if (idx->type.isBool())
    idx = RValue::num(OslType(BaseType::Int), convert(idx->value, b.getI32Type(), e.loc));
  if (!idx->type.isInt()) {
    error(e.args[1]->begin, "index must be an int, got '" + idx->type.str() + "'");
    return std::nullopt;
  }
  a.index = idx->value;
  if (auto k = getConstInt(idx->value)) {
    if (*k < 0 || *k >= a.length) {
      // OSL reports an index out of range where the point runs and clamps it.
      reportAtRunTime(indexRangeMessage(e, std::to_string(*k), a.length), e.loc);
      a.constIndex = std::clamp<int64_t>(*k, 0, a.length - 1);
      a.index = constInt(int(a.constIndex), e.loc);
    } else {
      a.constIndex = *k;
    }
  } else if (!baseType.isMatrix()) {
    // Checked per point, as OSL's range checking does; the access clamps.
    Value below = b.create<CmpOp>(loc(e.loc), "lt", a.index, constInt(0, e.loc));
    Value above = b.create<CmpOp>(loc(e.loc), "ge", a.index, constInt(a.length, e.loc));
    Value outside = b.create<OrOp>(loc(e.loc), below, above);
    Value index = a.index;
    auto reported = emitIfRegion(
        outside, e.loc, {},
        [&]() -> std::optional<RValue> {
          b.create<PrintOp>(loc(e.loc), "renderer_error", "si",
                            ValueRange{stringHandle(RValue::string(
                                                        indexRangeMessage(e, "%d", a.length)),
                                                    e.loc),
                                       index},
                            Value());
          return RValue::voidValue();
        },
        []() -> std::optional<RValue> { return RValue::voidValue(); }, /*wantValue=*/false);
    if (!reported)
      return std::nullopt;
  }
  return a;
}

std::string IRGen::indexRangeMessage(const Expr &e, const std::string &index, int length) {
  // OSL's words, with testshade's names for the group and the layer.
  std::string name = rootName(*e.args[0]).str();
  return "Index [" + index + "] out of range " + name + "[0.." + std::to_string(length - 1) +
         "]: " + fileLine(e.loc) + " (group " + groupName() + ", layer " +
         std::to_string(options.layerIndex) + " " + layerName() + ", shader " + shader + ")";
}

Value IRGen::selectsElement(Value index, int k, int n, SrcLoc l) {
  if (n == 1)
    return constBool(true, l);
  Location ml = loc(l);
  if (k == 0)
    return b.create<CmpOp>(ml, "le", index, constInt(0, l));
  if (k == n - 1)
    return b.create<CmpOp>(ml, "ge", index, constInt(n - 1, l));
  return b.create<CmpOp>(ml, "eq", index, constInt(k, l));
}

/// Element j of an array or component j of a triple.
RValue IRGen::elementAt(const RValue &cur, const Access &a, int j, SrcLoc l) {
  if (!a.component && cur.type.base == BaseType::Matrix) { // 16 values per matrix
    RValue m;
    m.type = cur.type.element();
    m.elems.assign(cur.elems.begin() + 16 * j, cur.elems.begin() + 16 * j + 16);
    return m;
  }
  if (!a.component)
    return RValue::num(cur.type.element(), cur.elems[j]);
  Value v = cur.value;
  Type ft = withUniformity(b.getF32Type(), isVarying(v.getType()));
  return RValue::num(OslType(BaseType::Float),
                     b.create<ExtractOp>(loc(l), ft, v, b.getI64IntegerAttr(j)));
}

/// Row i of a matrix, as four floats.
static RValue matrixRow(const RValue &m, int i) {
  RValue row;
  row.type = OslType(BaseType::Float, 4);
  row.elems.assign(m.elems.begin() + 4 * i, m.elems.begin() + 4 * i + 4);
  return row;
}

RValue IRGen::readAccess(const RValue &cur, const Access &a, SrcLoc l) {
  if (a.field >= 0)
    return cur.fields[a.field];
  if (cur.type.isMatrix()) {
    if (a.constIndex >= 0)
      return matrixRow(cur, int(a.constIndex));
    // Clamped index: per column, a chain of selects from the last row up.
    RValue row = matrixRow(cur, 3);
    for (int k = 2; k >= 0; --k) {
      Value c = b.create<CmpOp>(loc(l), "le", a.index, constInt(k, l));
      for (int j = 0; j < 4; ++j)
        row.elems[j] = b.create<SelectOp>(loc(l), c, cur.elems[4 * k + j], row.elems[j]);
    }
    return row;
  }
  if (cur.type.isArray() && cur.type.base == BaseType::String) {
    if (a.constIndex >= 0)
      return cur.fields[a.constIndex];
    Value last = constInt(a.length - 1, l);
    Value index = b.create<ClampOp>(loc(l), a.index, constInt(0, l), last);
    return stringChoice(cur.fields, index, l);
  }
  if (cur.type.isStructLike()) {
    // Element of an array of structs: that element of every field's array.
    RValue r;
    r.type = cur.type.element();
    for (const RValue &f : cur.fields)
      r.fields.push_back(readAccess(f, a, l));
    return r;
  }
  if (a.constIndex >= 0)
    return elementAt(cur, a, int(a.constIndex), l);
  // Clamped index: a chain of selects from the last element down.
  RValue acc = elementAt(cur, a, a.length - 1, l);
  for (int k = a.length - 2; k >= 0; --k) {
    RValue ek = elementAt(cur, a, k, l);
    Value c = b.create<CmpOp>(loc(l), "le", a.index, constInt(k, l));
    if (acc.type.isMatrix())
      for (size_t j = 0; j < acc.elems.size(); ++j)
        acc.elems[j] = b.create<SelectOp>(loc(l), c, ek.elems[j], acc.elems[j]);
    else
      acc.value = b.create<SelectOp>(loc(l), c, ek.value, acc.value);
  }
  return acc;
}

RValue IRGen::updatePath(const RValue &cur, const std::vector<Access> &path, size_t k,
                         const RValue &newValue, SrcLoc l) {
  if (k == path.size())
    return newValue;
  const Access &a = path[k];
  if (cur.type.isArray() && cur.type.base == BaseType::String) {
    RValue res = cur;
    if (a.constIndex >= 0)
      res.fields[a.constIndex] = newValue; // a varying index is rejected in storeLValue
    return res;
  }
  if (a.field >= 0) {
    RValue res = cur;
    res.fields[a.field] = updatePath(cur.fields[a.field], path, k + 1, newValue, l);
    return res;
  }
  if (cur.type.isStructLike()) {
    // An element of an array of structs: the same element of the field
    // arrays that the rest of the path reaches.
    RValue res = cur;
    if (k + 1 == path.size()) {
      for (size_t j = 0; j < cur.fields.size(); ++j)
        res.fields[j] = updatePath(cur.fields[j], {a}, 0, newValue.fields[j], l);
      return res;
    }
    int f = path[k + 1].field; // the element is a struct: a field comes next
    std::vector<Access> rest = {a};
    rest.insert(rest.end(), path.begin() + k + 2, path.end());
    res.fields[f] = updatePath(cur.fields[f], rest, 0, newValue, l);
    return res;
  }
  if (cur.type.isMatrix()) {
    RValue res = cur;
    for (int i = 0; i < 4; ++i) {
      if (a.constIndex >= 0 && a.constIndex != i)
        continue;
      RValue old = matrixRow(cur, i);
      RValue updated = updatePath(old, path, k + 1, newValue, l);
      Value sel = a.constIndex >= 0 ? Value() : selectsElement(a.index, i, 4, l);
      for (int j = 0; j < 4; ++j)
        res.elems[4 * i + j] =
            sel ? select(sel, updated.elems[j], old.elems[j], l) : updated.elems[j];
    }
    return res;
  }
  Location ml = loc(l);
  auto insertComponent = [&](Value f, Value vec, int j) -> Value {
    bool varying = isVarying(f.getType()) || isVarying(vec.getType());
    Type t = withUniformity(VectorType::get({3}, b.getF32Type()), varying);
    return b.create<InsertOp>(ml, t, f, vec, b.getI64IntegerAttr(j));
  };
  RValue res = cur;
  if (cur.type.base == BaseType::Matrix && !a.component) {
    // An element of an array of matrices: its 16 values, each selected
    // where the index is not a constant.
    for (int j = 0; j < a.length; ++j) {
      if (a.constIndex >= 0 && a.constIndex != j)
        continue;
      RValue old = elementAt(cur, a, j, l);
      RValue updated = updatePath(old, path, k + 1, newValue, l);
      Value sel = a.constIndex >= 0 ? Value() : selectsElement(a.index, j, a.length, l);
      for (int e = 0; e < 16; ++e)
        res.elems[16 * j + e] =
            sel ? select(sel, updated.elems[e], old.elems[e], l) : updated.elems[e];
    }
    return res;
  }
  if (a.constIndex >= 0) {
    int j = int(a.constIndex);
    RValue updated = updatePath(elementAt(cur, a, j, l), path, k + 1, newValue, l);
    if (a.component)
      res.value = insertComponent(updated.value, cur.value, j);
    else
      res.elems[j] = updated.value;
    return res;
  }
  for (int j = 0; j < a.length; ++j) {
    RValue old = elementAt(cur, a, j, l);
    RValue updated = updatePath(old, path, k + 1, newValue, l);
    Value sel = b.create<SelectOp>(ml, selectsElement(a.index, j, a.length, l),
                                   updated.value, old.value);
    if (a.component)
      res.value = insertComponent(sel, res.value, j);
    else
      res.elems[j] = sel;
  }
  return res;
}

std::optional<LValue> IRGen::emitLValue(const Expr &e) {
  if (e.kind == ExprKind::Ident) {
    Var *v = lookupVar(e.name);
    if (!v) {
      if (lookupFloatConstant(e.name)) {
        error(e.loc, "cannot assign to the constant '" + e.name + "'");
        return std::nullopt;
      }
      error(e.loc, "unknown identifier '" + e.name + "'");
      return std::nullopt;
    }
    LValue lv;
    lv.var = v;
    lv.type = v->type;
    return lv;
  }
  if (e.kind != ExprKind::Index && e.kind != ExprKind::Member) {
    error(e.loc, "expression is not assignable");
    return std::nullopt;
  }
  const Expr *savedRowAccess = rowAccessOK;
  rowAccessOK = e.kind == ExprKind::Index ? e.args[0].get() : nullptr;
  auto base = emitLValue(*e.args[0]);
  rowAccessOK = savedRowAccess;
  if (!base)
    return std::nullopt;
  OslType elemType;
  auto a = makeAccess(base->type, e, elemType);
  if (!a)
    return std::nullopt;
  base->path.push_back(*a);
  base->type = elemType;
  return base;
}

RValue IRGen::loadLValue(const LValue &lv, SrcLoc l) {
  RValue cur = readVar(lv.var, l);
  for (const Access &a : lv.path)
    cur = readAccess(cur, a, l);
  return cur;
}

bool IRGen::storeLValue(const LValue &lv, RValue v, SrcLoc l) {
  if (lv.var->type.isArray() && lv.var->type.base == BaseType::String && !lv.path.empty() &&
      lv.path[0].constIndex < 0) {
    // An element chosen per point: every element becomes a handle, and
    // each takes the new one where the index picks it.
    const Access &a = lv.path[0];
    readVar(lv.var, l);
    materializeStrings(lv.var, l);
    Value handle = stringHandle(v, l);
    for (int j = 0; j < a.length; ++j) {
      RValue &f = lv.var->val.fields[j];
      f = RValue::runtimeString(
          select(selectsElement(a.index, j, a.length, l), handle, f.value, l));
    }
    return true;
  }
  if (lv.path.empty()) {
    v.type = lv.var->type;
    lv.var->val = std::move(v);
    return true;
  }
  RValue cur = readVar(lv.var, l);
  RValue updated = updatePath(cur, lv.path, 0, v, l);
  updated.type = lv.var->type;
  lv.var->val = std::move(updated);
  return true;
}

std::optional<RValue> IRGen::emitIndexOrMember(const Expr &e) {
  const Expr *savedRowAccess = rowAccessOK;
  rowAccessOK = e.kind == ExprKind::Index ? e.args[0].get() : nullptr;
  auto base = emitExpr(*e.args[0]);
  rowAccessOK = savedRowAccess;
  if (!base)
    return std::nullopt;
  OslType elemType;
  auto a = makeAccess(base->type, e, elemType);
  if (!a)
    return std::nullopt;
  return readAccess(*base, *a, e.loc);
}

std::optional<RValue> IRGen::coerceForAssignment(RValue v, OslType to, SrcLoc l,
                                                 const llvm::Twine &context) {
  if (to.isInt() && v.type.isFloat())
    return cast(v, to, l);
  return coerce(v, to, l, context);
}

bool IRGen::checkWritable(const LValue &lv, SrcLoc l, const llvm::Twine &how) {
  if (!lv.var->readOnly)
    return true;
  lv.var->writtenThrough = true;
  return diags.warning(l, "cannot write to non-output parameter \"" + lv.var->name + "\"" +
                              how.str());
}

std::optional<RValue> IRGen::emitAssign(const Expr &e) {
  auto lv = emitLValue(*e.args[0]);
  if (!lv || !checkWritable(*lv, e.loc))
    return std::nullopt;
  std::string target = rootName(*e.args[0]).str();
  std::optional<RValue> value;
  if (e.name == "=") {
    value = emitExpr(*e.args[1], &lv->type);
    if (!value)
      return std::nullopt;
  } else {
    RValue cur = loadLValue(*lv, e.loc);
    bool arithmetic = e.name == "+=" || e.name == "-=" || e.name == "*=" || e.name == "/=";
    auto rhs = emitExpr(*e.args[1], arithmetic ? &lv->type : nullptr);
    if (!rhs)
      return std::nullopt;
    llvm::StringRef op = llvm::StringRef(e.name).drop_back();
    if (!tryOverloadedOperator(op, e, {cur, *rhs}, value))
      value = emitBinaryOp(op, cur, *rhs, e.loc);
    if (!value)
      return std::nullopt;
  }
  if (lv->type.isArray() && !value->type.isArray()) {
    error(e.loc, "cannot assign '" + value->type.str() + "' to array '" + target +
                     "' of type '" + lv->type.str() + "'");
    return std::nullopt;
  }
  auto c = coerceForAssignment(*value, lv->type, e.args[1]->begin,
                               "in assignment to '" + target + "'");
  if (!c)
    return std::nullopt;
  storeLValue(*lv, *c, e.loc);
  return c;
}

std::optional<RValue> IRGen::emitIncDec(const Expr &e) {
  auto lv = emitLValue(*e.args[0]);
  if (!lv || !checkWritable(*lv, e.loc))
    return std::nullopt;
  if (!lv->type.isInt() && !lv->type.isFloat()) {
    error(e.loc, "operator '" + e.name + "' needs an int or float, got '" +
                     lv->type.str() + "'");
    return std::nullopt;
  }
  RValue cur = loadLValue(*lv, e.loc);
  Value one = lv->type.isInt() ? constInt(1, e.loc) : constFloat(1, e.loc);
  Value nv = e.name == "++" ? b.create<AddOp>(loc(e.loc), cur.value, one).getResult()
                            : b.create<SubOp>(loc(e.loc), cur.value, one).getResult();
  RValue next = RValue::num(lv->type, nv);
  storeLValue(*lv, next, e.loc);
  return e.prefix ? next : cur;
}
