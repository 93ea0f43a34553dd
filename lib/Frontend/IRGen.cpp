//===- IRGen.cpp - Syntax tree to the osl dialect ------------------------------===//
#include "IRGen.h"

#include "OslRuntime/GlobalsLayout.h"

#include "mlir/Dialect/Arith/IR/Arith.h"
#include "mlir/IR/BuiltinAttributes.h"
#include "llvm/ADT/STLExtras.h"
#include "llvm/ADT/StringExtras.h"

#include <cmath>

using namespace osl::frontend;
using namespace mlir;
using namespace mlir::osl;

namespace {
constexpr unsigned kMaxInlineDepth = 64;
constexpr unsigned kMaxExprDepth = 1000;

/// The variable an lvalue-shaped expression designates, or "".
llvm::StringRef rootName(const Expr &e) {
  const Expr *cur = &e;
  while (cur->kind == ExprKind::Index || cur->kind == ExprKind::Member)
    cur = cur->args[0].get();
  return cur->kind == ExprKind::Ident ? llvm::StringRef(cur->name) : "";
}

bool isLValueShaped(const Expr &e) {
  return e.kind == ExprKind::Ident || e.kind == ExprKind::Index ||
         e.kind == ExprKind::Member;
}

/// Does every path through `s` end in a return?
bool alwaysReturns(const Stmt &s) {
  switch (s.kind) {
  case StmtKind::Return: return true;
  case StmtKind::Block: return !s.body.empty() && alwaysReturns(*s.body.back());
  case StmtKind::If:
    return s.elseStmt && alwaysReturns(*s.thenStmt) && alwaysReturns(*s.elseStmt);
  default: return false;
  }
}

struct FloatConstant {
  const char *name;
  double value;
};
const FloatConstant kFloatConstants[] = {
    {"M_PI", 3.14159265358979323846},   {"M_PI_2", 1.57079632679489661923},
    {"M_PI_4", 0.78539816339744830962}, {"M_2_PI", 0.63661977236758134308},
    {"M_2PI", 6.28318530717958647692},  {"M_4PI", 12.56637061435917295384},
    {"M_2_SQRTPI", 1.12837916709551257390}, {"M_E", 2.71828182845904523536},
    {"M_LN2", 0.69314718055994530942},  {"M_LN10", 2.30258509299404568402},
    {"M_LOG2E", 1.44269504088896340736}, {"M_LOG10E", 0.43429448190325182765},
    {"M_SQRT2", 1.41421356237309504880}, {"M_SQRT1_2", 0.70710678118654752440},
};

struct GlobalDecl {
  const char *name;
  BaseType type;
};
const GlobalDecl kGlobals[] = {
    {"P", BaseType::Point},      {"I", BaseType::Vector},    {"N", BaseType::Normal},
    {"Ng", BaseType::Normal},    {"dPdu", BaseType::Vector}, {"dPdv", BaseType::Vector},
    {"dPdz", BaseType::Vector},  {"dPdtime", BaseType::Vector}, {"Ps", BaseType::Point},
    {"u", BaseType::Float},      {"v", BaseType::Float},     {"time", BaseType::Float},
    {"dtime", BaseType::Float},
};

} // namespace

IRGen::IRGen(MLIRContext &ctx, Diagnostics &diags,
             llvm::ArrayRef<ParamOverride> overrides)
    : ctx(ctx), diags(diags), overrides(overrides), b(&ctx) {}

Location IRGen::loc(SrcLoc l) {
  return FileLineColLoc::get(&ctx, diags.getFilename(), l.line, l.col);
}

//===----------------------------------------------------------------------===//
// Constants and conversions
//===----------------------------------------------------------------------===//

Value IRGen::constInt(int32_t v, SrcLoc l) {
  return b.create<arith::ConstantOp>(loc(l), b.getI32IntegerAttr(v));
}
Value IRGen::constFloat(float v, SrcLoc l) {
  return b.create<arith::ConstantOp>(loc(l), b.getF32FloatAttr(v));
}
Value IRGen::constBool(bool v, SrcLoc l) {
  return b.create<arith::ConstantOp>(loc(l), b.getBoolAttr(v));
}
Value IRGen::constTriple(float x, float y, float z, SrcLoc l) {
  auto type = VectorType::get({3}, b.getF32Type());
  auto attr = DenseElementsAttr::get(type, llvm::ArrayRef<float>{x, y, z});
  return b.create<arith::ConstantOp>(loc(l), attr);
}

RValue IRGen::zeroValue(OslType t, SrcLoc l) {
  if (t.isString())
    return RValue::string("");
  if (t.isArray()) {
    RValue r;
    r.type = t;
    for (int i = 0; i < t.arrayLen; ++i)
      r.elems.push_back(zeroValue(t.element(), l).value);
    return r;
  }
  if (t.isTriple())
    return RValue::num(t, constTriple(0, 0, 0, l));
  if (t.isFloat())
    return RValue::num(t, constFloat(0, l));
  if (t.isBool())
    return RValue::num(t, constBool(false, l));
  return RValue::num(t, constInt(0, l));
}

std::optional<int64_t> IRGen::getConstInt(Value v) {
  if (!v)
    return std::nullopt;
  if (auto c = v.getDefiningOp<arith::ConstantOp>())
    if (auto ia = dyn_cast<IntegerAttr>(c.getValue()))
      if (ia.getType().isInteger(32))
        return ia.getInt();
  return std::nullopt;
}

std::optional<bool> IRGen::getConstBool(Value v) {
  if (!v)
    return std::nullopt;
  if (auto c = v.getDefiningOp<arith::ConstantOp>())
    if (auto ia = dyn_cast<IntegerAttr>(c.getValue()))
      if (ia.getType().isInteger(1))
        return !ia.getValue().isZero();
  return std::nullopt;
}

