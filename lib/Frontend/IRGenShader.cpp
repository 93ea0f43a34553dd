//===- IRGenShader.cpp - The shader body and its parameters ---------------===//
//
// Parameters become osl.param ops (one per element and per struct field)
// holding their defaults or instance values; a default runs only when the
// parameter is used, as in OSL. Per-geometry parameters take testshade's
// user data, unsized arrays the length of what is given or connected.
//
//===----------------------------------------------------------------------===//
#include "IRGen.h"

#include "OslDialect/GroupNames.h"

#include "mlir/Dialect/Arith/IR/Arith.h"
#include "llvm/ADT/StringSet.h"

#include <cmath>

using namespace osl::frontend;
using namespace mlir;
using namespace mlir::osl;

namespace {

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

bool IRGen::isPerGeometry(const Param &p) const {
  return p.intMetadataIsZero("lockgeom") || llvm::is_contained(options.perGeometryParams, p.name);
}

bool IRGen::emitShader(const ShaderDecl &shader, func::FuncOp func) {
  for (const ParamOverride &o : overrides) {
    // A struct parameter's fields are set as NAME.FIELD (nested: NAME.A.B).
    bool found = llvm::any_of(shader.params, [&](const Param &p) {
      return p.name == o.name ||
             (p.type.isStructLike() && llvm::StringRef(o.name).starts_with(p.name + "."));
    });
    // OSL warns and goes on ("attempting to set nonexistent parameter"):
    // a scene may set values for parameters a shader version dropped.
    if (!found && !diags.warning(shader.loc, "shader '" + shader.name +
                                                 "' has no parameter '" + o.name +
                                                 "': its value is ignored"))
      return false;
  }
  // Ci, the shader's closure result: written as output "Ci" if assigned.
  Var *ci = declareVar(root, "Ci", OslType(BaseType::Closure), shader.loc,
                       emptyClosure(*this, shader.loc));
  Value emptyCi = ci->val.value;
  // Ci as the shader starts: in a group, what earlier layers left
  // (osl-link-group, with lazy-globals=false).
  mlir::cast<ClosureEmptyOp>(emptyCi.getDefiningOp()).setInitialCi(true);
  Scope *paramScope = newScope(root);
  current = shaderParams = paramScope;
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
    if (p.intMetadataIsZero("allowconnect"))
      unconnectable.insert(p.name);
  if (!unconnectable.empty())
    func.walk([&](ParamOp op) {
      if (unconnectable.contains(op.getName().split('.').first))
        op.setNotConnectable(true);
    });

  current = shaderBody = newScope(paramScope);
  shaderReturned = declareFlag(current, kReturnedFlag, shader.loc);
  // Lanes a default value stopped run none of the body.
  std::optional<bool> exited = getConstBool(exitFlag->val.value);
  if (!exited) {
    llvm::StringSet<> names;
    for (const StmtPtr &s : shader.body->body)
      scanAssigned(*s, names);
    Value running = b.create<NotOp>(loc(shader.loc), exitFlag->val.value);
    auto body = [&]() -> std::optional<RValue> {
      bodyBlock = b.getInsertionBlock();
      if (!emitStmtList(shader.body->body, 0, /*tail=*/true))
        return std::nullopt;
      return RValue::voidValue();
    };
    auto nothing = []() -> std::optional<RValue> { return RValue::voidValue(); };
    if (!emitIfRegion(running, shader.loc, names, body, nothing, false))
      return false;
  } else if (!*exited) {
    bodyBlock = b.getInsertionBlock();
    if (!emitStmtList(shader.body->body, 0, /*tail=*/true))
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
      if (leaf.type.isString()) {
        // Strings are compile-time values; one a later layer reads is an
        // output of its handle, which the group links.
        if (llvm::is_contained(options.connectedOutputs, name))
          b.create<OutputOp>(loc(p.loc), name, stringHandle(leaf, p.loc));
        return;
      }
      if (leaf.type.hasElems()) {
        // One output per element (a matrix: 16, row-major); the compiler
        // merges them into one image with as many channels.
        for (size_t i = 0; i < leaf.elems.size(); ++i) {
          auto out = b.create<OutputOp>(loc(p.loc), name, leaf.elems[i]);
          out.setIndex(int64_t(i));
        }
        return;
      }
      b.create<OutputOp>(loc(p.loc), name, leaf.value);
    });
  }
  if (options.groupLayer)
    for (Var *v : globalVars)
      if (v->val.value) // in a layer only assigning a global sets it (see readVar)
        b.create<SetGlobalOp>(loc(endLoc), v->name, v->val.value);
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

