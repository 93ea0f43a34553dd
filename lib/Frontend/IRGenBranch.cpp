//===- IRGenBranch.cpp - What structured control flow carries -------------===//
//
// The variables a branch or loop assigns are carried through it as values
// (flattened: a struct's or an array's leaves, a matrix's 16 floats);
// strings are carried as choices among compile-time strings, or as
// run-time handles when an arm computes one. emitIfRegion builds one
// osl.if from two arms this way.
//
//===----------------------------------------------------------------------===//
#include "IRGen.h"

#include "mlir/Dialect/Arith/IR/Arith.h"
#include "llvm/ADT/STLExtras.h"

using namespace osl::frontend;
using namespace mlir;
using namespace mlir::osl;

std::vector<Var *> IRGen::carriedVars(const llvm::StringSet<> &names) {
  std::vector<Var *> result;
  for (const auto &entry : names) {
    Var *v = lookupVar(entry.getKey());
    if (v && (!v->type.isString() || stringsAsHandles.count(v)))
      result.push_back(v);
  }
  llvm::sort(result, [](Var *a, Var *b) { return a->id < b->id; });
  return result;
}

namespace {
/// The IR values of a variable's value: one, an array's (or a matrix's)
/// elements, or a struct's fields' values in order.
/// (A struct's string fields are not among them: an if merges them apart,
/// see takeStructStrings; a loop may not change them, checkStructStrings.)
void collectLeaves(const RValue &r, std::vector<Value> &out) {
  if (r.type.isString() && !r.type.isArray())
    return;
  if (r.type.isStructLike()) {
    for (const RValue &f : r.fields)
      collectLeaves(f, out);
  } else if (r.type.hasElems()) {
    out.insert(out.end(), r.elems.begin(), r.elems.end());
  } else {
    out.push_back(r.value);
  }
}
void replaceLeaves(RValue &r, ValueRange values, size_t &k) {
  if (r.type.isString() && !r.type.isArray())
    return;
  if (r.type.isStructLike()) {
    for (RValue &f : r.fields)
      replaceLeaves(f, values, k);
  } else if (r.type.hasElems()) {
    for (Value &e : r.elems)
      e = values[k++];
  } else {
    r.value = values[k++];
  }
}
} // namespace

std::vector<Value> IRGen::flatten(const std::vector<Var *> &vs, SrcLoc l) {
  std::vector<Value> out;
  for (Var *v : vs) {
    if (!stringsAsHandles.count(v)) {
      collectLeaves(readVar(v, l), out);
      continue;
    }
    materializeStrings(v, l);
    if (v->type.isArray())
      for (const RValue &f : v->val.fields)
        out.push_back(f.value);
    else
      out.push_back(v->val.value);
  }
  return out;
}

void IRGen::unflatten(const std::vector<Var *> &vs, ValueRange values) {
  size_t k = 0;
  for (Var *v : vs) {
    if (!stringsAsHandles.count(v)) {
      replaceLeaves(v->val, values, k);
      continue;
    }
    if (v->type.isArray())
      for (RValue &f : v->val.fields)
        f = RValue::runtimeString(values[k++]);
    else
      v->val = RValue::runtimeString(values[k++]);
  }
}

void IRGen::carryStringsAsHandles(const llvm::StringSet<> &names, bool scalarsToo) {
  for (const auto &entry : names)
    if (Var *v = lookupVar(entry.getKey()))
      if (v->type.base == BaseType::String && !v->type.isStructLike() &&
          (v->type.isArray() || scalarsToo))
        stringsAsHandles.insert(v);
}

void IRGen::materializeStrings(Var *v, SrcLoc l) {
  if (v->type.isArray()) {
    for (RValue &f : v->val.fields)
      if (!f.isRuntimeString())
        f = RValue::runtimeString(stringHandle(f, l));
  } else if (!v->val.isRuntimeString()) {
    v->val = RValue::runtimeString(stringHandle(v->val, l));
  }
}