Value IRGen::convert(Value v, Type toBase, SrcLoc l) {
  Type from = getUniformType(v.getType());
  if (from == toBase)
    return v;
  // Fold conversions of constants (literals are the common case).
  if (auto c = v.getDefiningOp<arith::ConstantOp>()) {
    std::optional<double> num;
    if (auto ia = dyn_cast<IntegerAttr>(c.getValue()))
      num = ia.getType().isInteger(1) ? double(!ia.getValue().isZero())
                                      : double(ia.getInt());
    else if (auto fa = dyn_cast<FloatAttr>(c.getValue()))
      num = fa.getValueAsDouble();
    if (num) {
      double d = *num;
      if (toBase.isF32())
        return constFloat(float(d), l);
      if (toBase.isInteger(1))
        return constBool(d != 0, l);
      if (toBase.isInteger(32)) {
        double t = std::trunc(d);
        if (!(t >= -2147483648.0 && t <= 2147483647.0))
          t = 0; // out of range: avoid UB; OSL leaves this undefined
        return constInt(int32_t(t), l);
      }
      if (isTriple(toBase))
        return constTriple(float(d), float(d), float(d), l);
    }
  }
  return b.create<ConvertOp>(loc(l), withUniformity(toBase, isVarying(v.getType())), v);
}

int IRGen::conversionCost(OslType from, OslType to) {
  if (from.isArray() || to.isArray()) {
    if (!from.isArray() || !to.isArray())
      return -1;
    bool sameBase = from.base == to.base ||
                    (from.element().isTriple() && to.element().isTriple());
    if (!sameBase || (to.arrayLen != 0 && to.arrayLen != from.arrayLen))
      return -1;
    return from.base == to.base ? 0 : 1;
  }
  if (from == to)
    return 0;
  if (from.isString() || to.isString() || from.isVoid() || to.isVoid())
    return -1;
  if (!from.isNumeric() || !to.isNumeric())
    return -1;
  if (to.isBool())
    return -1;
  if (to.isInt())
    return from.isBool() ? 0 : -1;
  if (to.isFloat())
    return from.isInt() || from.isBool() ? 1 : -1;
  // to is a triple
  if (from.isTriple())
    return 1;
  if (from.isFloat())
    return 2;
  return 3;
}

std::optional<RValue> IRGen::coerce(RValue v, OslType to, SrcLoc l,
                                    const llvm::Twine &context) {
  auto fail = [&]() -> std::optional<RValue> {
    std::string ctxText = context.str();
    error(l, "cannot convert '" + v.type.str() + "' to '" + to.str() + "'" +
                 (ctxText.empty() ? "" : " " + ctxText));
    return std::nullopt;
  };
  if (conversionCost(v.type, to) < 0)
    return fail();
  if (to.isArray()) {
    RValue r;
    r.type = v.type;
    r.type.base = to.base;
    r.elems = v.elems;
    return r;
  }
  if (to.isString()) {
    v.type = to;
    return v;
  }
  Value value = convert(v.value, irType(b, to), l);
  return RValue::num(to, value);
}

std::optional<RValue> IRGen::cast(RValue v, OslType to, SrcLoc l) {
  if (to.isInt() && v.type.isFloat())
    return RValue::num(to, convert(v.value, b.getI32Type(), l));
  if (v.type.isTriple() && !to.isTriple()) {
    error(l, "cannot cast '" + v.type.str() + "' to '" + to.str() + "'");
    return std::nullopt;
  }
  return coerce(std::move(v), to, l, "in cast");
}

std::optional<Value> IRGen::toBool(const RValue &v, SrcLoc l) {
  if (v.type.isBool())
    return v.value;
  if (!v.type.isNumeric()) {
    error(l, "a value of type '" + v.type.str() + "' cannot be used as a condition");
    return std::nullopt;
  }
  Value zero;
  if (v.type.isInt())
    zero = constInt(0, l);
  else if (v.type.isFloat())
    zero = constFloat(0, l);
  else
    zero = constTriple(0, 0, 0, l);
  return b.create<CmpOp>(loc(l), "ne", v.value, zero).getResult();
}

//===----------------------------------------------------------------------===//
// Scopes and variables
//===----------------------------------------------------------------------===//

Scope *IRGen::newScope(Scope *parent) {
  scopes.emplace_back();
  scopes.back().parent = parent;
  return &scopes.back();
}

Var *IRGen::declareVar(Scope *scope, const std::string &name, OslType type, SrcLoc l,
                       RValue init) {
  if (scope->vars.count(name)) {
    Var *old = scope->vars[name];
    error(l, "redefinition of '" + name + "' (first declared at line " +
                 llvm::Twine(old->loc.line) + ")");
    return nullptr;
  }
  vars.emplace_back();
  Var *v = &vars.back();
  v->name = name;
  v->type = type;
  v->loc = l;
  v->id = nextVarId++;
  v->val = std::move(init);
  v->val.type = type;
  scope->vars[name] = v;
  return v;
}

Var *IRGen::lookupVar(llvm::StringRef name) {
  for (Scope *s = current; s; s = s->parent) {
    auto it = s->vars.find(name);
    if (it != s->vars.end())
      return it->second;
  }
  return nullptr;
}

std::vector<FunctionRef> IRGen::lookupFunctions(llvm::StringRef name) {
  std::vector<FunctionRef> result;
  for (Scope *s = current; s; s = s->parent) {
    auto it = s->funcs.find(name);
    if (it != s->funcs.end())
      result.insert(result.end(), it->second.begin(), it->second.end());
  }
  return result;
}

Value IRGen::getGlobal(llvm::StringRef name, Type base, SrcLoc l) {
  auto it = globalValues.find(name);
  if (it != globalValues.end())
    return it->second;
  OpBuilder::InsertionGuard guard(b);
  if (lastGlobal)
    b.setInsertionPointAfter(lastGlobal);
  else
    b.setInsertionPointToStart(entryBlock);
  auto op = b.create<GlobalOp>(loc(l), VaryingType::get(base), name);
  lastGlobal = op;
  globalValues[name] = op.getResult();
  return op.getResult();
}

RValue IRGen::readVar(Var *v, SrcLoc l) {
  if (v->isGlobal && !v->val.value)
    v->val = RValue::num(v->type, getGlobal(v->name, irType(b, v->type), l));
  return v->val;
}

//===----------------------------------------------------------------------===//
// Program, shader and parameters
//===----------------------------------------------------------------------===//

void IRGen::collectFunctions(const Stmt &s) {
  if (s.kind == StmtKind::FuncDef) {
    allFunctions[s.func->name].push_back(s.func.get());
    collectFunctions(*s.func->body);
    return;
  }
  for (const StmtPtr &c : s.body)
    collectFunctions(*c);
  for (const Stmt *c : {s.init.get(), s.thenStmt.get(), s.elseStmt.get()})
    if (c)
      collectFunctions(*c);
}

