//===- IRGen.cpp - Constants, conversions, variables, shader and parameters ===//
//
// The rest of the emitter: IRGenStmt.cpp (statements, control flow),
// IRGenExpr.cpp (expressions, lvalues), IRGenCall.cpp (user functions).
//
//===----------------------------------------------------------------------===//
#include "IRGen.h"

#include <functional>

#include "OslRuntime/GlobalsLayout.h"
#include "OslTransforms/GroupNames.h"

#include "mlir/Dialect/Arith/IR/Arith.h"
#include "mlir/IR/BuiltinAttributes.h"
#include "llvm/ADT/STLExtras.h"
#include "llvm/ADT/StringExtras.h"

#include <cmath>

using namespace osl::frontend;
using namespace mlir;
using namespace mlir::osl;

namespace {
/// Inlining and peeling can multiply code; past this size we give up.
constexpr size_t kMaxOps = 2000000;

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

/// Every identifier `s` reads or writes, nested functions included.
void collectNames(const Expr &e, llvm::StringSet<> &names) {
  if (e.kind == ExprKind::Ident)
    names.insert(e.name);
  for (const ExprPtr &a : e.args)
    collectNames(*a, names);
}

void collectNames(const Stmt &s, llvm::StringSet<> &names) {
  for (const StmtPtr &c : s.body)
    collectNames(*c, names);
  for (const Declarator &d : s.decls)
    if (d.init)
      collectNames(*d.init, names);
  for (const Expr *e : {s.expr.get(), s.step.get()})
    if (e)
      collectNames(*e, names);
  for (const Stmt *c : {s.init.get(), s.thenStmt.get(), s.elseStmt.get()})
    if (c)
      collectNames(*c, names);
  if (s.func && s.func->body)
    collectNames(*s.func->body, names);
}

} // namespace


IRGen::IRGen(MLIRContext &ctx, Diagnostics &diags,
             llvm::ArrayRef<ParamOverride> overrides, const FrontendOptions &options)
    : ctx(ctx), diags(diags), overrides(overrides), options(options), b(&ctx) {
  b.setListener(&opCounter);
}

bool IRGen::checkSize(SrcLoc l) {
  if (opCounter.count <= kMaxOps)
    return true;
  return error(l, "the shader is too large after inlining functions (more than " +
                      llvm::Twine(kMaxOps) + " operations)");
}

