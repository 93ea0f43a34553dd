//===- IRGenCall.cpp - Calls: overloads and inlining of user functions ----===//
#include "IRGen.h"

#include "mlir/Dialect/Arith/IR/Arith.h"
#include "llvm/ADT/STLExtras.h"
#include "llvm/ADT/StringSwitch.h"

using namespace osl::frontend;
using namespace mlir;
using namespace mlir::osl;

namespace {
constexpr unsigned kMaxInlineDepth = 64;

bool isLValueShaped(const Expr &e) {
  return e.kind == ExprKind::Ident || e.kind == ExprKind::Index ||
         e.kind == ExprKind::Member;
}
} // namespace

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

/// Does `s` contain a return statement (not counting nested functions)?
static bool containsReturn(const Stmt &s) {
  if (s.kind == StmtKind::Return)
    return true;
  if (s.func)
    return false; // a nested function's returns are its own
  for (const StmtPtr &c : s.body)
    if (c && containsReturn(*c))
      return true;
  for (const StmtPtr *c : {&s.thenStmt, &s.elseStmt, &s.init})
    if (*c && containsReturn(**c))
      return true;
  return false;
}

std::optional<RValue> IRGen::emitCall(const Expr &e, const OslType *expected) {
  if (!e.isCtor && lookupVar(e.name)) {
    error(e.loc, "'" + e.name + "' is not a function");
    return std::nullopt;
  }
  if (!e.isCtor) {
    std::vector<FunctionRef> cands = lookupFunctions(e.name);
    // As in C, a file-level function is callable only after its definition
    // (or, in osl-mlir, a prototype: oslc takes one for an empty body).
    int use = usePosition();
    auto later = [&](const FunctionRef &f) {
      return f.decl->order >= 0 && f.decl->visibleFrom >= use;
    };
    bool definedLater = llvm::any_of(cands, later);
    llvm::erase_if(cands, later);
    if (definedLater && cands.empty() && !isBuiltinName(e.name) && !lookupStruct(e.name)) {
      error(e.loc, "function '" + e.name + "' was not declared in this scope (it is defined "
                   "later in the file)");
      return std::nullopt;
    }
    if (isBuiltinName(e.name))
      // A function that redefines a library one calls the library one by
      // its name (OSL has no recursion).
      llvm::erase_if(cands, [&](const FunctionRef &f) {
        return llvm::any_of(inlineStack,
                            [&](const InlineFrame &frame) { return frame.fn == f.decl; });
      });
    bool arityMatch = llvm::any_of(cands, [&](const FunctionRef &f) {
      return f.decl->params.size() == e.args.size();
    });
    if (!cands.empty() && (arityMatch || !isBuiltinName(e.name)))
      return emitUserCall(e, cands, expected);
    if (cands.empty())
      if (const StructDecl *s = lookupStruct(e.name))
        return emitStructConstructor(*s, e);
  }
  return emitBuiltin(e, expected);
}