OwningOpRef<ModuleOp> IRGen::emitProgram(const Program &program) {
  const ShaderDecl &shader = *program.shader;
  OwningOpRef<ModuleOp> module = ModuleOp::create(loc(shader.loc));
  root = newScope(nullptr);
  current = root;
  for (const GlobalDecl &g : kGlobals) {
    Var *v = declareVar(root, g.name, OslType(g.type), SrcLoc(), RValue());
    v->isGlobal = true;
  }
  for (const auto &fn : program.functions) {
    root->funcs[fn->name].push_back({fn.get(), root});
    allFunctions[fn->name].push_back(fn.get());
    collectFunctions(*fn->body);
  }
  collectFunctions(*shader.body);

  b.setInsertionPointToEnd(module->getBody());
  auto func = b.create<func::FuncOp>(loc(shader.loc), shader.name,
                                     b.getFunctionType({}, {}));
  func->setAttr("osl.shader_type", b.getStringAttr(shader.shaderType));
  entryBlock = func.addEntryBlock();
  b.setInsertionPointToStart(entryBlock);
  if (!emitShader(shader, func))
    return nullptr;
  return module;
}

bool IRGen::emitShader(const ShaderDecl &shader, func::FuncOp func) {
  for (const ParamOverride &o : overrides) {
    bool found = llvm::any_of(shader.params,
                              [&](const Param &p) { return p.name == o.name; });
    if (!found)
      return error(shader.loc, "shader '" + shader.name + "' has no parameter '" +
                                   o.name + "'");
  }
  Scope *paramScope = newScope(root);
  current = paramScope;
  for (const Param &p : shader.params)
    if (!emitParam(p, paramScope))
      return false;

  current = newScope(paramScope);
  if (!emitStmtList(shader.body->body, 0, /*tail=*/true))
    return false;

  SrcLoc endLoc = shader.loc;
  current = paramScope;
  for (const Param &p : shader.params) {
    if (!p.isOutput)
      continue;
    Var *v = paramScope->vars[p.name];
    if (v->type.isString())
      continue; // strings are compile-time; nothing to write
    if (v->type.isArray()) {
      for (size_t i = 0; i < v->val.elems.size(); ++i) {
        auto out = b.create<OutputOp>(loc(p.loc), p.name, v->val.elems[i]);
        out->setAttr("osl.index", b.getI64IntegerAttr(int64_t(i)));
      }
      continue;
    }
    b.create<OutputOp>(loc(p.loc), p.name, v->val.value);
  }
  b.create<func::ReturnOp>(loc(endLoc));
  (void)func;
  return true;
}

std::optional<RValue> IRGen::overrideValue(const Param &p, const std::string &text) {
  OslType t = p.type;
  if (t.isString())
    return RValue::string(text);
  llvm::SmallVector<llvm::StringRef> parts;
  llvm::StringRef(text).split(parts, ',', -1, /*KeepEmpty=*/true);
  std::vector<double> nums;
  for (llvm::StringRef part : parts) {
    part = part.trim();
    double d;
    if (part.empty() || part.getAsDouble(d)) {
      error(p.loc, "invalid value '" + text + "' for parameter '" + p.name + "' of type '" +
                       t.str() + "'");
      return std::nullopt;
    }
    if (t.base == BaseType::Int && d != std::trunc(d)) {
      error(p.loc, "parameter '" + p.name + "' is an int; '" + part.str() +
                       "' is not an integer");
      return std::nullopt;
    }
    nums.push_back(d);
  }
  OslType elem = t.element();
  size_t per = elem.isTriple() ? 3 : 1;
  size_t count = t.isArray() ? size_t(t.arrayLen) : 1;
  auto makeElem = [&](size_t i, bool splat) -> Value {
    auto at = [&](size_t k) { return nums[splat ? i : i * per + k]; };
    if (elem.isTriple())
      return constTriple(float(at(0)), float(at(1)), float(at(2)), p.loc);
    if (elem.isFloat())
      return constFloat(float(at(0)), p.loc);
    return constInt(int32_t(at(0)), p.loc);
  };
  if (!t.isArray()) {
    if (nums.size() != 1 && nums.size() != per) {
      error(p.loc, "parameter '" + p.name + "' of type '" + t.str() + "' takes " +
                       (per == 3 ? "1 or 3 values" : "1 value") + ", got '" + text + "'");
      return std::nullopt;
    }
    return RValue::num(t, makeElem(0, nums.size() == 1 && per == 3 ? false : false) ?
                                  makeElem(0, false) : Value());
  }
  if (nums.size() != count * per) {
    error(p.loc, "parameter '" + p.name + "' of type '" + t.str() + "' takes " +
                     llvm::Twine(count * per) + " values, got '" + text + "'");
    return std::nullopt;
  }
  RValue r;
  r.type = t;
  for (size_t i = 0; i < count; ++i)
    r.elems.push_back(makeElem(i, false));
  return r;
}

bool IRGen::emitParam(const Param &p, Scope *scope) {
  OslType t = p.type;
  if (t.base == BaseType::Matrix || t.base == BaseType::Closure)
    return error(p.loc, "parameters of type '" + t.str() + "' are not supported yet");
  if (t.isVoid())
    return error(p.loc, "parameters cannot have type 'void'");
  if (t.isArray() && t.base == BaseType::String)
    return error(p.loc, "string array parameters are not supported yet");
  const ParamOverride *ov = nullptr;
  for (const ParamOverride &o : overrides)
    if (o.name == p.name)
      ov = &o;
  std::optional<RValue> init;
  if (ov) {
    if (t.arrayLen == 0) {
      // Length from the default's initializer list.
      if (p.init->kind == ExprKind::InitList)
        t.arrayLen = int(p.init->args.size());
    }
    Param sized;
    sized.type = t;
    sized.name = p.name;
    sized.loc = p.loc;
    init = overrideValue(sized, ov->value);
  } else {
    init = emitInitializer(*p.init, t, p.name, p.loc);
  }
  if (!init)
    return false;
  RValue val = *init;
  if (t.isArray()) {
    for (size_t i = 0; i < val.elems.size(); ++i) {
      Value d = val.elems[i];
      auto op = b.create<ParamOp>(loc(p.loc), d.getType(), p.name, d);
      op->setAttr("osl.index", b.getI64IntegerAttr(int64_t(i)));
      val.elems[i] = op.getResult();
    }
  } else if (!t.isString()) {
    Value d = val.value;
    val.value = b.create<ParamOp>(loc(p.loc), d.getType(), p.name, d).getResult();
  }
  Var *v = declareVar(scope, p.name, t, p.loc, val);
  if (!v)
    return false;
  v->isOutputParam = p.isOutput;
  return true;
}

