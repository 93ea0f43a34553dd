//===- ConnectionBuiltins.cpp - isconnected --------------------------------===//
//
// isconnected(p) is 1 when an upstream layer's output feeds the parameter
// p, 2 when p is an output a downstream layer or the renderer reads, 3 for
// both, 0 otherwise. The group's connections are known when a layer is
// compiled (FrontendOptions), so the answer is a constant. A function's
// parameter bound to a shader parameter answers for it, as OSL passes
// references; a struct answers for its fields and a field for its struct.
// (The layer's own local variables and expressions answer 0.)
//
//===----------------------------------------------------------------------===//
#include "IRGen.h"

#include "OslFrontend/Frontend.h"

namespace osl::frontend {
namespace {

/// Does a connection of `connected` reach `path`: the same name, or one a
/// field of the other?
bool reaches(llvm::StringRef connected, llvm::StringRef path) {
  auto within = [](llvm::StringRef inner, llvm::StringRef outer) {
    return inner.size() > outer.size() && inner.starts_with(outer) &&
           inner[outer.size()] == '.';
  };
  return connected == path || within(connected, path) || within(path, connected);
}

bool anyReaches(const std::vector<std::string> &connected, llvm::StringRef path) {
  for (const std::string &c : connected)
    if (reaches(c, path))
      return true;
  return false;
}

} // namespace

ParamRef IRGen::parameterOf(const Expr &e) {
  if (e.kind == ExprKind::Ident) {
    Var *v = lookupVar(e.name);
    return v ? v->param : ParamRef();
  }
  if ((e.kind != ExprKind::Member && e.kind != ExprKind::Index) || e.args.empty())
    return {};
  // The type of the base names the field.
  const Expr *root = e.args[0].get();
  while (root->kind == ExprKind::Member || root->kind == ExprKind::Index)
    root = root->args[0].get();
  if (root->kind != ExprKind::Ident)
    return {};
  Var *v = lookupVar(root->name);
  if (!v || v->param.path.empty())
    return {};
  std::vector<const Expr *> chain;
  for (const Expr *x = &e; x != root; x = x->args[0].get())
    chain.push_back(x);
  ParamRef ref = v->param;
  OslType t = v->type;
  for (const Expr *x : llvm::reverse(chain)) {
    if (x->kind == ExprKind::Index || !t.isStructLike() || t.isArray())
      break; // an element or a component answers for what holds it
    int field = t.structDecl->fieldIndex(x->name);
    if (field < 0)
      break;
    ref.path += "." + t.structDecl->fields[field].name;
    t = t.structDecl->fields[field].type;
  }
  return ref;
}

std::optional<RValue> emitConnectionBuiltin(IRGen &g, const Expr &call, bool &known) {
  known = call.name == "isconnected";
  if (!known)
    return std::nullopt;
  if (call.args.size() != 1) {
    g.error(call.loc, "wrong arguments to 'isconnected'; candidates: int isconnected(T)");
    return std::nullopt;
  }
  const Expr &arg = *call.args[0];
  OslType intType(BaseType::Int);
  // The argument is evaluated (its errors reported) though only its name
  // matters.
  std::optional<RValue> value = g.emitExpr(arg);
  if (!value)
    return std::nullopt;
  // oslc's signature is "i?": any type but an array (an element is fine).
  if (value->type.isArray()) {
    g.error(call.loc, "wrong arguments to 'isconnected(" + value->type.str() +
                          ")'; candidates: int isconnected(T), T not an array (ask of an "
                          "element)");
    return std::nullopt;
  }
  ParamRef param = g.parameterOf(arg);
  const FrontendOptions &options = g.frontendOptions();
  int answer = 0;
  if (!param.path.empty()) {
    if ((options.userdataIsConnected && param.geometryData) ||
        anyReaches(options.connectedInputs, param.path))
      answer |= 1;
    // (A name is an input or an output, so each list holds only its kind.)
    if (anyReaches(options.connectedOutputs, param.path))
      answer |= 2;
  }
  return RValue::num(intType, g.constInt(answer, call.loc));
}

} // namespace osl::frontend