/// String variables the region may assign, with their values before it.
std::vector<std::pair<Var *, RValue>> IRGen::stringSnapshot(const llvm::StringSet<> &names) {
  std::vector<std::pair<Var *, RValue>> snap;
  for (const auto &entry : names)
    if (Var *v = lookupVar(entry.getKey()))
      if (v->type.isString() && !stringsAsHandles.count(v))
        snap.push_back({v, v->val});
  return snap;
}

bool IRGen::checkStrings(const std::vector<std::pair<Var *, RValue>> &snap, SrcLoc l,
                         llvm::StringRef what) {
  for (auto &[v, before] : snap)
    if (v->val.str != before.str || v->val.value != before.value ||
        v->val.choices != before.choices)
      return error(l, (v->name == kReturnVarName ? std::string("the string returned")
                                                 : "string variable '" + v->name + "'") +
                          " is changed inside " + what +
                          "; strings cannot depend on control flow yet");
  return true;
}

namespace {
bool sameString(const RValue &a, const RValue &b) {
  return a.str == b.str && a.value == b.value && a.choices == b.choices;
}
/// The string fields of a struct value, nested ones and the elements of
/// string arrays (fields of arrays of structs) included, in order.
void collectStringFields(const RValue &r, std::vector<RValue> &out) {
  if (r.type.isStructLike()) {
    for (const RValue &f : r.fields)
      collectStringFields(f, out);
  } else if (r.type.isString()) {
    out.push_back(r);
  } else if (r.type.isArray() && r.type.base == BaseType::String) {
    out.insert(out.end(), r.fields.begin(), r.fields.end());
  }
}
/// The inverse: sets the string fields, in collectStringFields' order.
void replaceStringFields(RValue &r, const std::vector<RValue> &strings, size_t &k) {
  if (r.type.isStructLike()) {
    for (RValue &f : r.fields)
      replaceStringFields(f, strings, k);
  } else if (r.type.isString()) {
    r = strings[k++];
  } else if (r.type.isArray() && r.type.base == BaseType::String) {
    for (RValue &f : r.fields)
      f = strings[k++];
  }
}
} // namespace

std::vector<std::pair<Var *, std::vector<RValue>>>
IRGen::structStringSnapshot(const std::vector<Var *> &carried) {
  std::vector<std::pair<Var *, std::vector<RValue>>> snap;
  for (Var *v : carried) {
    if (!v->type.isStructLike())
      continue; // strings carried as handles are leaves like numbers
    std::vector<RValue> fields;
    collectStringFields(v->val, fields);
    if (!fields.empty())
      snap.push_back({v, std::move(fields)});
  }
  return snap;
}

bool IRGen::checkStructStrings(
    const std::vector<std::pair<Var *, std::vector<RValue>>> &snap, SrcLoc l,
    llvm::StringRef what) {
  for (auto &[v, before] : snap) {
    std::vector<RValue> now;
    collectStringFields(v->val, now);
    bool same = now.size() == before.size();
    for (size_t k = 0; same && k < now.size(); ++k)
      same = sameString(now[k], before[k]);
    if (!same)
      return error(l, "a string field of '" + v->name + "' is changed inside " + what +
                          "; strings cannot depend on control flow yet");
  }
  return true;
}

std::vector<std::vector<RValue>>
IRGen::takeStructStrings(const std::vector<std::pair<Var *, std::vector<RValue>>> &snap) {
  std::vector<std::vector<RValue>> now;
  for (auto &[v, before] : snap) {
    collectStringFields(v->val, now.emplace_back());
    size_t k = 0;
    replaceStringFields(v->val, before, k);
  }
  return now;
}

namespace {
/// The compile-time strings a string may be (one, or its choices).
std::vector<std::string> candidateStrings(const RValue &s) {
  return s.isStringChoice() ? s.choices : std::vector<std::string>{s.str};
}
} // namespace