std::optional<RValue> IRGen::emitInitializer(const Expr &init, OslType &type,
                                             llvm::StringRef name, SrcLoc l) {
  if (init.kind == ExprKind::InitList) {
    if (!type.isArray()) {
      error(init.loc, "initializer list for '" + name + "', which is not an array");
      return std::nullopt;
    }
    if (type.arrayLen == 0)
      type.arrayLen = int(init.args.size());
    if (type.arrayLen == 0) {
      error(init.loc, "array '" + name + "' cannot be empty");
      return std::nullopt;
    }
    if (int(init.args.size()) > type.arrayLen) {
      error(init.args[type.arrayLen]->loc,
            "too many initializers for '" + name + "' of type '" + type.str() + "'");
      return std::nullopt;
    }
    if (type.base == BaseType::String) {
      error(init.loc, "string arrays are not supported yet");
      return std::nullopt;
    }
    OslType elem = type.element();
    RValue r;
    r.type = type;
    for (int i = 0; i < type.arrayLen; ++i) {
      if (i < int(init.args.size())) {
        const Expr &e = *init.args[i];
        auto v = emitExpr(e, &elem);
        if (!v)
          return std::nullopt;
        auto c = coerce(*v, elem, e.loc, "in initializer of '" + name + "'");
        if (!c)
          return std::nullopt;
        r.elems.push_back(c->value);
      } else {
        r.elems.push_back(zeroValue(elem, l).value);
      }
    }
    return r;
  }
  auto v = emitExpr(init, &type);
  if (!v)
    return std::nullopt;
  if (type.arrayLen == 0 && v->type.isArray())
    type.arrayLen = v->type.arrayLen;
  return coerce(*v, type, init.loc, "in initialization of '" + name + "'");
}

//===----------------------------------------------------------------------===//
// Statements
//===----------------------------------------------------------------------===//

bool IRGen::emitStmtList(const std::vector<StmtPtr> &stmts, size_t from, bool tail) {
  for (size_t i = from; i < stmts.size(); ++i) {
    const Stmt &s = *stmts[i];
    bool last = i + 1 == stmts.size();
    // `if (c) { ...; return; } rest` == `if (c) { ... } else { rest }`.
    if (tail && !last && s.kind == StmtKind::If && alwaysReturns(*s.thenStmt)) {
      auto cond = emitExpr(*s.expr);
      if (!cond)
        return false;
      auto c = toBool(*cond, s.expr->loc);
      if (!c)
        return false;
      llvm::StringSet<> names;
      scanAssigned(*s.thenStmt, names);
      if (s.elseStmt)
        scanAssigned(*s.elseStmt, names);
      for (size_t k = i + 1; k < stmts.size(); ++k)
        scanAssigned(*stmts[k], names);
      auto r = emitIfRegion(
          *c, s.loc, names,
          [&]() -> std::optional<RValue> {
            if (!emitScoped(*s.thenStmt, true))
              return std::nullopt;
            return RValue::voidValue();
          },
          [&]() -> std::optional<RValue> {
            Scope *saved = current;
            current = newScope(current);
            bool ok = (!s.elseStmt || emitStmt(*s.elseStmt, false)) &&
                      emitStmtList(stmts, i + 1, true);
            current = saved;
            if (!ok)
              return std::nullopt;
            return RValue::voidValue();
          },
          /*wantValue=*/false);
      return r.has_value();
    }
    if (!emitStmt(s, tail && last))
      return false;
  }
  return true;
}

bool IRGen::emitScoped(const Stmt &s, bool tail) {
  Scope *saved = current;
  current = newScope(current);
  bool ok = emitStmt(s, tail);
  current = saved;
  return ok;
}

bool IRGen::emitStmt(const Stmt &s, bool tail) {
  switch (s.kind) {
  case StmtKind::Block:
    return emitScoped(s.body, tail);
  case StmtKind::Decl:
    return emitDecl(s);
  case StmtKind::ExprStmt:
    return emitExpr(*s.expr).has_value();
  case StmtKind::If:
    return emitIf(s, tail);
  case StmtKind::For:
  case StmtKind::While:
  case StmtKind::DoWhile:
    return emitLoop(s);
  case StmtKind::Break:
    return error(s.loc, "'break' is not supported yet");
  case StmtKind::Continue:
    return error(s.loc, "'continue' is not supported yet");
  case StmtKind::Return: {
    if (!tail)
      return error(s.loc, "'return' is not supported yet here (only where it ends "
                          "the function or shader)");
    if (inlineStack.empty()) {
      if (s.expr)
        return error(s.expr->loc, "a shader cannot return a value");
      return true;
    }
    InlineFrame &frame = inlineStack.back();
    const FunctionDecl &fn = *frame.fn;
    if (fn.returnType.isVoid()) {
      if (s.expr)
        return error(s.expr->loc, "void function '" + fn.name + "' cannot return a value");
      return true;
    }
    if (!s.expr)
      return error(s.loc, "function '" + fn.name + "' must return a value of type '" +
                              fn.returnType.str() + "'");
    auto v = emitExpr(*s.expr, &fn.returnType);
    if (!v)
      return false;
    auto c = coerce(*v, fn.returnType, s.expr->loc,
                    "in return from '" + fn.name + "'");
    if (!c)
      return false;
    frame.returnVar->val = *c;
    return true;
  }
  case StmtKind::FuncDef:
    current->funcs[s.func->name].push_back({s.func.get(), current});
    return true;
  case StmtKind::Empty:
    return true;
  }
  return true;
}

bool IRGen::emitScoped(const std::vector<StmtPtr> &stmts, bool tail) {
  Scope *saved = current;
  current = newScope(current);
  bool ok = emitStmtList(stmts, 0, tail);
  current = saved;
  return ok;
}

