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
    if (t.base == BaseType::Matrix && t.isArray()) {
      error(p.loc, "arrays of matrices are not supported yet");
      return std::nullopt;
    }
    auto v = coerce(args[k], t, call.args[k]->begin,
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
  // Write output parameters back to the caller's variables.
  for (size_t k = 0; k < fn.params.size(); ++k) {
    if (!fn.params[k].isOutput)
      continue;
    const LValue &lv = *lvalues[k];
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