std::optional<RValue> IRGen::emitBuiltin(const Expr &e, const OslType *expected) {
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

const StructDecl *IRGen::lookupStruct(llvm::StringRef name) const {
  auto it = structsByName.find(name);
  return it == structsByName.end() ? nullptr : it->second;
}

std::optional<RValue> IRGen::emitStructConstructor(const StructDecl &s, const Expr &e) {
  // `name(a, b, ...)` builds the struct from one value per field, in order.
  if (e.args.size() != s.fields.size()) {
    error(e.loc, "struct '" + s.name + "' has " + llvm::Twine(s.fields.size()) +
                     " fields; its constructor got " + llvm::Twine(e.args.size()) +
                     " arguments");
    return std::nullopt;
  }
  RValue r;
  r.type = OslType::ofStruct(&s);
  for (size_t j = 0; j < s.fields.size(); ++j) {
    OslType ft = s.fields[j].type;
    auto v = emitExpr(*e.args[j], &ft);
    if (!v)
      return std::nullopt;
    auto c = coerce(*v, ft, e.args[j]->begin,
                    "for field '" + s.fields[j].name + "' of '" + s.name + "'");
    if (!c)
      return std::nullopt;
    r.fields.push_back(*c);
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
  // Initializer lists whose type the candidates do not agree on take the
  // type of the overload the other arguments choose (OSL: f({1}, 1)).
  std::vector<int> initListSizes(n, -1);
  bool deferred = false;
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
      outputSomewhere |= p.isOutput || writesParam(*f.decl, p.name);
      if (!agreed)
        agreed = p.type;
      else if (*agreed != p.type)
        agree = false;
    }
    if (agreed && agree)
      argExpected = &*agreed;
    if (!argExpected && a.kind == ExprKind::InitList) {
      initListSizes[k] = int(a.args.size());
      args[k].type = OslType(BaseType::Void);
      deferred = true;
      continue;
    }
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
  const FunctionRef *best =
      resolveOverload(cands, args, lvalues, expected, deferred ? &initListSizes : nullptr, &e);
  if (best && deferred) {
    for (size_t k = 0; k < n; ++k) {
      if (initListSizes[k] < 0)
        continue;
      auto v = emitExpr(*e.args[k], &best->decl->params[k].type);
      if (!v)
        return std::nullopt;
      args[k] = *v;
    }
  }
  if (!best && isBuiltinName(e.name) && !deferred) {
    // No user overload takes these arguments: the library function does
    // (a header overloading abs() for its struct still calls abs(float)).
    PreEvaluated scoped(*this, e, args);
    return emitBuiltin(e, expected);
  }
  if (!best) {
    std::string argText;
    for (size_t k = 0; k < n; ++k)
      argText += (k ? ", " : "") + (initListSizes[k] >= 0 ? std::string("{...}")
                                                          : args[k].type.str());
    std::string candText;
    for (const FunctionRef &f : cands)
      candText += (candText.empty() ? "" : "; ") + signatureText(*f.decl);
    // Output arguments that are not variables get their own message.
    for (const FunctionRef &f : cands)
      if (f.decl->params.size() == n && cands.size() == 1)
        for (size_t k = 0; k < n; ++k)
          if (f.decl->params[k].isOutput && !lvalues[k] &&
              conversionCost(args[k].type, f.decl->params[k].type) >= 0) {
            error(e.args[k]->begin, "argument " + llvm::Twine(k + 1) + " of '" + e.name +
                                      "' is an output parameter and must be a variable");
            return std::nullopt;
          }
    error(e.loc, "wrong arguments to '" + e.name + "(" + argText + ")'; candidates: " +
                     candText);
    return std::nullopt;
  }
  return inlineCall(*best, e, args, lvalues);
}

int IRGen::usePosition() const {
  for (auto frame = inlineStack.rbegin(); frame != inlineStack.rend(); ++frame)
    if (frame->fn->order >= 0)
      return frame->fn->order;
  return shaderPosition;
}

/// Whether file-level function `later` rather than `kept` (the same
/// signature) is the one the code being emitted calls: the last defined
/// before it.
bool IRGen::redefinitionApplies(const FunctionDecl &later, const FunctionDecl &kept) const {
  int use = usePosition();
  if (later.order < 0 || kept.order < 0 || later.order >= use)
    return false;
  return kept.order >= use || later.order > kept.order;
}

namespace osl::frontend {
bool sameSignature(const FunctionDecl &a, const FunctionDecl &b) {
  if (a.returnType != b.returnType || a.params.size() != b.params.size())
    return false;
  for (size_t k = 0; k < a.params.size(); ++k)
    if (a.params[k].type != b.params[k].type || a.params[k].isOutput != b.params[k].isOutput)
      return false;
  return true;
}
} // namespace osl::frontend

/// oslc's preference among overloads only their return types tell apart
/// (seen in its function-overloads test): lower is preferred.
static int returnTypeRank(const OslType &t) {
  if (t.isStructLike())
    return 9;
  switch (t.base) {
  case BaseType::Float: return 0;
  case BaseType::Int:
  case BaseType::Bool: return 1;
  case BaseType::Color: return 2;
  case BaseType::Vector: return 3;
  case BaseType::Point: return 4;
  case BaseType::Normal: return 5;
  case BaseType::Matrix: return 6;
  case BaseType::String: return 7;
  case BaseType::Closure: return 8;
  case BaseType::Void: return 10;
  default: return 9;
  }
}

/// A type as oslc writes it in declarations: "struct A", "closure color".
static std::string declTypeText(const OslType &t) {
  return (t.isStructLike() ? "struct " : "") + t.str();
}

namespace osl::frontend {
std::string oslcSignatureText(const FunctionDecl &fn) {
  std::string s = declTypeText(fn.returnType) + " " + fn.name + " (";
  for (size_t k = 0; k < fn.params.size(); ++k)
    s += (k ? ", " : "") + std::string(fn.params[k].isOutput ? "output " : "") +
         declTypeText(fn.params[k].type);
  return s + ")";
}
} // namespace osl::frontend

std::string IRGen::ambiguityMessage(const Expr &call, const std::vector<RValue> &args,
                                    const std::vector<const FunctionRef *> &ranked) {
  std::string argText;
  for (size_t k = 0; k < args.size(); ++k)
    argText += (k ? ", " : "") + declTypeText(args[k].type);
  auto declText = [&](const FunctionDecl &fn) {
    return fileLine(fn.loc) + "\t" + oslcSignatureText(fn);
  };
  std::string text = "Ambiguous call to '" + call.name + " (" + argText + ")'\n" +
                     "  Chosen function is:\n    " + declText(*ranked.front()->decl) +
                     "\n  Other candidates are:";
  for (size_t k = 1; k < ranked.size(); ++k)
    text += "\n    " + declText(*ranked[k]->decl);
  return text;
}

const FunctionRef *
IRGen::resolveOverload(const std::vector<FunctionRef> &cands, const std::vector<RValue> &args,
                       const std::vector<std::optional<LValue>> &lvalues,
                       const OslType *expected, const std::vector<int> *initListSizes,
                       const Expr *call) {
  // Rank the candidates: total conversion cost, then the return type.
  size_t n = args.size();
  std::vector<const FunctionRef *> best; // the lowest cost's candidates
  int bestCost = 0;
  for (const FunctionRef &f : cands) {
    const FunctionDecl &fn = *f.decl;
    if (fn.params.size() != n)
      continue;
    int cost = 0;
    bool ok = true;
    for (size_t k = 0; k < n && ok; ++k) {
      const Param &p = fn.params[k];
      if (initListSizes && (*initListSizes)[k] >= 0) {
        int size = (*initListSizes)[k];
        const OslType &t = p.type;
        ok = !p.isOutput &&
             (t.isArray() ? (t.arrayLen == 0 || t.arrayLen == size)
              : t.isStructLike() ? int(t.structDecl->fields.size()) == size
                                 : t.isTriple() && size == 3);
        continue;
      }
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
    // The arguments rank first; among equal ones, the overload returning
    // what the context wants (oslc: float f = g(int) takes int g(int) over
    // float g(float)).
    cost *= 2;
    if (expected && !fn.returnType.isVoid() &&
        conversionCost(fn.returnType, *expected) != 0)
      cost += 1;
    if (best.empty() || cost < bestCost) {
      best.clear();
      bestCost = cost;
    }
    // A second definition of the same signature is no rival: in one scope
    // the last defined before the code being emitted stands (oslc warns of
    // the redefinition; what follows it calls it), else the first found.
    if (cost != bestCost)
      continue;
    auto same = llvm::find_if(best, [&](const FunctionRef *g) {
      return sameSignature(*g->decl, fn);
    });
    if (same == best.end())
      best.push_back(&f);
    else if ((*same)->scope == f.scope && redefinitionApplies(fn, *(*same)->decl))
      *same = &f;
  }
  if (best.size() <= 1)
    return best.empty() ? nullptr : best.front();
  std::stable_sort(best.begin(), best.end(), [](const FunctionRef *a, const FunctionRef *b) {
    return returnTypeRank(a->decl->returnType) < returnTypeRank(b->decl->returnType);
  });
  if (call)
    diags.warning(call->loc, ambiguityMessage(*call, args, best));
  return best.front();
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
    SrcLoc argLoc = k < call.args.size() ? call.args[k]->begin : p.loc;
    auto v = coerce(args[k], t, argLoc,
                    "in argument " + llvm::Twine(k + 1) + " of '" + fn.name + "'");
    if (!v)
      return std::nullopt;
    Var *pv = declareVar(fs, p.name, t, p.loc, *v);
    if (!pv)
      return std::nullopt;
    pv->readOnly = !p.isOutput;
    // A reference to a shader parameter stays one (isconnected()).
    if (k < call.args.size())
      pv->param = parameterOf(*call.args[k]);
    params.push_back(pv);
  }
  inlinedFunctions.insert(&fn);
  InlineFrame frame;
  frame.fn = &fn;
  frame.returned = declareFlag(fs, kReturnedFlag, fn.loc);
  frame.loopBase = loopStack.size();
  if (!fn.returnType.isVoid()) {
    if ((fn.returnType.base == BaseType::Matrix && fn.returnType.isArray()) ||
        (fn.returnType.base == BaseType::Closure && fn.returnType.isArray())) {
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
  if (!fn.returnType.isVoid() && !containsReturn(*fn.body)) {
    error(call.loc, "non-void function '" + fn.name + "' has no 'return' statement");
    return std::nullopt;
  }
  // Write output parameters back to the caller's variables, and the
  // non-output ones the function wrote (OSL passes references).
  for (size_t k = 0; k < fn.params.size(); ++k) {
    if (!fn.params[k].isOutput) {
      if (params[k]->writtenThrough && lvalues[k]) {
        auto v = coerce(params[k]->val, lvalues[k]->type, call.args[k]->begin,
                        "when writing back argument " + llvm::Twine(k + 1) + " of '" +
                            fn.name + "'");
        if (!v)
          return std::nullopt;
        storeLValue(*lvalues[k], *v, call.loc);
      }
      continue;
    }
    if (!lvalues[k])
      continue; // checkUncalledFunctions: no caller to write back to
    const LValue &lv = *lvalues[k];
    if (!checkWritable(lv, call.args[k]->begin,
                       ", as passed to function " + fn.name + "() as arg " +
                           llvm::Twine(k + 1) + " (output parameter \"" + fn.params[k].name +
                           "\")"))
      return std::nullopt;
    auto v = coerce(params[k]->val, lv.type, call.args[k]->begin,
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

//===----------------------------------------------------------------------===//
// Operator overloading
//===----------------------------------------------------------------------===//

/// The function OSL calls for operator `op` on a struct: `a + b` is
/// `__operator__add__(a, b)`, `-a` is `__operator__neg__(a)`; oslc's own
/// words (`!=` is "neq": the __operator__ne__ its color2.h and others
/// define is never called).
static llvm::StringRef operatorFunctionName(llvm::StringRef op, bool unary) {
  if (unary)
    return llvm::StringSwitch<llvm::StringRef>(op)
        .Case("-", "__operator__neg__")
        .Case("+", "__operator__add__")
        .Case("!", "__operator__not__")
        .Case("~", "__operator__compl__")
        .Default("");
  return llvm::StringSwitch<llvm::StringRef>(op)
      .Case("+", "__operator__add__")
      .Case("-", "__operator__sub__")
      .Case("*", "__operator__mul__")
      .Case("/", "__operator__div__")
      .Case("%", "__operator__mod__")
      .Case("==", "__operator__eq__")
      .Case("!=", "__operator__neq__")
      .Case("&&", "__operator__and__")
      .Case("||", "__operator__or__")
      .Case("<", "__operator__lt__")
      .Case("<=", "__operator__le__")
      .Case(">", "__operator__gt__")
      .Case(">=", "__operator__ge__")
      .Case("&", "__operator__bitand__")
      .Case("|", "__operator__bitor__")
      .Case("^", "__operator__xor__")
      .Case("<<", "__operator__shl__")
      .Case(">>", "__operator__shr__")
      .Default("");
}

bool IRGen::tryOverloadedOperator(llvm::StringRef op, const Expr &site,
                                  std::vector<RValue> operands,
                                  std::optional<RValue> &result) {
  // Only operators on structs look for user functions: the built-in
  // operators on numbers, triples and matrices cannot be redefined.
  if (!llvm::any_of(operands, [](const RValue &v) { return v.type.isStructLike(); }))
    return false;
  llvm::StringRef fname = operatorFunctionName(op, operands.size() == 1);
  if (fname.empty())
    return false;
  std::vector<FunctionRef> cands = lookupFunctions(fname);
  std::vector<std::optional<LValue>> lvalues(operands.size());
  const FunctionRef *best = resolveOverload(cands, operands, lvalues, nullptr);
  if (!best)
    return false;
  result = inlineCall(*best, site, operands, lvalues);
  return true;
}

IRGen::PreEvaluated::PreEvaluated(IRGen &gen, const Expr &call,
                                  const std::vector<RValue> &args)
    : gen(gen) {
  for (size_t k = 0; k < args.size() && k < call.args.size(); ++k) {
    gen.preEvaluated[call.args[k].get()] = args[k];
    keys.push_back(call.args[k].get());
  }
}

IRGen::PreEvaluated::~PreEvaluated() {
  for (const Expr *k : keys)
    gen.preEvaluated.erase(k);
}