bool IRGen::emitDecl(const Stmt &s) {
  OslType base = s.declType;
  if (base.base == BaseType::Matrix || base.base == BaseType::Closure)
    return error(s.loc, "type '" + base.str() + "' is not supported yet");
  for (const Declarator &d : s.decls) {
    OslType t = base;
    t.arrayLen = d.arrayLen;
    if (t.isArray() && t.base == BaseType::String)
      return error(d.loc, "string arrays are not supported yet");
    RValue init;
    if (d.init) {
      auto v = emitInitializer(*d.init, t, d.name, d.loc);
      if (!v)
        return false;
      init = *v;
    } else {
      init = zeroValue(t, d.loc);
    }
    if (!declareVar(current, d.name, t, d.loc, init))
      return false;
  }
  return true;
}

bool IRGen::emitIf(const Stmt &s, bool tail) {
  auto cond = emitExpr(*s.expr);
  if (!cond)
    return false;
  auto c = toBool(*cond, s.expr->loc);
  if (!c)
    return false;
  llvm::StringSet<> names;
  scanAssigned(*s.thenStmt, names);
  if (s.elseStmt)
    scanAssigned(*s.elseStmt, names);
  auto r = emitIfRegion(
      *c, s.loc, names,
      [&]() -> std::optional<RValue> {
        if (!emitScoped(*s.thenStmt, tail))
          return std::nullopt;
        return RValue::voidValue();
      },
      [&]() -> std::optional<RValue> {
        if (s.elseStmt && !emitScoped(*s.elseStmt, tail))
          return std::nullopt;
        return RValue::voidValue();
      },
      /*wantValue=*/false);
  return r.has_value();
}

std::vector<Var *> IRGen::carriedVars(const llvm::StringSet<> &names) {
  std::vector<Var *> result;
  for (const auto &entry : names) {
    Var *v = lookupVar(entry.getKey());
    if (v && !v->type.isString())
      result.push_back(v);
  }
  llvm::sort(result, [](Var *a, Var *b) { return a->id < b->id; });
  return result;
}

std::vector<Value> IRGen::flatten(const std::vector<Var *> &vs, SrcLoc l) {
  std::vector<Value> out;
  for (Var *v : vs) {
    RValue r = readVar(v, l);
    if (v->type.isArray())
      out.insert(out.end(), r.elems.begin(), r.elems.end());
    else
      out.push_back(r.value);
  }
  return out;
}

void IRGen::unflatten(const std::vector<Var *> &vs, ValueRange values) {
  size_t k = 0;
  for (Var *v : vs) {
    if (v->type.isArray()) {
      for (Value &e : v->val.elems)
        e = values[k++];
    } else {
      v->val.value = values[k++];
    }
  }
}

/// String variables the region may assign, with their values before it.
std::vector<std::pair<Var *, std::string>>
IRGen::stringSnapshot(const llvm::StringSet<> &names) {
  std::vector<std::pair<Var *, std::string>> snap;
  for (const auto &entry : names)
    if (Var *v = lookupVar(entry.getKey()))
      if (v->type.isString())
        snap.push_back({v, v->val.str});
  return snap;
}

bool IRGen::checkStrings(const std::vector<std::pair<Var *, std::string>> &snap,
                         SrcLoc l, llvm::StringRef what) {
  for (auto &[v, s] : snap)
    if (v->val.str != s)
      return error(l, "string variable '" + v->name + "' is changed inside " + what +
                          "; strings are compile-time values and cannot depend on "
                          "control flow yet");
  return true;
}

std::optional<RValue>
IRGen::emitIfRegion(Value cond, SrcLoc l, const llvm::StringSet<> &assigned,
                    llvm::function_ref<std::optional<RValue>()> thenArm,
                    llvm::function_ref<std::optional<RValue>()> elseArm,
                    bool wantValue) {
  std::vector<Var *> carried = carriedVars(assigned);
  std::vector<Value> init = flatten(carried, l);
  auto strings = stringSnapshot(assigned);
  Location mloc = loc(l);

  auto tmp = b.create<IfOp>(mloc, TypeRange{}, cond);
  Block *thenBlock = b.createBlock(&tmp.getThenRegion());
  auto tv = thenArm();
  if (!tv)
    return std::nullopt;
  std::vector<Value> thenVals = flatten(carried, l);
  if (!checkStrings(strings, l, "'if'"))
    return std::nullopt;
  unflatten(carried, init);

  Block *elseBlock = b.createBlock(&tmp.getElseRegion());
  auto ev = elseArm();
  if (!ev)
    return std::nullopt;
  std::vector<Value> elseVals = flatten(carried, l);
  if (!checkStrings(strings, l, "'if'"))
    return std::nullopt;

  OslType resultType;
  if (wantValue) {
    auto t = unify(tv->type, ev->type);
    if (!t || !t->isNumeric()) {
      error(l, "incompatible types in conditional expression: '" + tv->type.str() +
                   "' and '" + ev->type.str() + "'");
      return std::nullopt;
    }
    resultType = *t;
    b.setInsertionPointToEnd(thenBlock);
    auto ct = coerce(*tv, resultType, l, "");
    b.setInsertionPointToEnd(elseBlock);
    auto ce = coerce(*ev, resultType, l, "");
    if (!ct || !ce)
      return std::nullopt;
    thenVals.push_back(ct->value);
    elseVals.push_back(ce->value);
  }
  b.setInsertionPointToEnd(thenBlock);
  b.create<YieldOp>(mloc, thenVals);
  b.setInsertionPointToEnd(elseBlock);
  b.create<YieldOp>(mloc, elseVals);

  std::vector<Type> types;
  for (size_t i = 0; i < thenVals.size(); ++i) {
    Type base = getUniformType(thenVals[i].getType());
    bool varying = isVarying(thenVals[i].getType()) || isVarying(elseVals[i].getType());
    types.push_back(withUniformity(base, varying));
  }
  b.setInsertionPoint(tmp);
  auto ifOp = b.create<IfOp>(mloc, types, cond);
  ifOp.getThenRegion().takeBody(tmp.getThenRegion());
  ifOp.getElseRegion().takeBody(tmp.getElseRegion());
  tmp.erase();
  b.setInsertionPointAfter(ifOp);
  unflatten(carried, ifOp.getResults().take_front(init.size()));
  if (!wantValue)
    return RValue::voidValue();
  return RValue::num(resultType, ifOp.getResults().back());
}

