//===- IRGenStmt.cpp - Statements and structured control flow -------------===//
#include "IRGen.h"

#include "mlir/Dialect/Arith/IR/Arith.h"
#include "llvm/ADT/STLExtras.h"
#include "llvm/ADT/StringSwitch.h"

using namespace osl::frontend;
using namespace mlir;
using namespace mlir::osl;

namespace {
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
} // namespace

//===----------------------------------------------------------------------===//
// Statements
//===----------------------------------------------------------------------===//

bool IRGen::emitStmtList(const std::vector<StmtPtr> &stmts, size_t from, bool tail) {
  for (size_t i = from; i < stmts.size(); ++i) {
    const Stmt &s = *stmts[i];
    bool last = i + 1 == stmts.size();
    // `if (c) { ...; return; } rest` == `if (c) { ... } else { rest }`,
    // and `if (c) A; else { ...; return; } rest` == `if (c) { A; rest } else ...`.
    bool thenReturns = s.kind == StmtKind::If && alwaysReturns(*s.thenStmt);
    bool elseReturns = s.kind == StmtKind::If && !thenReturns && s.elseStmt &&
                       alwaysReturns(*s.elseStmt);
    if (tail && !last && (thenReturns || elseReturns)) {
      auto cond = emitExpr(*s.expr);
      if (!cond)
        return false;
      auto c = toBool(*cond, s.expr->begin);
      if (!c)
        return false;
      llvm::StringSet<> names;
      scanAssigned(*s.thenStmt, names);
      if (s.elseStmt)
        scanAssigned(*s.elseStmt, names);
      for (size_t k = i + 1; k < stmts.size(); ++k)
        scanAssigned(*stmts[k], names);
      // The arm that always returns, and the arm that continues with the
      // rest of the list.
      const Stmt *returning = thenReturns ? s.thenStmt.get() : s.elseStmt.get();
      const Stmt *continuing = thenReturns ? s.elseStmt.get() : s.thenStmt.get();
      auto returningArm = [&]() -> std::optional<RValue> {
        if (!emitScoped(*returning, true))
          return std::nullopt;
        return RValue::voidValue();
      };
      auto continuingArm = [&]() -> std::optional<RValue> {
        Scope *saved = current;
        current = newScope(current);
        bool ok = (!continuing || emitStmt(*continuing, false)) &&
                  emitStmtList(stmts, i + 1, true);
        current = saved;
        if (!ok)
          return std::nullopt;
        return RValue::voidValue();
      };
      auto r = thenReturns
                   ? emitIfRegion(*c, s.loc, names, returningArm, continuingArm, false)
                   : emitIfRegion(*c, s.loc, names, continuingArm, returningArm, false);
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
  if (!checkSize(s.loc))
    return false;
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
    auto c = coerce(*v, fn.returnType, s.expr->begin,
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
  auto c = toBool(*cond, s.expr->begin);
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
      return error(l, (v->name == kReturnVarName ? std::string("the string returned")
                                                 : "string variable '" + v->name + "'") +
                          " is changed inside " + what +
                          "; strings are compile-time values and cannot depend on "
                          "control flow yet");
  return true;
}

std::optional<RValue>
IRGen::emitIfRegion(Value cond, SrcLoc l, const llvm::StringSet<> &assigned,
                    llvm::function_ref<std::optional<RValue>()> thenArm,
                    llvm::function_ref<std::optional<RValue>()> elseArm,
                    bool wantValue) {
  // A constant condition (e.g. from a literal or a macro) picks its arm.
  if (auto k = getConstBool(cond)) {
    auto v = *k ? thenArm() : elseArm();
    if (!v)
      return std::nullopt;
    return wantValue ? v : RValue::voidValue();
  }
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
  if (e.kind == ExprKind::Call && e.name == "sincos" && !allFunctions.count(e.name))
    for (size_t k = 1; k < e.args.size(); ++k) {
      llvm::StringRef root = rootName(*e.args[k]);
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
        for (const auto &n : functionAssigned(fn))
          names.insert(n.getKey());
      }
    }
  }
  for (const ExprPtr &a : e.args)
    scanAssigned(*a, names);
}

const llvm::StringSet<> &IRGen::functionAssigned(const FunctionDecl *fn) {
  auto it = functionAssignedCache.find(fn);
  if (it != functionAssignedCache.end())
    return it->second; // done, or in progress (recursion): partial is fine
  functionAssignedCache[fn]; // mark in progress
  llvm::StringSet<> names;
  scanAssigned(*fn->body, names);
  auto &slot = functionAssignedCache[fn];
  for (const auto &n : names)
    slot.insert(n.getKey());
  return slot;
}

bool IRGen::hasSideEffects(const Expr &e) {
  if (e.kind == ExprKind::Assign || e.kind == ExprKind::IncDec)
    return true;
  if (e.kind == ExprKind::Call && !e.isCtor &&
      (allFunctions.count(e.name) || e.name == "sincos"))
    return true;
  return llvm::any_of(e.args, [&](const ExprPtr &a) { return hasSideEffects(*a); });
}