std::vector<RValue>
IRGen::takeStrings(const std::vector<std::pair<Var *, RValue>> &snap) {
  std::vector<RValue> now;
  for (auto &[v, before] : snap) {
    now.push_back(v->val);
    v->val = before;
  }
  return now;
}

IRGen::StringArms IRGen::mergeStringPair(const RValue &t, const RValue &e, Block *thenBlock,
                                         Block *elseBlock, SrcLoc l) {
  OpBuilder::InsertionGuard guard(b);
  StringArms m;
  if (t.isRuntimeString() || e.isRuntimeString()) {
    // A string computed at run time in either arm: both yield handles.
    b.setInsertionPointToEnd(thenBlock);
    m.thenValue = stringHandle(t, l);
    b.setInsertionPointToEnd(elseBlock);
    m.elseValue = stringHandle(e, l);
    return m;
  }
  // Compile-time strings: a choice among both arms' candidates.
  m.choices = candidateStrings(t);
  std::vector<std::string> elseChoices = candidateStrings(e);
  int offset = int(m.choices.size());
  m.choices.insert(m.choices.end(), elseChoices.begin(), elseChoices.end());
  b.setInsertionPointToEnd(thenBlock);
  m.thenValue = t.isStringChoice() ? t.value : constInt(0, l);
  b.setInsertionPointToEnd(elseBlock);
  m.elseValue = e.isStringChoice()
                    ? b.create<AddOp>(loc(l), e.value, constInt(offset, l)).getResult()
                    : constInt(offset, l);
  return m;
}

RValue IRGen::StringArms::merged(Value result) const {
  if (choices.empty())
    return RValue::runtimeString(result);
  RValue s = RValue::string("");
  s.choices = choices;
  s.value = result;
  return s;
}

