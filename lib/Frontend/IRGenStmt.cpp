//===- IRGenStmt.cpp - Statements and structured control flow -------------===//
#include "IRGen.h"
#include "OslAbi/Print.h"

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
        // The continuing arm may itself return on some lanes (`else if
        // (c) return x;`): the rest runs only on the others.
        bool ok = !continuing || emitStmt(*continuing, false);
        if (ok) {
          std::vector<Var *> flags;
          Value jumped = jumpedCondition(continuing ? continuing->loc : s.loc,
                                         /*withContinue=*/true, &flags);
          ok = jumped ? emitUnlessJumped(jumped, flags, s.loc, stmts, i + 1, true)
                      : emitStmtList(stmts, i + 1, true);
        }
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
    if (last)
      break;
    // The rest of the list runs only where no jump has happened.
    std::vector<Var *> flags;
    Value jumped = jumpedCondition(s.loc, /*withContinue=*/true, &flags);
    if (jumped)
      return emitUnlessJumped(jumped, flags, s.loc, stmts, i + 1, tail);
  }
  return true;
}

bool IRGen::emitUnlessJumped(Value jumped, const std::vector<Var *> &flags, SrcLoc l,
                             const std::vector<StmtPtr> &stmts, size_t from, bool tail) {
  llvm::StringSet<> names;
  for (size_t k = from; k < stmts.size(); ++k)
    scanAssigned(*stmts[k], names);
  for (Var *f : flags)
    names.insert(f->name);
  auto rest = [&]() -> std::optional<RValue> {
    Scope *saved = current;
    current = newScope(current);
    // The flags are clear on the lanes that run the rest; one the rest
    // does not set keeps its value from before (no merge needed).
    std::vector<std::pair<Var *, RValue>> before;
    Value clear = constBool(false, l);
    for (Var *f : flags) {
      before.push_back({f, f->val});
      f->val = RValue::num(OslType(BaseType::Bool), clear);
    }
    bool ok = emitStmtList(stmts, from, tail);
    for (auto &[f, old] : before)
      if (f->val.value == clear)
        f->val = old;
    current = saved;
    if (!ok)
      return std::nullopt;
    return RValue::voidValue();
  };
  auto nothing = []() -> std::optional<RValue> { return RValue::voidValue(); };
  Value running = b.create<NotOp>(loc(l), jumped);
  return emitIfRegion(running, l, names, rest, nothing, false).has_value();
}

//===----------------------------------------------------------------------===//
// Jumps
//===----------------------------------------------------------------------===//

Var *IRGen::declareFlag(Scope *scope, llvm::StringRef name, SrcLoc l) {
  return declareVar(scope, name.str(), OslType(BaseType::Bool), l,
                    RValue::num(OslType(BaseType::Bool), constBool(false, l)));
}

void IRGen::setFlag(Var *flag, SrcLoc l) {
  flag->val = RValue::num(OslType(BaseType::Bool), constBool(true, l));
}

bool IRGen::inLoop() const {
  size_t base = inlineStack.empty() ? 0 : inlineStack.back().loopBase;
  return loopStack.size() > base;
}

Value IRGen::jumpedCondition(SrcLoc l, bool withContinue, std::vector<Var *> *flagsOut) {
  std::vector<Var *> candidates = {exitFlag,
                                   inlineStack.empty() ? shaderReturned
                                                       : inlineStack.back().returned};
  if (inLoop()) {
    candidates.push_back(loopStack.back().broke);
    if (withContinue)
      candidates.push_back(loopStack.back().continued);
  }
  Value result;
  for (Var *f : candidates) {
    if (!f)
      continue;
    Value v = f->val.value;
    if (auto k = getConstBool(v)) {
      if (!*k)
        continue; // never set on this path
      return constBool(true, l);
    }
    if (flagsOut)
      flagsOut->push_back(f);
    result = result ? b.create<OrOp>(loc(l), result, v).getResult() : v;
  }
  return result;
}

void IRGen::emitExit(SrcLoc l) { setFlag(exitFlag, l); }