/// The instance value given for parameter `name`, or null.
const ::osl::ParamOverride *IRGen::overrideOf(const std::string &name) const {
  const ParamOverride *found = nullptr;
  for (const ParamOverride &o : overrides)
    if (o.name == name)
      found = &o;
  return found;
}

/// Each value of `v` (each element of an array) becomes an osl.param named
/// `name` with that value as its default; `perGeometry` marks it as data
/// the renderer may supply per point (lockgeom=0), which a group never
/// specialises on, as OSL's optimizer does not.
void IRGen::wrapInParamOps(RValue &v, const std::string &name, bool perGeometry, SrcLoc at) {
  auto wrap = [&](Value value) {
    auto op = b.create<ParamOp>(loc(at), value.getType(), name, value);
    op.setUserdata(perGeometry);
    return op;
  };
  if (v.type.hasElems()) {
    for (size_t i = 0; i < v.elems.size(); ++i) {
      ParamOp op = wrap(v.elems[i]);
      op.setIndex(int64_t(i));
      v.elems[i] = op.getResult();
    }
  } else {
    v.value = wrap(v.value).getResult();
  }
}

bool IRGen::emitParam(const Param &p, Scope *scope, bool runDefault) {
  OslType t = p.type;
  if ((t.base == BaseType::Matrix && t.isArray()) || (t.isStructLike() && t.isArray()))
    return error(p.loc, "shader parameters of type '" + t.str() + "' are not supported yet");
  if (t.isStructLike())
    return emitStructParam(p, scope);
  if (t.isVoid())
    return error(p.loc, "parameters cannot have type 'void'");
  if (p.isOutput && t.arrayLen == 0)
    return error(p.loc, "shader output parameter '" + p.name + "' cannot be an unsized array");
  const ParamOverride *ov = overrideOf(p.name);
  if (t.isArray() && t.base == BaseType::String && ov)
    return emitStringArrayParam(p, t, ov->value, scope);
  if (ov && t.isClosure())
    return error(p.loc, "closure parameter '" + p.name + "' cannot be given a value");
  std::optional<RValue> init = paramDefault(p, t, ov, runDefault);
  if (!init)
    return false;
  RValue val = *init;
  bool connected = llvm::is_contained(options.connectedInputs, p.name);
  // Per-geometry string data (lockgeom=0) given on the command line takes
  // precedence, as numbers do below: one string for every point.
  if (t.isString() && !t.isArray() && !connected && isPerGeometry(p))
    if (std::optional<std::string> data = testshadeStringUserdata(*this, p.name))
      val = RValue::string(*data);
  // A string an upstream layer computes: a run-time handle, which the group
  // links as it links numbers (strings are otherwise compile-time values).
  if (t.isString() && connected) {
    Value handle = stringHandle(val, p.loc);
    val = RValue::runtimeString(
        b.create<ParamOp>(loc(p.loc), handle.getType(), p.name, handle).getResult());
  }
  // (A closure parameter takes no instance value, but may be connected.)
  if (t.hasElems() || !t.isString()) {
    wrapInParamOps(val, p.name, isPerGeometry(p), p.loc);
    // Per-geometry data (lockgeom=0) the renderer has takes precedence.
    if (!t.hasElems() && isPerGeometry(p))
      if (auto data = testshadeUserdata(*this, p.name, t, p.loc))
        val.value = select(data->first, data->second, val.value, p.loc);
  }
  Var *v = declareVar(scope, p.name, t, p.loc, val);
  if (!v)
    return false;
  v->isOutputParam = p.isOutput;
  v->isShaderInput = !p.isOutput;
  v->param = {p.name, isPerGeometry(p)};
  return true;
}