std::vector<IRGen::StringArms>
IRGen::mergeStringArms(const std::vector<std::pair<Var *, RValue>> &snap,
                       const std::vector<RValue> &thenStrings,
                       const std::vector<RValue> &elseStrings, Block *thenBlock,
                       Block *elseBlock, SrcLoc l) {
  std::vector<StringArms> merges;
  for (size_t i = 0; i < snap.size(); ++i) {
    const RValue &t = thenStrings[i], &e = elseStrings[i];
    if (sameString(t, e)) {
      snap[i].first->val = t;
      continue;
    }
    StringArms m = mergeStringPair(t, e, thenBlock, elseBlock, l);
    m.var = snap[i].first;
    merges.push_back(m);
  }
  return merges;
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
  carryStringsAsHandles(assigned, /*scalarsToo=*/false);
  std::vector<Var *> carried = carriedVars(assigned);
  std::vector<Value> init = flatten(carried, l);
  auto strings = stringSnapshot(assigned);
  auto structStrings = structStringSnapshot(carried);
  Location mloc = loc(l);

  auto tmp = b.create<IfOp>(mloc, TypeRange{}, cond);
  Block *thenBlock = b.createBlock(&tmp.getThenRegion());
  auto tv = thenArm();
  if (!tv)
    return std::nullopt;
  std::vector<Value> thenVals = flatten(carried, l);
  std::vector<RValue> thenStrings = takeStrings(strings);
  std::vector<std::vector<RValue>> thenStructStrings = takeStructStrings(structStrings);
  unflatten(carried, init);

  Block *elseBlock = b.createBlock(&tmp.getElseRegion());
  auto ev = elseArm();
  if (!ev)
    return std::nullopt;
  std::vector<Value> elseVals = flatten(carried, l);
  std::vector<RValue> elseStrings = takeStrings(strings);
  std::vector<std::vector<RValue>> elseStructStrings = takeStructStrings(structStrings);

  OslType resultType;
  size_t resultLeaves = 0;
  if (wantValue && tv->type.isString() && ev->type.isString()) {
    // Strings: each arm's handle (an element picked per point, a[i] ? ...).
    resultType = tv->type;
    resultLeaves = 1;
    b.setInsertionPointToEnd(thenBlock);
    thenVals.push_back(stringHandle(*tv, l));
    b.setInsertionPointToEnd(elseBlock);
    elseVals.push_back(stringHandle(*ev, l));
  } else if (wantValue) {
    auto t = unify(tv->type, ev->type);
    if (!t || !(t->isNumeric() || t->isMatrix() || t->isClosure())) {
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
    collectLeaves(*ct, thenVals);
    collectLeaves(*ce, elseVals);
    resultLeaves = thenVals.size() - init.size();
  }
  // A value both arms leave alone (the same SSA value, so defined before
  // the if) is no result: the if yields only what changes.
  std::vector<Value> merged(thenVals.size());
  std::vector<Value> thenYield, elseYield;
  std::vector<Type> types;
  for (size_t i = 0; i < thenVals.size(); ++i) {
    if (thenVals[i] == elseVals[i]) {
      merged[i] = thenVals[i];
      continue;
    }
    thenYield.push_back(thenVals[i]);
    elseYield.push_back(elseVals[i]);
    Type base = getUniformType(thenVals[i].getType());
    bool varying = isVarying(thenVals[i].getType()) || isVarying(elseVals[i].getType());
    types.push_back(withUniformity(base, varying));
  }
  size_t numericResults = types.size();
  std::vector<StringArms> stringMerges =
      mergeStringArms(strings, thenStrings, elseStrings, thenBlock, elseBlock, l);
  // A struct's string fields: those the arms leave different are merged
  // as string variables are; the rest take the arms' common value.
  for (size_t i = 0; i < structStrings.size(); ++i)
    for (size_t k = 0; k < thenStructStrings[i].size(); ++k) {
      const RValue &t = thenStructStrings[i][k], &e = elseStructStrings[i][k];
      if (sameString(t, e))
        continue;
      StringArms m = mergeStringPair(t, e, thenBlock, elseBlock, l);
      m.var = structStrings[i].first;
      m.structIndex = i;
      m.field = int(k);
      stringMerges.push_back(m);
    }
  for (StringArms &m : stringMerges) {
    thenYield.push_back(m.thenValue);
    elseYield.push_back(m.elseValue);
    bool varying = isVarying(m.thenValue.getType()) || isVarying(m.elseValue.getType());
    types.push_back(withUniformity(b.getI32Type(), varying));
  }
  b.setInsertionPointToEnd(thenBlock);
  b.create<YieldOp>(mloc, thenYield);
  b.setInsertionPointToEnd(elseBlock);
  b.create<YieldOp>(mloc, elseYield);

  b.setInsertionPoint(tmp);
  auto ifOp = b.create<IfOp>(mloc, types, cond);
  ifOp.getThenRegion().takeBody(tmp.getThenRegion());
  ifOp.getElseRegion().takeBody(tmp.getElseRegion());
  tmp.erase();
  b.setInsertionPointAfter(ifOp);
  for (size_t i = 0, r = 0; i < merged.size(); ++i)
    if (!merged[i])
      merged[i] = ifOp.getResult(r++);
  unflatten(carried, ArrayRef<Value>(merged).take_front(init.size()));
  for (auto [k, m] : llvm::enumerate(stringMerges)) {
    RValue value = m.merged(ifOp.getResult(numericResults + k));
    if (m.field < 0)
      m.var->val = value;
    else
      thenStructStrings[m.structIndex][m.field] = value;
  }
  for (size_t i = 0; i < structStrings.size(); ++i) {
    size_t k = 0;
    replaceStringFields(structStrings[i].first->val, thenStructStrings[i], k);
  }
  if (!wantValue)
    return RValue::voidValue();
  // The value's leaves follow the carried variables' (one, or a matrix's 16).
  RValue result;
  result.type = resultType;
  if (resultType.isMatrix())
    result.elems.assign(merged.end() - resultLeaves, merged.end());
  else if (resultType.isString())
    return RValue::runtimeString(merged.back());
  else
    result.value = merged.back();
  return result;
}