bool IRGen::emitLoop(const Stmt &s) {
  Scope *saved = current;
  current = newScope(current);
  bool ok = true;
  llvm::StringSet<> names;
  if (s.kind == StmtKind::For && s.init) {
    ok = emitStmt(*s.init, false);
    if (ok && s.init->kind == StmtKind::Decl)
      for (const Declarator &d : s.init->decls)
        names.insert(d.name);
  }
  if (ok && s.kind == StmtKind::DoWhile)
    ok = emitScoped(*s.thenStmt, false); // the first iteration, peeled
  if (ok) {
    if (s.expr)
      scanAssigned(*s.expr, names);
    if (s.step)
      scanAssigned(*s.step, names);
    scanAssigned(*s.thenStmt, names);
    ok = emitWhile(s.expr.get(), *s.thenStmt, s.step.get(), names, s.loc);
  }
  current = saved;
  return ok;
}

bool IRGen::emitWhile(const Expr *condExpr, const Stmt &body, const Expr *step,
                      const llvm::StringSet<> &names, SrcLoc l) {
  std::vector<Var *> carried = carriedVars(names);
  std::vector<Value> init = flatten(carried, l);
  auto strings = stringSnapshot(names);
  Location mloc = loc(l);
  std::vector<Type> types;
  std::vector<Location> locs;
  for (Value v : init) {
    types.push_back(v.getType());
    locs.push_back(mloc);
  }
  auto whileOp = b.create<WhileOp>(mloc, types, init);
  Block *before = b.createBlock(&whileOp.getBefore(), {}, types, locs);
  unflatten(carried, before->getArguments());
  Value cond;
  if (condExpr) {
    auto c = emitExpr(*condExpr);
    if (!c)
      return false;
    auto cb = toBool(*c, condExpr->loc);
    if (!cb)
      return false;
    cond = *cb;
  } else {
    cond = constBool(true, l);
  }
  b.create<ConditionOp>(mloc, cond, flatten(carried, l));

  Block *after = b.createBlock(&whileOp.getAfter(), {}, types, locs);
  unflatten(carried, after->getArguments());
  if (!emitScoped(body, false))
    return false;
  if (step && !emitExpr(*step))
    return false;
  b.create<YieldOp>(mloc, flatten(carried, l));
  if (!checkStrings(strings, l, "a loop"))
    return false;
  b.setInsertionPointAfter(whileOp);
  unflatten(carried, whileOp.getResults());
  return true;
}

//===----------------------------------------------------------------------===//
// Assignment scan
//===----------------------------------------------------------------------===//

void IRGen::scanAssigned(const Stmt &s, llvm::StringSet<> &names) {
  switch (s.kind) {
  case StmtKind::FuncDef:
    return; // scanned where it is called
  case StmtKind::Return:
    if (s.expr) {
      names.insert(kReturnVarName);
      scanAssigned(*s.expr, names);
    }
    return;
  case StmtKind::Decl:
    for (const Declarator &d : s.decls)
      if (d.init)
        scanAssigned(*d.init, names);
    return;
  default:
    break;
  }
  for (const StmtPtr &c : s.body)
    scanAssigned(*c, names);
  for (const Stmt *c : {s.init.get(), s.thenStmt.get(), s.elseStmt.get()})
    if (c)
      scanAssigned(*c, names);
  for (const Expr *e : {s.expr.get(), s.step.get()})
    if (e)
      scanAssigned(*e, names);
}

void IRGen::scanAssigned(const Expr &e, llvm::StringSet<> &names) {
  if (e.kind == ExprKind::Assign || e.kind == ExprKind::IncDec) {
    llvm::StringRef root = rootName(*e.args[0]);
    if (!root.empty())
      names.insert(root);
  }
  if (e.kind == ExprKind::Call && !e.isCtor) {
    auto it = allFunctions.find(e.name);
    if (it != allFunctions.end()) {
      for (const FunctionDecl *fn : it->second) {
        for (size_t k = 0; k < fn->params.size() && k < e.args.size(); ++k)
          if (fn->params[k].isOutput) {
            llvm::StringRef root = rootName(*e.args[k]);
            if (!root.empty())
              names.insert(root);
          }
        // What the function assigns besides its own locals (captured
        // variables of a nested function, globals), conservatively.
        if (scanVisited.insert(fn).second) {
          scanAssigned(*fn->body, names);
          scanVisited.erase(fn);
        }
      }
    }
  }
  for (const ExprPtr &a : e.args)
    scanAssigned(*a, names);
}

bool IRGen::hasSideEffects(const Expr &e) {
  if (e.kind == ExprKind::Assign || e.kind == ExprKind::IncDec)
    return true;
  if (e.kind == ExprKind::Call && !e.isCtor && allFunctions.count(e.name))
    return true;
  return llvm::any_of(e.args, [&](const ExprPtr &a) { return hasSideEffects(*a); });
}

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
    return emitUnary(e);
  case ExprKind::Binary: {
    if (e.name == "&&" || e.name == "||")
      return emitLogical(e);
    auto l = emitExpr(*e.args[0]);
    if (!l)
      return std::nullopt;
    auto r = emitExpr(*e.args[1]);
    if (!r)
      return std::nullopt;
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
    if (e.castType.base == BaseType::Matrix || e.castType.base == BaseType::Closure ||
        e.castType.isVoid()) {
      error(e.loc, "casts to '" + e.castType.str() + "' are not supported");
      return std::nullopt;
    }
    return cast(*v, e.castType, e.loc);
  }
  case ExprKind::InitList:
    error(e.loc, "initializer lists are only allowed in declarations");
    return std::nullopt;
  }
  return std::nullopt;
}

std::optional<RValue> IRGen::emitIdent(const Expr &e) {
  if (Var *v = lookupVar(e.name))
    return readVar(v, e.loc);
  for (const FloatConstant &c : kFloatConstants)
    if (e.name == c.name)
      return RValue::num(OslType(BaseType::Float), constFloat(float(c.value), e.loc));
  if (allFunctions.count(e.name) || isBuiltinName(e.name))
    error(e.loc, "'" + e.name + "' is a function; call it with '" + e.name + "(...)'");
  else
    error(e.loc, "unknown identifier '" + e.name + "'");
  return std::nullopt;
}

