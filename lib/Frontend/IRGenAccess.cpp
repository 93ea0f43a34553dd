//===- IRGenAccess.cpp - Lvalues, components and array elements -----------===//
//
// A path of accesses (struct fields, triple components, array elements,
// matrix rows) from a variable: read, updated by rebuilding the value along
// the path, and indexed per point by selects over the elements (osl.pick
// for long arrays).
//
//===----------------------------------------------------------------------===//
#include "IRGen.h"

#include "mlir/Dialect/Arith/IR/Arith.h"
#include "mlir/IR/Matchers.h"
#include "llvm/ADT/STLExtras.h"
#include "llvm/ADT/StringSwitch.h"

#include <algorithm>

using namespace osl::frontend;
using namespace mlir;
using namespace mlir::osl;

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

/// The elements' constants, one list per component (one for numbers, three
/// for triples), or none when an element is not a constant.
static std::optional<std::vector<DenseElementsAttr>>
constantComponents(llvm::ArrayRef<Value> elems, int ncomp) {
  std::vector<llvm::SmallVector<Attribute>> lists(ncomp);
  for (Value v : elems) {
    Attribute attr;
    if (!matchPattern(v, m_Constant(&attr)))
      return std::nullopt;
    if (ncomp == 1) {
      lists[0].push_back(attr);
      continue;
    }
    auto triple = dyn_cast<DenseElementsAttr>(attr);
    if (!triple)
      return std::nullopt;
    auto values = llvm::to_vector(triple.getValues<Attribute>());
    for (int c = 0; c < ncomp; ++c)
      lists[c].push_back(values[c]);
  }
  std::vector<DenseElementsAttr> tables;
  for (auto &list : lists) {
    Type element = cast<TypedAttr>(list.front()).getType();
    tables.push_back(DenseElementsAttr::get(
        RankedTensorType::get({int64_t(list.size())}, element), list));
  }
  return tables;
}

std::optional<RValue> IRGen::readLongArray(const RValue &cur, const Access &a, SrcLoc l) {
  OslType element = cur.type.element();
  bool number = element.base == BaseType::Int || element.base == BaseType::Float;
  if (a.component || a.length < kTableMinLength || !(number || element.isTriple()) ||
      int(cur.elems.size()) != a.length)
    return std::nullopt;
  Location ml = loc(l);
  Value index = b.create<ClampOp>(ml, a.index, constInt(0, l), constInt(a.length - 1, l));
  bool varying = isVarying(index.getType());
  if (auto tables = constantComponents(cur.elems, number ? 1 : 3)) {
    SmallVector<Value, 3> parts;
    for (DenseElementsAttr table : *tables)
      parts.push_back(b.create<TableReadOp>(
          ml, withUniformity(table.getElementType(), varying), table, index));
    if (number)
      return RValue::num(element, parts[0]);
    return RValue::num(element, b.create<ConstructOp>(ml, parts[0], parts[1], parts[2]));
  }
  varying |= llvm::any_of(cur.elems, [](Value e) { return isVarying(e.getType()); });
  Type type = withUniformity(getUniformType(cur.elems.front().getType()), varying);
  return RValue::num(element, b.create<PickOp>(ml, type, index, cur.elems));
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
  if (auto element = readLongArray(cur, a, l))
    return *element;
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
    if (a.constIndex >= 0) {
      res.fields[a.constIndex] = newValue;
      return res;
    }
    // An element chosen per point: every element becomes a handle, and
    // each takes the new one where the index picks it.
    Value handle = stringHandle(newValue, l);
    for (int j = 0; j < a.length; ++j)
      res.fields[j] = RValue::runtimeString(select(selectsElement(a.index, j, a.length, l),
                                                   handle, stringHandle(cur.fields[j], l), l));
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
  if (lv.var->isShaderInput) {
    error(l, "cannot write to non-output parameter \"" + lv.var->name + "\"" + how.str() +
                 " (declare it 'output', or copy it to a local)");
    return false;
  }
  if (lv.var->isReadOnlyGlobal)
    return diags.warning(l, "cannot write to non-output parameter \"" + lv.var->name + "\"" +
                                how.str());
  if (!lv.var->readOnly)
    return true;
  lv.var->writtenThrough = true;
  return diags.warning(l, "cannot write to non-output parameter \"" + lv.var->name + "\"" +
                              how.str());
}

/// OSL assigns an array of another length but the same element type
/// (not structs) element by element, as far as the shorter one goes.
static bool isShorterOrLongerArray(const OslType &from, const OslType &to) {
  return from.isArray() && to.isArray() && from.arrayLen > 0 && to.arrayLen > 0 &&
         from.arrayLen != to.arrayLen && from.base == to.base && !to.isStructLike();
}

/// `target` with its first elements replaced by `source`'s; the rest keep
/// their values.
static RValue copyArrayPrefix(RValue target, const RValue &source) {
  size_t n = std::min(target.type.arrayLen, source.type.arrayLen);
  for (size_t k = 0; k < n; ++k) {
    if (k < target.elems.size() && k < source.elems.size())
      target.elems[k] = source.elems[k];
    if (k < target.fields.size() && k < source.fields.size())
      target.fields[k] = source.fields[k];
  }
  return target;
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
    // A variable is read where the operator runs, after the right-hand
    // side (OSL's ops take the variable itself): x += f(x) adds to what f
    // left in x. An element or component is read first, as OSL copies it.
    bool readAfter = e.args[0]->kind == ExprKind::Ident;
    std::optional<RValue> cur;
    if (!readAfter)
      cur = loadLValue(*lv, e.loc);
    bool arithmetic = e.name == "+=" || e.name == "-=" || e.name == "*=" || e.name == "/=";
    auto rhs = emitExpr(*e.args[1], arithmetic ? &lv->type : nullptr);
    if (!rhs)
      return std::nullopt;
    if (readAfter)
      cur = loadLValue(*lv, e.loc);
    llvm::StringRef op = llvm::StringRef(e.name).drop_back();
    if (!tryOverloadedOperator(op, e, {*cur, *rhs}, value))
      value = emitBinaryOp(op, *cur, *rhs, e.loc);
    if (!value)
      return std::nullopt;
  }
  if (lv->type.isArray() && !value->type.isArray()) {
    error(e.loc, "cannot assign '" + value->type.str() + "' to array '" + target +
                     "' of type '" + lv->type.str() + "'");
    return std::nullopt;
  }
  if (isShorterOrLongerArray(value->type, lv->type))
    value = copyArrayPrefix(loadLValue(*lv, e.loc), *value);
  auto c = coerceForAssignment(*value, lv->type, e.args[1]->begin,
                               "in assignment to '" + target + "'");
  if (!c)
    return std::nullopt;
  storeLValue(*lv, *c, e.loc);
  if (!checkNotNan(target, *c, *e.args[1], e.name, e.loc))
    return std::nullopt;
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