/// A struct parameter: instance values and connections name the fields
/// (`p.field`), so each numeric field is a parameter of its own.
bool IRGen::emitStructParam(const Param &p, Scope *scope) {
  OslType t = p.type;
  if (overrideOf(p.name))
    return error(p.loc, "struct parameter '" + p.name + "' takes values field by field ('" +
                            p.name + ".FIELD')");
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
    if (!ok)
      return;
    if (leaf.type.isString()) {
      // A compile-time string, as a string parameter: the instance value,
      // or the handle an upstream layer computes.
      if (const ParamOverride *fieldValue = overrideOf(name))
        leaf = RValue::string(fieldValue->value);
      if (llvm::is_contained(options.connectedInputs, name)) {
        Value handle = stringHandle(leaf, p.loc);
        leaf = RValue::runtimeString(
            b.create<ParamOp>(loc(p.loc), handle.getType(), name, handle).getResult());
      }
      return;
    }
    if (const ParamOverride *fieldValue = overrideOf(name)) {
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
    wrapInParamOps(leaf, name, isPerGeometry(p), p.loc);
  });
  if (!ok)
    return false;
  Var *v = declareVar(scope, p.name, t, p.loc, *c);
  if (!v)
    return false;
  v->isOutputParam = p.isOutput;
  v->isShaderInput = !p.isOutput;
  v->param = {p.name, isPerGeometry(p)};
  return true;
}

/// A string array given an instance value: comma-separated strings, each
/// optionally quoted (as a serialized group writes them); an unsized array
/// takes their count.
bool IRGen::emitStringArrayParam(const Param &p, OslType t, const std::string &value,
                                 Scope *scope) {
  llvm::SmallVector<llvm::StringRef> parts;
  llvm::StringRef(value).split(parts, ',');
  if (t.arrayLen == 0)
    t.arrayLen = int(parts.size());
  if (int(parts.size()) != t.arrayLen)
    return error(p.loc, "parameter '" + p.name + "' of type '" + t.str() + "' takes " +
                            std::to_string(t.arrayLen) + " strings, got '" + value + "'");
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
  v->isShaderInput = !p.isOutput;
  return true;
}

/// A parameter's value before osl.param: its instance value `ov`, zeros
/// (an unsized array connected to an array output; a default with side
/// effects not run), or its default. Sizes an unsized array `t`.
std::optional<RValue> IRGen::paramDefault(const Param &p, OslType &t, const ParamOverride *ov,
                                          bool runDefault) {
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
    return overrideValue(sized, ov->value);
  }
  if (int length = connectedArrayLength(p.name); t.arrayLen == 0 && length > 0) {
    // An unsized array input takes the length of the array output
    // connected to it, which gives every element.
    t.arrayLen = length;
    return zeroValue(t, p.loc);
  }
  if (!runDefault && !t.isString() && !t.isClosure() && hasSideEffects(*p.init)) {
    if (t.arrayLen == 0 && p.init->kind == ExprKind::InitList)
      t.arrayLen = int(p.init->args.size());
    return zeroValue(t, p.loc);
  }
  if (p.init->kind == ExprKind::InitList && p.init->args.empty()) {
    // `{ }`: zeros; an unsized array of one element, as OSL makes it.
    if (t.arrayLen == 0)
      t.arrayLen = 1;
    return zeroValue(t, p.loc);
  }
  return emitInitializer(*p.init, t, p.name, p.loc);
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