std::optional<RValue> IRGen::emitUnary(const Expr &e) {
  auto v = emitExpr(*e.args[0]);
  if (!v)
    return std::nullopt;
  const std::string &op = e.name;
  if (op == "!") {
    auto c = toBool(*v, e.args[0]->loc);
    if (!c)
      return std::nullopt;
    if (auto k = getConstBool(*c))
      return RValue::num(OslType(BaseType::Bool), constBool(!*k, e.loc));
    return RValue::num(OslType(BaseType::Bool), b.create<NotOp>(loc(e.loc), *c));
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
  if (a.isTriple() && b2.isTriple())
    return a;
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
    if (a->str == bv->str)
      return a;
    error(e.loc, "choosing between strings at run time is not supported yet "
                 "(strings are compile-time values)");
    return std::nullopt;
  }
  auto t = unify(a->type, bv->type);
  if (!t || !t->isNumeric()) {
    error(e.loc, "incompatible types in conditional expression: '" + a->type.str() +
                     "' and '" + bv->type.str() + "'");
    return std::nullopt;
  }
  auto ca = coerce(*a, *t, e.args[1]->loc, "");
  auto cbv = coerce(*bv, *t, e.args[2]->loc, "");
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
  Location ml = loc(sl);
  bool isEq = op == "==" || op == "!=";
  if (l.type.isString() || r.type.isString()) {
    if (isEq && l.type.isString() && r.type.isString())
      return RValue::num(OslType(BaseType::Bool),
                         constBool((l.str == r.str) == (op == "=="), sl));
    return invalid();
  }
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
    return RValue::num(OslType(BaseType::Bool), b.create<CmpOp>(ml, pred, a, c));
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
  if (baseType.isArray()) {
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
    error(e.args[1]->loc, "index must be an int, got '" + idx->type.str() + "'");
    return std::nullopt;
  }
  a.index = idx->value;
  if (auto k = getConstInt(idx->value)) {
    if (*k < 0 || *k >= a.length) {
      error(e.args[1]->loc, "index " + llvm::Twine(*k) + " is out of range for '" +
                                baseType.str() + "'");
      return std::nullopt;
    }
    a.constIndex = *k;
  }
  return a;
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
  if (!a.component)
    return RValue::num(cur.type.element(), cur.elems[j]);
  Value v = cur.value;
  Type ft = withUniformity(b.getF32Type(), isVarying(v.getType()));
  return RValue::num(OslType(BaseType::Float),
                     b.create<ExtractOp>(loc(l), ft, v, b.getI64IntegerAttr(j)));
}

RValue IRGen::readAccess(const RValue &cur, const Access &a, SrcLoc l) {
  if (a.constIndex >= 0)
    return elementAt(cur, a, int(a.constIndex), l);
  // Clamped index: a chain of selects from the last element down.
  RValue acc = elementAt(cur, a, a.length - 1, l);
  for (int k = a.length - 2; k >= 0; --k) {
    RValue ek = elementAt(cur, a, k, l);
    Value c = b.create<CmpOp>(loc(l), "le", a.index, constInt(k, l));
    acc.value = b.create<SelectOp>(loc(l), c, ek.value, acc.value);
  }
  return acc;
}