bool IRGen::emitJump(const Stmt &s, bool tail) {
  if (s.kind == StmtKind::Break || s.kind == StmtKind::Continue) {
    bool isBreak = s.kind == StmtKind::Break;
    if (!inLoop())
      return error(s.loc, llvm::Twine("'") + (isBreak ? "break" : "continue") +
                              "' is not inside a loop");
    setFlag(isBreak ? loopStack.back().broke : loopStack.back().continued, s.loc);
    return true;
  }
  // return
  Var *returned = inlineStack.empty() ? shaderReturned : inlineStack.back().returned;
  if (inlineStack.empty()) {
    if (s.expr)
      return error(s.expr->loc, "a shader cannot return a value");
  } else {
    // By index: the returned expression may inline calls, which grow the
    // stack (a reference into it would dangle).
    size_t frameIndex = inlineStack.size() - 1;
    const FunctionDecl &fn = *inlineStack[frameIndex].fn;
    if (fn.returnType.isVoid()) {
      if (s.expr)
        return error(s.expr->loc, "void function '" + fn.name + "' cannot return a value");
    } else {
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
      inlineStack[frameIndex].returnVar->val = *c;
    }
  }
  // At the end of the function nothing follows to be skipped.
  if (!tail)
    setFlag(returned, s.loc);
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
  case StmtKind::Continue:
  case StmtKind::Return:
    return emitJump(s, tail);
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
  for (const Declarator &d : s.decls) {
    OslType t = base;
    t.arrayLen = d.arrayLen;
    if (!checkStructType(t, d.loc))
      return false;
    RValue init;
    if (d.init) {
      auto v = emitInitializer(*d.init, t, d.name, d.loc);
      if (!v || !checkNotNan(d.name, *v, *d.init, "", d.loc))
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

bool IRGen::emitLoop(const Stmt &s) {
  Scope *saved = current;
  current = newScope(current);
  LoopFrame frame;
  frame.broke = declareFlag(current, kBreakFlag, s.loc);
  frame.continued = declareFlag(current, kContinueFlag, s.loc);
  loopStack.push_back(frame);
  bool ok = true;
  llvm::StringSet<> names;
  if (s.kind == StmtKind::For && s.init) {
    ok = emitStmt(*s.init, false);
    if (ok && s.init->kind == StmtKind::Decl)
      for (const Declarator &d : s.init->decls)
        names.insert(d.name);
  }
  if (ok && s.kind == StmtKind::DoWhile) {
    ok = emitScoped(*s.thenStmt, false); // the first iteration, peeled
    frame.continued->val =
        RValue::num(OslType(BaseType::Bool), constBool(false, s.loc));
  }
  if (ok) {
    if (s.expr)
      scanAssigned(*s.expr, names);
    if (s.step)
      scanAssigned(*s.step, names);
    scanAssigned(*s.thenStmt, names);
    names.erase(kContinueFlag); // clear at the start of every iteration
    ok = emitWhile(s.expr.get(), *s.thenStmt, s.step.get(), names, s.loc);
  }
  loopStack.pop_back();
  current = saved;
  return ok;
}

bool IRGen::emitWhile(const Expr *condExpr, const Stmt &body, const Expr *step,
                      const llvm::StringSet<> &names, SrcLoc l) {
  carryStringsAsHandles(names, /*scalarsToo=*/true);
  std::vector<Var *> carried = carriedVars(names);
  std::vector<Value> init = flatten(carried, l);
  auto strings = stringSnapshot(names);
  auto structStrings = structStringSnapshot(carried);
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
  // Lanes that broke out, returned or exited do not test the condition
  // (it may have side effects).
  Value left = jumpedCondition(l, /*withContinue=*/false);
  Value stay = left ? b.create<NotOp>(mloc, left).getResult() : Value();
  Value cond;
  if (condExpr) {
    auto emitCond = [&]() -> std::optional<RValue> {
      auto c = emitExpr(*condExpr);
      if (!c)
        return std::nullopt;
      auto cb = toBool(*c, condExpr->loc);
      if (!cb)
        return std::nullopt;
      return RValue::num(OslType(BaseType::Bool), *cb);
    };
    std::optional<RValue> c;
    if (stay && mustRunMasked(*condExpr)) {
      llvm::StringSet<> condNames;
      scanAssigned(*condExpr, condNames);
      c = emitIfRegion(
          stay, l, condNames, emitCond,
          [&]() -> std::optional<RValue> {
            return RValue::num(OslType(BaseType::Bool), constBool(false, l));
          },
          /*wantValue=*/true);
    } else {
      c = emitCond();
      if (c && stay)
        c->value = b.create<AndOp>(mloc, stay, c->value);
    }
    if (!c)
      return false;
    cond = c->value;
  } else {
    cond = stay ? stay : constBool(true, l);
  }
  b.create<ConditionOp>(mloc, cond, flatten(carried, l));

  Block *after = b.createBlock(&whileOp.getAfter(), {}, types, locs);
  unflatten(carried, after->getArguments());
  loopStack.back().continued->val =
      RValue::num(OslType(BaseType::Bool), constBool(false, l));
  if (!emitScoped(body, false))
    return false;
  // `continue` ends only this iteration: the step still runs.
  loopStack.back().continued->val =
      RValue::num(OslType(BaseType::Bool), constBool(false, l));
  if (step) {
    Value stepSkipped = jumpedCondition(l, /*withContinue=*/false);
    if (stepSkipped) {
      llvm::StringSet<> stepNames;
      scanAssigned(*step, stepNames);
      auto r = emitIfRegion(
          b.create<NotOp>(mloc, stepSkipped), l, stepNames,
          [&]() -> std::optional<RValue> {
            if (!emitExpr(*step))
              return std::nullopt;
            return RValue::voidValue();
          },
          []() -> std::optional<RValue> { return RValue::voidValue(); },
          /*wantValue=*/false);
      if (!r)
        return false;
    } else if (!emitExpr(*step)) {
      return false;
    }
  }
  b.create<YieldOp>(mloc, flatten(carried, l));
  if (!checkStrings(strings, l, "a loop") ||
      !checkStructStrings(structStrings, l, "a loop"))
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
    names.insert(kReturnedFlag);
    if (s.expr) {
      names.insert(kReturnVarName);
      scanAssigned(*s.expr, names);
    }
    return;
  case StmtKind::Break:
    names.insert(kBreakFlag);
    return;
  case StmtKind::Continue:
    names.insert(kContinueFlag);
    return;
  case StmtKind::For:
  case StmtKind::While:
  case StmtKind::DoWhile: {
    // A loop's own break and continue do not leave it.
    llvm::StringSet<> inner;
    for (const Stmt *c : {s.init.get(), s.thenStmt.get()})
      if (c)
        scanAssigned(*c, inner);
    for (const Expr *e : {s.expr.get(), s.step.get()})
      if (e)
        scanAssigned(*e, inner);
    inner.erase(kBreakFlag);
    inner.erase(kContinueFlag);
    for (const auto &n : inner)
      names.insert(n.getKey());
    return;
  }
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

llvm::SmallVector<size_t> IRGen::libraryOutputArgs(const Expr &e) const {
  llvm::SmallVector<size_t> outputs;
  if (e.kind != ExprKind::Call || e.isCtor || allFunctions.count(e.name) || e.args.empty())
    return outputs;
  llvm::StringRef name = e.name;
  if (name == "sincos") // sincos(x, s, c)
    for (size_t k = 1; k < e.args.size(); ++k)
      outputs.push_back(k);
  if (name == "split" && e.args.size() > 1) // split(str, results, ...)
    outputs.push_back(1);
  if (name == "getmatrix" || name == "getattribute" || name == "gettextureinfo" ||
      name == "dict_value" || name == "getmessage" || name == "pointcloud_get")
    outputs.push_back(e.args.size() - 1); // the value comes last
  if (name == "pointcloud_search") // (file, center, radius, max, [sort,] name, array, ...)
    for (size_t k = e.args.size() % 2 ? 6 : 5; k < e.args.size(); k += 2)
      outputs.push_back(k);
  if (name == "fresnel") // (I, N, eta, Kr, Kt [, R, T])
    for (size_t k = 3; k < e.args.size(); ++k)
      outputs.push_back(k);
  if ((name == "regex_search" || name == "regex_match") && e.args.size() == 3)
    outputs.push_back(1); // (subject, results, regex)
  if (name == "texture" || name == "texture3d" || name == "environment")
    // The values of the "alpha" and "errormessage" options are outputs.
    // Options are (name, value) pairs that end the call, after at least
    // the file and the lookup point; a name TextureCall does not know as
    // a literal is an error there.
    for (size_t k = 2; k + 1 < e.args.size(); ++k)
      if ((e.args.size() - k) % 2 == 0 && e.args[k]->kind == ExprKind::StringLit &&
          (e.args[k]->name == "alpha" || e.args[k]->name == "errormessage"))
        outputs.push_back(k + 1);
  return outputs;
}

void IRGen::scanAssigned(const Expr &e, llvm::StringSet<> &names) {
  if (e.kind == ExprKind::Assign || e.kind == ExprKind::IncDec) {
    llvm::StringRef root = rootName(*e.args[0]);
    if (!root.empty())
      names.insert(root);
  }
  for (size_t k : libraryOutputArgs(e)) {
    llvm::StringRef root = rootName(*e.args[k]);
    if (!root.empty())
      names.insert(root);
  }
  if (e.kind == ExprKind::Call && e.name == "exit" && !allFunctions.count(e.name))
    names.insert(kExitFlag);
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
  // The function's own return state is not the caller's.
  for (const char *local : {kReturnVarName, kReturnedFlag, kBreakFlag, kContinueFlag})
    names.erase(local);
  auto &slot = functionAssignedCache[fn];
  for (const auto &n : names)
    slot.insert(n.getKey());
  return slot;
}

bool IRGen::hasSideEffects(const Expr &e) {
  if (e.kind == ExprKind::Assign || e.kind == ExprKind::IncDec)
    return true;
  // (exit() stops lanes and printf prints: both only where evaluated.)
  if (e.kind == ExprKind::Call && !e.isCtor &&
      (allFunctions.count(e.name) || !libraryOutputArgs(e).empty() || e.name == "exit" ||
       e.name == "pointcloud_write" || e.name == "setmessage" ||
       ::osl::printStreamCode(e.name) >= 0))
    return true;
  return llvm::any_of(e.args, [&](const ExprPtr &a) { return hasSideEffects(*a); });
}

bool IRGen::mustRunMasked(const Expr &e) {
  // An index known only at run time is range-checked where it is evaluated:
  // `m >= 0 && a[m] > x` must not report a[-1].
  if (e.kind == ExprKind::Index && e.args[1]->kind != ExprKind::IntLit)
    return true;
  return hasSideEffects(e) ||
         llvm::any_of(e.args, [&](const ExprPtr &a) { return mustRunMasked(*a); });
}