Location IRGen::loc(SrcLoc l) {
  return FileLineColLoc::get(&ctx, diags.fileName(l.file), l.line, l.col);
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

void IRGen::appendElement(RValue &array, const RValue &element) {
  if (element.type.isMatrix())
    array.elems.insert(array.elems.end(), element.elems.begin(), element.elems.end());
  else
    array.elems.push_back(element.value);
}

RValue IRGen::zeroValue(OslType t, SrcLoc l) {
  if (t.base == BaseType::Closure && !t.isArray())
    return emptyClosure(*this, l);
  if (t.isString())
    return RValue::string("");
  if (t.isArray() && t.base == BaseType::String) {
    RValue r;
    r.type = t;
    r.fields.assign(t.arrayLen, RValue::string(""));
    return r;
  }
  if (t.isStructLike()) {
    RValue r;
    r.type = t;
    for (size_t j = 0; j < t.structDecl->fields.size(); ++j)
      r.fields.push_back(zeroValue(fieldType(t, j), l));
    return r;
  }
  if (t.isArray()) {
    RValue r;
    r.type = t;
    for (int i = 0; i < t.arrayLen; ++i)
      appendElement(r, zeroValue(t.element(), l));
    return r;
  }
  if (t.isMatrix())
    return scaledIdentity(constFloat(0, l), l);
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

std::optional<double> IRGen::getConstScalar(Value v) {
  if (!v)
    return std::nullopt;
  if (auto c = v.getDefiningOp<arith::ConstantOp>()) {
    if (auto ia = dyn_cast<IntegerAttr>(c.getValue()))
      return ia.getType().isInteger(1) ? double(!ia.getValue().isZero())
                                       : double(ia.getInt());
    if (auto fa = dyn_cast<FloatAttr>(c.getValue()))
      return fa.getValueAsDouble();
  }
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

OslType IRGen::fieldType(const OslType &structType, size_t j) {
  OslType f = structType.structDecl->fields[j].type;
  if (structType.isArray())
    f.arrayLen = structType.arrayLen;
  return f;
}

RValue IRGen::packStructArray(const OslType &arrayType, const std::vector<RValue> &elems) {
  RValue r;
  r.type = arrayType;
  for (size_t j = 0; j < arrayType.structDecl->fields.size(); ++j) {
    OslType ft = fieldType(arrayType, j);
    std::vector<RValue> column;
    for (const RValue &e : elems)
      column.push_back(e.fields[j]);
    if (ft.isStructLike()) {
      r.fields.push_back(packStructArray(ft, column));
      continue;
    }
    RValue f;
    f.type = ft;
    for (const RValue &c : column)
      f.elems.push_back(c.value);
    r.fields.push_back(f);
  }
  return r;
}

bool IRGen::checkStructType(const OslType &t, SrcLoc l) {
  if (!t.isStructLike())
    return true;
  for (size_t j = 0; j < t.structDecl->fields.size(); ++j) {
    const StructField &f = t.structDecl->fields[j];
    // String fields: single ones, in structs that are not in arrays.
    bool unsupportedString =
        f.type.base == BaseType::String && (t.isArray() || f.type.isArray());
    if (unsupportedString)
      return error(l, "field '" + f.name + "' of struct '" + t.structDecl->name +
                          "': string fields of arrays of structs, and arrays of strings "
                          "as fields, are not supported yet");
    if ((f.type.base == BaseType::Closure && (t.isArray() || f.type.isArray())) ||
        (f.type.base == BaseType::Matrix && (t.isArray() || f.type.isArray())))
      return error(l, "field '" + f.name + "' of struct '" + t.structDecl->name +
                          "': '" + f.type.str() + "' fields are not supported yet");
    if (t.isArray() && f.type.isArray())
      return error(l, "arrays of struct '" + t.structDecl->name +
                          "' (it has the array field '" + f.name +
                          "') are not supported yet");
    if (!checkStructType(fieldType(t, j), l))
      return false;
  }
  return true;
}

int IRGen::conversionCost(OslType from, OslType to) {
  if (from.isStructLike() || to.isStructLike()) {
    bool same = from.structDecl == to.structDecl &&
                (from.arrayLen == to.arrayLen || (to.arrayLen == 0 && from.isArray()));
    return same ? 0 : -1;
  }
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
  // A number becomes a matrix as n * identity; a matrix becomes nothing else.
  if (to.isMatrix())
    return from.isScalar() ? 2 : -1;
  if (from.isMatrix())
    return -1;
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
  // OSL lets a closure be assigned the number 0: the empty closure.
  if (to.base == BaseType::Closure && !to.isArray() && v.type.isScalar()) {
    auto k = getConstScalar(v.value);
    if (!k || *k != 0)
      return fail();
    return emptyClosure(*this, l);
  }
  if (conversionCost(v.type, to) < 0)
    return fail();
  if (to.isStructLike())
    return v; // the same struct (and length), by conversionCost

  if (to.isArray()) {
    RValue r;
    r.type = v.type;
    r.type.base = to.base;
    r.elems = v.elems;
    r.fields = v.fields; // a string array's strings
    return r;
  }
  if (to.isString()) {
    v.type = to;
    return v;
  }
  if (to.isMatrix())
    return v.type.isMatrix() ? v : scaledIdentity(v.value, l);
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
  // A string is true when it is not empty.
  if (v.isKnownString())
    return constBool(!v.str.empty(), l);
  if (v.isStringChoice()) {
    Value any = constBool(false, l);
    for (size_t k = 0; k < v.choices.size(); ++k)
      if (!v.choices[k].empty())
        any = boolOr(any, cmp("eq", v.value, constInt(int(k), l), l), l);
    return any;
  }
  if (v.type.isClosure()) // a closure is true when it is not empty
    return b.create<CmpOp>(loc(l), "ne", v.value,
                           b.create<ClosureEmptyOp>(loc(l), getUniformType(v.value.getType())))
        .getResult();
  if (!v.type.isNumeric()) {
    error(l, "a value of type '" + v.type.str() + "' cannot be used as a condition");
    return std::nullopt;
  }
  if (auto k = getConstScalar(v.value))
    return constBool(*k != 0, l);
  Value zero;
  if (v.type.isInt())
    zero = constInt(0, l);
  else if (v.type.isFloat())
    zero = constFloat(0, l);
  else
    zero = constTriple(0, 0, 0, l);
  return b.create<CmpOp>(loc(l), "ne", v.value, zero).getResult();
}

RValue IRGen::stringChoice(std::vector<RValue> strings, Value index, SrcLoc l) {
  // A run-time string among them: select among handles.
  if (llvm::any_of(strings, [](const RValue &s) { return s.isRuntimeString(); })) {
    Value handle = stringHandle(strings[0], l);
    for (size_t k = 1; k < strings.size(); ++k) {
      Value isK = b.create<CmpOp>(loc(l), "eq", index, constInt(int(k), l));
      handle = b.create<SelectOp>(loc(l), isK, stringHandle(strings[k], l), handle);
    }
    return RValue::runtimeString(handle);
  }
  // Flatten nested choices: each choice becomes its own entry.
  RValue r = RValue::string("");
  Value flat = constInt(0, l);
  for (size_t k = 0; k < strings.size(); ++k) {
    Value isK = b.create<CmpOp>(loc(l), "eq", index, constInt(int(k), l));
    const RValue &s = strings[k];
    Value sub;
    if (s.isStringChoice()) {
      sub = b.create<AddOp>(loc(l), s.value, constInt(int(r.choices.size()), l));
      r.choices.insert(r.choices.end(), s.choices.begin(), s.choices.end());
    } else {
      sub = constInt(int(r.choices.size()), l);
      r.choices.push_back(s.str);
    }
    flat = b.create<SelectOp>(loc(l), isK, sub, flat);
  }
  r.value = flat;
  return r;
}

void IRGen::reportAtRunTime(const std::string &message, SrcLoc l) {
  std::string format; // the message as a format string: '%' doubled
  for (char c : message)
    format += c == '%' ? std::string("%%") : std::string(1, c);
  b.create<PrintOp>(loc(l), "renderer_error", "s",
                    ValueRange{stringHandle(RValue::string(format), l)}, Value());
}

Value IRGen::stringHandle(const RValue &s, SrcLoc l) {
  if (s.isRuntimeString())
    return s.value;
  auto intern = [&](const std::string &text) -> Value {
    return b.create<mlir::osl::StringConstantOp>(loc(l), b.getI32Type(), text);
  };
  if (!s.isStringChoice())
    return intern(s.str);
  Value handle = intern(s.choices[0]);
  for (size_t k = 1; k < s.choices.size(); ++k) {
    Value isK = b.create<CmpOp>(loc(l), "eq", s.value, constInt(int(k), l));
    handle = b.create<SelectOp>(loc(l), isK, intern(s.choices[k]), handle);
  }
  return handle;
}

std::optional<std::vector<std::string>>
IRGen::compileTimeStrings(const RValue &s, SrcLoc l, const llvm::Twine &what) {
  if (s.isRuntimeString()) {
    error(l, what + " must be known when the shader is compiled; this string is computed "
                    "at run time");
    return std::nullopt;
  }
  if (s.isStringChoice())
    return s.choices;
  return std::vector<std::string>{s.str};
}

std::optional<RValue>
IRGen::forEachStringChoice(const RValue &s, SrcLoc l,
                           llvm::function_ref<std::optional<RValue>(const std::string &)> emitOne) {
  if (!s.isStringChoice())
    return emitOne(s.str);
  // if (choice == 0) A else if (choice == 1) B ... else <last>
  std::function<std::optional<RValue>(size_t)> from = [&](size_t k) -> std::optional<RValue> {
    if (k + 1 == s.choices.size())
      return emitOne(s.choices[k]);
    Value isK = b.create<CmpOp>(loc(l), "eq", s.value, constInt(int(k), l));
    return emitIfRegion(
        isK, l, {}, [&]() { return emitOne(s.choices[k]); }, [&]() { return from(k + 1); },
        /*wantValue=*/true);
  };
  return from(0);
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
  this->shader = shader.name;
  OwningOpRef<ModuleOp> module = ModuleOp::create(loc(shader.loc));
  root = newScope(nullptr);
  current = root;
  for (const GlobalDecl &g : kGlobals) {
    Var *v = declareVar(root, g.name, OslType(g.type), SrcLoc(), RValue());
    v->isGlobal = true;
  }
  for (const auto &s : program.structs)
    structsByName[s->name] = s.get();
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

/// Does the parameter's metadata say [[int NAME = 0]]?
static bool intMetadataIsZero(const Param &p, llvm::StringRef name) {
  for (const Metadatum &m : p.metadata)
    if (m.name == name && m.value && m.value->kind == ExprKind::IntLit)
      return m.value->intValue == 0;
  return false;
}

static bool isLockgeomZero(const Param &p) { return intMetadataIsZero(p, "lockgeom"); }

bool IRGen::emitShader(const ShaderDecl &shader, func::FuncOp func) {
  for (const ParamOverride &o : overrides) {
    // A struct parameter's fields are set as NAME.FIELD (nested: NAME.A.B).
    bool found = llvm::any_of(shader.params, [&](const Param &p) {
      return p.name == o.name ||
             (p.type.isStructLike() && llvm::StringRef(o.name).starts_with(p.name + "."));
    });
    if (!found)
      return error(shader.loc, "shader '" + shader.name + "' has no parameter '" +
                                   o.name + "'");
  }
  // Ci, the shader's closure result: written as output "Ci" if assigned.
  Var *ci = declareVar(root, "Ci", OslType(BaseType::Closure), shader.loc,
                       emptyClosure(*this, shader.loc));
  Value emptyCi = ci->val.value;
  // Ci as the shader starts: in a group, what earlier layers left
  // (osl-link-group, with lazy-globals=false).
  emptyCi.getDefiningOp()->setAttr(kInitialCiAttr, b.getUnitAttr());
  Scope *paramScope = newScope(root);
  current = paramScope;
  // Before the parameters: a default value may call exit().
  exitFlag = declareFlag(root, kExitFlag, shader.loc);
  // OSL runs a parameter's default when the parameter is first used: the
  // default of one nothing reads never runs, so its exit() or printf never
  // happens. (Used ones run here, in order, which differs from OSL only
  // when an effect of the body comes before the first use.)
  llvm::StringSet<> used;
  collectNames(*shader.body, used);
  for (const Param &p : shader.params)
    if (p.init)
      collectNames(*p.init, used);
  for (const Param &p : shader.params)
    if (!emitParam(p, paramScope, /*runDefault=*/p.isOutput || used.count(p.name)))
      return false;
  // [[int allowconnect = 0]]: the group builder refuses to connect these.
  llvm::StringSet<> unconnectable;
  for (const Param &p : shader.params)
    if (intMetadataIsZero(p, "allowconnect"))
      unconnectable.insert(p.name);
  if (!unconnectable.empty())
    func.walk([&](ParamOp op) {
      if (unconnectable.contains(op.getName().split('.').first))
        op->setAttr(kNotConnectableAttr, b.getUnitAttr());
    });

  current = newScope(paramScope);
  shaderReturned = declareFlag(current, kReturnedFlag, shader.loc);
  // Lanes a default value stopped run none of the body.
  std::optional<bool> exited = getConstBool(exitFlag->val.value);
  if (!exited) {
    llvm::StringSet<> names;
    for (const StmtPtr &s : shader.body->body)
      scanAssigned(*s, names);
    Value running = b.create<NotOp>(loc(shader.loc), exitFlag->val.value);
    auto body = [&]() -> std::optional<RValue> {
      if (!emitStmtList(shader.body->body, 0, /*tail=*/true))
        return std::nullopt;
      return RValue::voidValue();
    };
    auto nothing = []() -> std::optional<RValue> { return RValue::voidValue(); };
    if (!emitIfRegion(running, shader.loc, names, body, nothing, false))
      return false;
  } else if (!*exited && !emitStmtList(shader.body->body, 0, /*tail=*/true)) {
    return false;
  }

  SrcLoc endLoc = shader.loc;
  current = paramScope;
  for (const Param &p : shader.params) {
    if (!p.isOutput)
      continue;
    Var *v = paramScope->vars[p.name];
    // A struct's fields are outputs of their own, NAME.FIELD, which layers
    // connect (a struct input takes them field by field).
    forEachStructLeaf(p.name, v->type, v->val, [&](const std::string &name, RValue &leaf) {
      if (leaf.type.isString())
        return; // strings are compile-time
      if (leaf.type.hasElems()) {
        // One output per element (a matrix: 16, row-major); the compiler
        // merges them into one image with as many channels.
        for (size_t i = 0; i < leaf.elems.size(); ++i) {
          auto out = b.create<OutputOp>(loc(p.loc), name, leaf.elems[i]);
          out->setAttr("osl.index", b.getI64IntegerAttr(int64_t(i)));
        }
        return;
      }
      b.create<OutputOp>(loc(p.loc), name, leaf.value);
    });
  }
  if (ci->val.value != emptyCi)
    b.create<OutputOp>(loc(endLoc), "Ci", ci->val.value);
  b.create<func::ReturnOp>(loc(endLoc));
  // Literals converted at compile time leave their original constant
  // unused; drop those (innermost first, so nothing dangles).
  llvm::SmallVector<Operation *> dead;
  func.walk<WalkOrder::PostOrder>([&](arith::ConstantOp c) {
    if (c->use_empty())
      dead.push_back(c);
  });
  for (Operation *op : dead)
    op->erase();
  return true;
}

void IRGen::forEachStructLeaf(const std::string &name, const OslType &type, RValue &value,
                              llvm::function_ref<void(const std::string &, RValue &)> fn) {
  if (!type.isStructLike() || type.isArray()) {
    fn(name, value);
    return;
  }
  for (size_t j = 0; j < value.fields.size(); ++j)
    forEachStructLeaf(name + "." + type.structDecl->fields[j].name, fieldType(type, j),
                      value.fields[j], fn);
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
  if (t.isMatrix()) {
    if (nums.size() != 1 && nums.size() != 16) {
      error(p.loc, "parameter '" + p.name + "' of type 'matrix' takes 1 or 16 values, got '" +
                       text + "'");
      return std::nullopt;
    }
    if (nums.size() == 1)
      return scaledIdentity(constFloat(float(nums[0]), p.loc), p.loc);
    MatrixElems m;
    for (double d : nums)
      m.push_back(constFloat(float(d), p.loc));
    return matrixValue(m);
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
    return RValue::num(t, makeElem(0, /*splat=*/nums.size() == 1));
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

int IRGen::connectedArrayLength(llvm::StringRef name) const {
  for (const auto &[input, length] : options.connectedArrayLengths)
    if (input == name)
      return length;
  return 0;
}

bool IRGen::emitParam(const Param &p, Scope *scope, bool runDefault) {
  OslType t = p.type;
  if ((t.base == BaseType::Matrix && t.isArray()) || (t.isStructLike() && t.isArray()))
    return error(p.loc, "shader parameters of type '" + t.str() + "' are not supported yet");
  if (t.isStructLike()) {
    // Instance values and connections name the fields (`p.field`): each
    // numeric field is a parameter of its own.
    for (const ParamOverride &o : overrides)
      if (o.name == p.name)
        return error(p.loc, "struct parameter '" + p.name +
                                "' takes values field by field ('" + p.name + ".FIELD')");
    if (!checkStructType(t, p.loc))
      return false;
    auto init = emitInitializer(*p.init, t, p.name, p.loc);
    if (!init)
      return false;
    auto c = coerce(*init, t, p.loc, "in the default of '" + p.name + "'");
    if (!c)
      return false;
    bool ok = true;
    forEachStructLeaf(p.name, t, *c, [&](const std::string &name, RValue &leaf) {
      if (!ok || leaf.type.isString())
        return;
      const ParamOverride *fieldValue = nullptr;
      for (const ParamOverride &o : overrides)
        if (o.name == name)
          fieldValue = &o;
      if (fieldValue) {
        Param field;
        field.type = leaf.type;
        field.name = name;
        field.loc = p.loc;
        std::optional<RValue> given = overrideValue(field, fieldValue->value);
        if (!given) {
          ok = false;
          return;
        }
        leaf = *given;
      }
      if (leaf.type.hasElems()) {
        for (size_t i = 0; i < leaf.elems.size(); ++i) {
          auto op = b.create<ParamOp>(loc(p.loc), leaf.elems[i].getType(), name, leaf.elems[i]);
          op->setAttr("osl.index", b.getI64IntegerAttr(int64_t(i)));
          leaf.elems[i] = op.getResult();
        }
      } else {
        leaf.value = b.create<ParamOp>(loc(p.loc), leaf.value.getType(), name, leaf.value);
      }
    });
    if (!ok)
      return false;
    Var *v = declareVar(scope, p.name, t, p.loc, *c);
    if (!v)
      return false;
    v->isOutputParam = p.isOutput;
    v->param = {p.name, isLockgeomZero(p)};
    return true;
  }
  if (t.isVoid())
    return error(p.loc, "parameters cannot have type 'void'");
  if (p.isOutput && t.arrayLen == 0)
    return error(p.loc, "shader output parameter '" + p.name + "' cannot be an unsized array");
  const ParamOverride *ov = nullptr;
  for (const ParamOverride &o : overrides)
    if (o.name == p.name)
      ov = &o;
  if (t.isArray() && t.base == BaseType::String && ov) {
    // Comma-separated strings, each optionally quoted (as a serialized
    // group writes them); an unsized array takes their count.
    llvm::SmallVector<llvm::StringRef> parts;
    llvm::StringRef(ov->value).split(parts, ',');
    if (t.arrayLen == 0)
      t.arrayLen = int(parts.size());
    if (int(parts.size()) != t.arrayLen)
      return error(p.loc, "parameter '" + p.name + "' of type '" + t.str() + "' takes " +
                              std::to_string(t.arrayLen) + " strings, got '" + ov->value +
                              "'");
    RValue strings;
    strings.type = t;
    for (llvm::StringRef part : parts) {
      part = part.trim();
      part.consume_front("\"");
      part.consume_back("\"");
      strings.fields.push_back(RValue::string(part.str()));
    }
    Var *v = declareVar(scope, p.name, t, p.loc, strings);
    if (!v)
      return false;
    v->isOutputParam = p.isOutput;
    return true;
  }
  std::optional<RValue> init;
  if (ov && t.isClosure())
    return error(p.loc, "closure parameter '" + p.name + "' cannot be given a value");
  if (ov) {
    if (t.arrayLen == 0) {
      // An unsized array takes its length from the value given (OSL's
      // `float a[]` parameters), as many elements as it has numbers.
      size_t numbers = llvm::StringRef(ov->value).count(',') + 1;
      size_t per = t.element().isTriple() ? 3 : 1;
      if (numbers % per == 0)
        t.arrayLen = int(numbers / per);
      else if (p.init->kind == ExprKind::InitList)
        t.arrayLen = int(p.init->args.size());
    }
    Param sized;
    sized.type = t;
    sized.name = p.name;
    sized.loc = p.loc;
    init = overrideValue(sized, ov->value);
  } else if (int length = connectedArrayLength(p.name); t.arrayLen == 0 && length > 0) {
    // An unsized array input takes the length of the array output
    // connected to it, which gives every element.
    t.arrayLen = length;
    init = zeroValue(t, p.loc);
  } else if (!runDefault && !t.isString() && !t.isClosure() && hasSideEffects(*p.init)) {
    if (t.arrayLen == 0 && p.init->kind == ExprKind::InitList)
      t.arrayLen = int(p.init->args.size());
    init = zeroValue(t, p.loc);
  } else if (p.init->kind == ExprKind::InitList && p.init->args.empty()) {
    // `{ }`: zeros; an unsized array of one element, as OSL makes it.
    if (t.arrayLen == 0)
      t.arrayLen = 1;
    init = zeroValue(t, p.loc);
  } else {
    init = emitInitializer(*p.init, t, p.name, p.loc);
  }
  if (!init)
    return false;
  RValue val = *init;
  if (t.hasElems()) {
    for (size_t i = 0; i < val.elems.size(); ++i) {
      Value d = val.elems[i];
      auto op = b.create<ParamOp>(loc(p.loc), d.getType(), p.name, d);
      op->setAttr("osl.index", b.getI64IntegerAttr(int64_t(i)));
      val.elems[i] = op.getResult();
    }
  } else if (!t.isString()) {
    // (A closure parameter takes no instance value, but may be connected.)
    Value d = val.value;
    val.value = b.create<ParamOp>(loc(p.loc), d.getType(), p.name, d).getResult();
    // Per-geometry data (lockgeom=0) the renderer has takes precedence.
    if (isLockgeomZero(p))
      if (auto data = testshadeUserdata(*this, p.name, t, p.loc))
        val.value = select(data->first, data->second, val.value, p.loc);
  }
  Var *v = declareVar(scope, p.name, t, p.loc, val);
  if (!v)
    return false;
  v->isOutputParam = p.isOutput;
  v->param = {p.name, isLockgeomZero(p)};
  return true;
}

std::optional<RValue> IRGen::emitInitializer(const Expr &init, OslType &type,
                                             llvm::StringRef name, SrcLoc l) {
  if (init.kind == ExprKind::InitList && !type.isArray()) {
    // {x, y, z} for a triple is its constructor; for a struct, its fields.
    if (type.isNumeric() || type.isString())
      return emitTypeConstructor(*this, type, init.args, init.loc);
    if (type.isStructLike()) {
      const auto &fields = type.structDecl->fields;
      if (init.args.size() > fields.size()) {
        error(init.args[fields.size()]->loc,
              "too many initializers for '" + name + "' of type '" + type.str() + "'");
        return std::nullopt;
      }
      RValue r;
      r.type = type;
      for (size_t j = 0; j < fields.size(); ++j) {
        OslType ft = fields[j].type;
        std::optional<RValue> f = j < init.args.size()
                                      ? emitInitializer(*init.args[j], ft, fields[j].name, l)
                                      : std::optional<RValue>(zeroValue(ft, l));
        if (!f)
          return std::nullopt;
        r.fields.push_back(*f);
      }
      return r;
    }
    error(init.loc, "initializer list for '" + name + "' of type '" + type.str() + "'");
    return std::nullopt;
  }
  if (init.kind == ExprKind::InitList) {
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
    OslType elem = type.element();
    RValue r;
    r.type = type;
    if (type.base == BaseType::String) {
      for (int i = 0; i < type.arrayLen; ++i) {
        if (i >= int(init.args.size())) {
          r.fields.push_back(RValue::string(""));
          continue;
        }
        auto v = emitExpr(*init.args[i], &elem);
        if (!v)
          return std::nullopt;
        if (!v->type.isString()) {
          error(init.args[i]->begin, "cannot convert '" + v->type.str() +
                                         "' to 'string' in initializer of '" + name + "'");
          return std::nullopt;
        }
        r.fields.push_back(*v);
      }
      return r;
    }
    if (elem.isStructLike()) {
      if (!checkStructType(type, l))
        return std::nullopt;
      std::vector<RValue> structs;
      for (int i = 0; i < type.arrayLen; ++i) {
        OslType et = elem;
        auto v = i < int(init.args.size())
                     ? emitInitializer(*init.args[i], et, name, l)
                     : std::optional<RValue>(zeroValue(elem, l));
        if (!v)
          return std::nullopt;
        structs.push_back(*v);
      }
      return packStructArray(type, structs);
    }
    for (int i = 0; i < type.arrayLen; ++i) {
      if (i < int(init.args.size())) {
        const Expr &e = *init.args[i];
        auto v = emitExpr(e, &elem);
        if (!v)
          return std::nullopt;
        auto c = coerce(*v, elem, e.begin, "in initializer of '" + name + "'");
        if (!c)
          return std::nullopt;
        appendElement(r, *c);
      } else {
        appendElement(r, zeroValue(elem, l));
      }
    }
    return r;
  }
  auto v = emitExpr(init, &type);
  if (!v)
    return std::nullopt;
  if (type.arrayLen == 0 && v->type.isArray())
    type.arrayLen = v->type.arrayLen;
  return coerceForAssignment(*v, type, init.begin, "in initialization of '" + name + "'");
}