RValue IRGen::updatePath(const RValue &cur, const std::vector<Access> &path, size_t k,
                         const RValue &newValue, SrcLoc l) {
  if (k == path.size())
    return newValue;
  const Access &a = path[k];
  Location ml = loc(l);
  auto insertComponent = [&](Value f, Value vec, int j) -> Value {
    bool varying = isVarying(f.getType()) || isVarying(vec.getType());
    Type t = withUniformity(VectorType::get({3}, b.getF32Type()), varying);
    return b.create<InsertOp>(ml, t, f, vec, b.getI64IntegerAttr(j));
  };
  RValue res = cur;
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
      for (const FloatConstant &c : kFloatConstants)
        if (e.name == c.name) {
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
  auto base = emitLValue(*e.args[0]);
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
  auto base = emitExpr(*e.args[0]);
  if (!base)
    return std::nullopt;
  OslType elemType;
  auto a = makeAccess(base->type, e, elemType);
  if (!a)
    return std::nullopt;
  return readAccess(*base, *a, e.loc);
}

std::optional<RValue> IRGen::emitAssign(const Expr &e) {
  auto lv = emitLValue(*e.args[0]);
  if (!lv)
    return std::nullopt;
  std::string target = rootName(*e.args[0]).str();
  std::optional<RValue> value;
  if (e.name == "=") {
    value = emitExpr(*e.args[1], &lv->type);
    if (!value)
      return std::nullopt;
  } else {
    RValue cur = loadLValue(*lv, e.loc);
    auto rhs = emitExpr(*e.args[1]);
    if (!rhs)
      return std::nullopt;
    llvm::StringRef op = llvm::StringRef(e.name).drop_back();
    value = emitBinaryOp(op, cur, *rhs, e.loc);
    if (!value)
      return std::nullopt;
  }
  if (lv->type.isArray() && !value->type.isArray()) {
    error(e.loc, "cannot assign '" + value->type.str() + "' to array '" + target +
                     "' of type '" + lv->type.str() + "'");
    return std::nullopt;
  }
  auto c = coerce(*value, lv->type, e.loc, "in assignment to '" + target + "'");
  if (!c)
    return std::nullopt;
  storeLValue(*lv, *c, e.loc);
  return c;
}

std::optional<RValue> IRGen::emitIncDec(const Expr &e) {
  auto lv = emitLValue(*e.args[0]);
  if (!lv)
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

//===----------------------------------------------------------------------===//
// Calls
//===----------------------------------------------------------------------===//

static std::string signatureText(const FunctionDecl &fn) {
  std::string s = fn.returnType.str() + " " + fn.name + "(";
  for (size_t i = 0; i < fn.params.size(); ++i) {
    if (i)
      s += ", ";
    if (fn.params[i].isOutput)
      s += "output ";
    s += fn.params[i].type.str();
  }
  return s + ")";
}

std::optional<RValue> IRGen::emitCall(const Expr &e, const OslType *expected) {
  if (!e.isCtor) {
    std::vector<FunctionRef> cands = lookupFunctions(e.name);
    bool arityMatch = llvm::any_of(cands, [&](const FunctionRef &f) {
      return f.decl->params.size() == e.args.size();
    });
    if (!cands.empty() && (arityMatch || !isBuiltinName(e.name)))
      return emitUserCall(e, cands, expected);
  }
  bool known = true;
  auto r = emitBuiltinCall(*this, e, expected, known);
  if (!known) {
    if (allFunctions.count(e.name))
      error(e.loc, "function '" + e.name + "' is not visible here");
    else
      error(e.loc, "unknown function '" + e.name + "'");
    return std::nullopt;
  }
  return r;
}

std::optional<RValue> IRGen::emitUserCall(const Expr &e,
                                          const std::vector<FunctionRef> &cands,
                                          const OslType *expected) {
  size_t n = e.args.size();
  // Evaluate the arguments; output positions are kept as lvalues.
  std::vector<RValue> args(n);
  std::vector<std::optional<LValue>> lvalues(n);
  for (size_t k = 0; k < n; ++k) {
    const Expr &a = *e.args[k];
    const OslType *argExpected = nullptr;
    bool outputSomewhere = false;
    std::optional<OslType> agreed;
    bool agree = true;
    for (const FunctionRef &f : cands) {
      if (f.decl->params.size() != n)
        continue;
      const Param &p = f.decl->params[k];
      outputSomewhere |= p.isOutput;
      if (!agreed)
        agreed = p.type;
      else if (*agreed != p.type)
        agree = false;
    }
    if (agreed && agree)
      argExpected = &*agreed;
    if (outputSomewhere && isLValueShaped(a)) {
      lvalues[k] = emitLValue(a);
      if (!lvalues[k])
        return std::nullopt;
      args[k] = loadLValue(*lvalues[k], a.loc);
    } else {
      auto v = emitExpr(a, argExpected);
      if (!v)
        return std::nullopt;
      args[k] = *v;
    }
  }
  // Rank the candidates: total conversion cost, then the return type.
  const FunctionRef *best = nullptr;
  int bestCost = 0;
  for (const FunctionRef &f : cands) {
    const FunctionDecl &fn = *f.decl;
    if (fn.params.size() != n)
      continue;
    int cost = 0;
    bool ok = true;
    for (size_t k = 0; k < n && ok; ++k) {
      const Param &p = fn.params[k];
      int c = conversionCost(args[k].type, p.type);
      if (c < 0) {
        ok = false;
      } else if (p.isOutput) {
        OslType argT = lvalues[k] ? lvalues[k]->type : args[k].type;
        OslType paramT = p.type;
        if (paramT.arrayLen == 0)
          paramT.arrayLen = argT.arrayLen;
        ok = lvalues[k] && conversionCost(paramT, argT) >= 0;
      }
      cost += c;
    }
    if (!ok)
      continue;
    if (expected && !fn.returnType.isVoid() &&
        conversionCost(fn.returnType, *expected) != 0)
      cost += 1; // prefer the overload returning what the context wants
    if (!best || cost < bestCost) {
      best = &f;
      bestCost = cost;
    }
  }
  if (!best) {
    std::string argText;
    for (size_t k = 0; k < n; ++k)
      argText += (k ? ", " : "") + args[k].type.str();
    std::string candText;
    for (const FunctionRef &f : cands)
      candText += (candText.empty() ? "" : "; ") + signatureText(*f.decl);
    // Output arguments that are not variables get their own message.
    for (const FunctionRef &f : cands)
      if (f.decl->params.size() == n && cands.size() == 1)
        for (size_t k = 0; k < n; ++k)
          if (f.decl->params[k].isOutput && !lvalues[k] &&
              conversionCost(args[k].type, f.decl->params[k].type) >= 0) {
            error(e.args[k]->loc, "argument " + llvm::Twine(k + 1) + " of '" + e.name +
                                      "' is an output parameter and must be a variable");
            return std::nullopt;
          }
    error(e.loc, "wrong arguments to '" + e.name + "(" + argText + ")'; candidates: " +
                     candText);
    return std::nullopt;
  }
  return inlineCall(*best, e, args, lvalues);
}

static void findTailReturns(const Stmt &s, std::set<const Stmt *> &out) {
  (void)s;
  (void)out;
}

std::optional<RValue> IRGen::inlineCall(const FunctionRef &f, const Expr &call,
                                        std::vector<RValue> &args,
                                        std::vector<std::optional<LValue>> &lvalues) {
  const FunctionDecl &fn = *f.decl;
  for (const InlineFrame &frame : inlineStack)
    if (frame.fn == &fn) {
      error(call.loc, "recursive call to '" + fn.name + "' is not supported");
      return std::nullopt;
    }
  if (inlineStack.size() >= kMaxInlineDepth) {
    error(call.loc, "function calls are nested too deeply");
    return std::nullopt;
  }
  Scope *fs = newScope(f.scope);
  std::vector<Var *> params;
  for (size_t k = 0; k < fn.params.size(); ++k) {
    const Param &p = fn.params[k];
    OslType t = p.type;
    if (t.arrayLen == 0)
      t.arrayLen = args[k].type.arrayLen;
    auto v = coerce(args[k], t, call.args[k]->loc,
                    "in argument " + llvm::Twine(k + 1) + " of '" + fn.name + "'");
    if (!v)
      return std::nullopt;
    Var *pv = declareVar(fs, p.name, t, p.loc, *v);
    if (!pv)
      return std::nullopt;
    params.push_back(pv);
  }
  InlineFrame frame;
  frame.fn = &fn;
  if (!fn.returnType.isVoid()) {
    if (fn.returnType.base == BaseType::Matrix || fn.returnType.base == BaseType::Closure) {
      error(fn.loc, "functions returning '" + fn.returnType.str() +
                        "' are not supported yet");
      return std::nullopt;
    }
    frame.returnVar = declareVar(fs, kReturnVarName, fn.returnType, fn.loc,
                                 zeroValue(fn.returnType, call.loc));
  }
  Scope *saved = current;
  current = fs;
  inlineStack.push_back(frame);
  bool ok = emitStmtList(fn.body->body, 0, /*tail=*/true);
  Var *returnVar = inlineStack.back().returnVar;
  inlineStack.pop_back();
  current = saved;
  if (!ok)
    return std::nullopt;
  // Write output parameters back to the caller's variables.
  for (size_t k = 0; k < fn.params.size(); ++k) {
    if (!fn.params[k].isOutput)
      continue;
    const LValue &lv = *lvalues[k];
    auto v = coerce(params[k]->val, lv.type, call.args[k]->loc,
                    "when writing back output argument " + llvm::Twine(k + 1) + " of '" +
                        fn.name + "'");
    if (!v)
      return std::nullopt;
    storeLValue(lv, *v, call.loc);
  }
  if (!returnVar)
    return RValue::voidValue();
  return returnVar->val;
}
