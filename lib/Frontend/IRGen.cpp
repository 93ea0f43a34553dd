//===- IRGen.cpp - Constants, conversions, variables, the program ---------===//
//
// The rest of the emitter: IRGenShader.cpp (the shader and its parameters),
// IRGenStmt.cpp (statements, control flow), IRGenExpr.cpp (expressions,
// lvalues), IRGenCall.cpp (user functions).
//
//===----------------------------------------------------------------------===//
#include "IRGen.h"

#include <functional>

#include "OslAbi/GlobalsLayout.h"
#include "OslDialect/GroupNames.h"

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
        // NaN and values past int's range: INT_MIN, as the run-time
        // conversion (lane::convert) and x86 give.
        double t = std::trunc(d);
        if (!(t >= -2147483648.0 && t <= 2147483647.0))
          t = -2147483648.0;
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
    // A string array's elements are string values (constants, choices or
    // handles), kept whole as fields.
    for (const RValue &c : column) {
      if (ft.base == BaseType::String)
        f.fields.push_back(c);
      else
        f.elems.push_back(c.value);
    }
    r.fields.push_back(f);
  }
  return r;
}

bool IRGen::checkStructType(const OslType &t, SrcLoc l) {
  if (!t.isStructLike())
    return true;
  for (size_t j = 0; j < t.structDecl->fields.size(); ++j) {
    const StructField &f = t.structDecl->fields[j];
    if ((f.type.base == BaseType::Closure || f.type.base == BaseType::Matrix) &&
        f.type.isArray())
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
  // to is a triple. oslc prefers keeping a point, vector or normal
  // spatial (f(1, 1, point) takes f(float, int, vector) over
  // f(int, float, color)): crossing to or from color costs more.
  if (from.isTriple())
    return (from.base == BaseType::Color) == (to.base == BaseType::Color) ? 1 : 2;
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
  Value value = v.value;
  // A comparison made a triple (color(u > 0.5)): 0 or 1 first.
  if (v.type.isBool() && to.isTriple())
    value = convert(value, b.getF32Type(), l);
  return RValue::num(to, convert(value, irType(b, to), l));
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
  RValue r = RValue::string("");
  if (strings.size() > 2 &&
      llvm::none_of(strings, [](const RValue &s) { return s.isStringChoice(); })) {
    // Choice k is string k: the index itself where it is one (0 elsewhere),
    // two compares where a compare and a select per string would do.
    for (const RValue &s : strings)
      r.choices.push_back(s.str);
    int32_t last = int32_t(strings.size()) - 1;
    if (auto clamp = index.getDefiningOp<ClampOp>()) {
      // An array's index, clamped as OSL clamps it: in range already.
      auto lo = getConstScalar(clamp.getB()), hi = getConstScalar(clamp.getC());
      if (lo && hi && *lo >= 0 && *hi <= last) {
        r.value = index;
        return r;
      }
    }
    Value inRange = boolAnd(cmp("ge", index, constInt(0, l), l),
                            cmp("le", index, constInt(last, l), l), l);
    r.value = select(inRange, index, constInt(0, l), l);
    return r;
  }
  // Flatten nested choices: each choice becomes its own entry.
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
    valueError(l, what + " must be known when the shader is compiled; this string is computed "
                         "at run time");
    return std::nullopt;
  }
  if (s.isStringChoice())
    return s.choices;
  return std::vector<std::string>{s.str};
}

std::optional<RValue>
IRGen::forEachStringChoice(const RValue &s, SrcLoc l,
                           llvm::function_ref<std::optional<RValue>(const std::string &)> emitOne,
                           const llvm::StringSet<> &assigned, bool wantValue) {
  if (!s.isStringChoice())
    return emitOne(s.str);
  // if (choice == 0) A else if (choice == 1) B ... else <last>
  std::function<std::optional<RValue>(size_t)> from = [&](size_t k) -> std::optional<RValue> {
    if (k + 1 == s.choices.size())
      return emitOne(s.choices[k]);
    Value isK = b.create<CmpOp>(loc(l), "eq", s.value, constInt(int(k), l));
    return emitIfRegion(
        isK, l, assigned, [&]() { return emitOne(s.choices[k]); },
        [&]() { return from(k + 1); }, wantValue);
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
  if (scope == shaderParams || scope == shaderBody) {
    auto global = root->vars.find(name);
    if (global != root->vars.end() && global->second->isGlobal) {
      error(l, "\"" + name + "\" already declared in this scope (a shader global; a nested "
               "block or a function may use the name)");
      return nullptr;
    }
  }
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
  if (options.groupLayer) {
    // Each read before the outermost statement that holds it (not one read
    // for all): osl-link-group lets a read see what the layers it places
    // before that statement assign (OSL's layers share their globals).
    Block *block = b.getInsertionBlock();
    Block::iterator at = b.getInsertionPoint();
    while (block != entryBlock && block != bodyBlock && !isa<func::FuncOp>(block->getParentOp())) {
      at = block->getParentOp()->getIterator();
      block = block->getParentOp()->getBlock();
    }
    b.setInsertionPoint(block, at);
  } else if (lastGlobal) {
    b.setInsertionPointAfter(lastGlobal);
  } else {
    b.setInsertionPointToStart(entryBlock);
  }
  auto op = b.create<GlobalOp>(loc(l), VaryingType::get(base), name);
  if (!options.groupLayer) {
    lastGlobal = op;
    globalValues[name] = op.getResult();
  }
  return op.getResult();
}

RValue IRGen::readVar(Var *v, SrcLoc l) {
  if (v->isGlobal && !v->val.value) {
    RValue read = RValue::num(v->type, getGlobal(v->name, irType(b, v->type), l));
    if (options.groupLayer)
      return read; // each read its own (see getGlobal)
    v->val = read;
  }
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
    globalVars.push_back(v);
    // oslc's read-only globals: all but P, I and N (and Ci, declared apart).
    llvm::StringRef name = g.name;
    v->isReadOnlyGlobal = name != "P" && name != "I" && name != "N";
  }
  for (const auto &s : program.structs)
    structsByName[s->name] = s.get();
  for (const auto &fn : program.functions) {
    // oslc warns of a second definition of a signature (the later is
    // called from then on), listing the earlier ones, latest first.
    std::string earlier;
    for (const FunctionRef &f : llvm::reverse(root->funcs[fn->name]))
      if (sameSignature(*f.decl, *fn))
        earlier += "\n    " + fileLine(f.decl->loc);
    if (!earlier.empty() &&
        !diags.warning(fn->loc, "Function '" + oslcSignatureText(*fn) +
                                    "' redefined in the same scope\n  Previous definitions:" +
                                    earlier))
      return nullptr;
    root->funcs[fn->name].push_back({fn.get(), root});
    allFunctions[fn->name].push_back(fn.get());
    collectFunctions(*fn->body);
  }
  collectFunctions(*shader.body);
  shaderPosition = int(shader.functionsBefore);

  b.setInsertionPointToEnd(module->getBody());
  auto func = b.create<func::FuncOp>(loc(shader.loc), shader.name,
                                     b.getFunctionType({}, {}));
  func->setAttr("osl.shader_type", b.getStringAttr(shader.shaderType));
  entryBlock = func.addEntryBlock();
  b.setInsertionPointToStart(entryBlock);
  if (!emitShader(shader, func) || !checkUncalledFunctions(program, *module))
    return nullptr;
  return module;
}
