//===- StringBuiltins.cpp - String functions on run-time strings ---------===//
//
// format, concat, substr and the functions that read strings (strlen,
// hash, startswith, endswith, getchar, stoi, stof, regex_search,
// regex_match) become one osl.string_call each, on string handles: any
// compile-time string or string choice among the operands is interned
// (IRGen::stringHandle). The call is uniform when its operands are, so a
// function of compile-time strings runs once per batch.
//
// A format string or regular expression known when the shader is compiled
// is checked then, so its errors point at the call. A call whose operands
// are all known then (concat of string parameters, format of constants) is
// folded by running the string functions the runtime runs (OslStrings), so
// its result is a compile-time string that can name a texture, a noise or a
// space.
//
//===----------------------------------------------------------------------===//
#include "IRGen.h"
#include "OslAbi/Print.h"
#include "OslStrings/StringFunctions.h"

#include "llvm/ADT/StringSwitch.h"

#include <cstring>

using namespace osl::frontend;
using namespace mlir;
using namespace mlir::osl;

namespace {

/// Signatures, for errors.
const char *usage(llvm::StringRef name) {
  return llvm::StringSwitch<const char *>(name)
      .Case("concat", "string concat(string, string[, string... up to 6])")
      .Case("format", "string format(string fmt, ...)")
      .Case("strlen", "int strlen(string)")
      .Case("hash", "int hash(string)")
      .Case("startswith", "int startswith(string, string prefix)")
      .Case("endswith", "int endswith(string, string suffix)")
      .Case("getchar", "int getchar(string, int index)")
      .Case("substr", "string substr(string, int start [, int length])")
      .Case("stoi", "int stoi(string)")
      .Case("stof", "float stof(string)")
      .Case("regex_search", "int regex_search(string subject, string regex)")
      .Case("regex_match", "int regex_match(string subject, string regex)")
      .Case("dict_next", "int dict_next(int nodeID)")
      .Case("printf", "void printf(string fmt, ...)")
      .Case("fprintf", "void fprintf(string filename, string fmt, ...)")
      .Case("warning", "void warning(string fmt, ...)")
      .Case("error", "void error(string fmt, ...)")
      .Default("");
}

/// Builds one string call from a call's arguments.
class StringCall {
public:
  StringCall(IRGen &g, const Expr &call) : g(g), call(call) {}

  std::optional<RValue> emit();
  /// printf, fprintf, warning and error: one osl.print.
  std::optional<RValue> emitPrint();

private:
  /// hash of numbers and triples (osl.hash); emit() hashes strings.
  std::optional<RValue> emitNumericHash();
  bool emitArgs();
  /// Adds one formatted value: a number, triple or string as one operand;
  /// an array's elements or a matrix's 16 values each, with the count in
  /// `valueCounts` so that their conversion is repeated.
  bool addFormatted(size_t k);
  /// The format string operand at `formatIndex`, its conversions repeated
  /// for arrays and matrices, checked against the values' kinds.
  bool checkFormat(size_t formatIndex);
  bool wrong() {
    return g.error(call.loc, "wrong arguments to '" + call.name + "'; candidates: " +
                                 usage(call.name));
  }
  /// Adds argument `k` as an operand of kind `kind` (s, i, or for
  /// format's values whatever it is).
  bool addOperand(size_t k, char kind);
  bool addFormatValue(size_t k);
  bool checkConstantOperands();
  /// The operands' 32-bit rows when every operand is known now.
  /// The operands' values when all are known now (no triples).
  std::optional<std::vector<::osl::StringValue>> knownValues();
  RValue fold(const std::vector<::osl::StringValue> &values, int32_t code);
  /// The operands as IR values (strings as handles).
  SmallVector<Value> materialize();

  IRGen &g;
  const Expr &call;
  std::vector<RValue> args;
  /// One per operand (coerced); `kinds` says how each is passed.
  std::vector<RValue> operands;
  std::vector<SrcLoc> operandLocs;
  std::string kinds;
  /// Operands per formatted value, when an array or matrix is among them.
  std::vector<int> valueCounts;
};

bool StringCall::addOperand(size_t k, char kind) {
  const RValue &v = args[k];
  SrcLoc l = call.args[k]->begin;
  if (kind == 's') {
    if (!v.type.isString())
      return g.error(l, "'" + call.name + "' expects a string here, got '" + v.type.str() +
                            "'");
    operands.push_back(v);
  } else {
    auto c = g.coerce(v, OslType(BaseType::Int), l, "for '" + call.name + "'");
    if (!c)
      return false;
    operands.push_back(*c);
  }
  operandLocs.push_back(l);
  kinds += kind;
  return true;
}

/// One value to format: a string, an int, a float or a triple.
bool StringCall::addFormatValue(size_t k) {
  const RValue &v = args[k];
  SrcLoc l = call.args[k]->begin;
  if (v.type.isString())
    return addOperand(k, 's');
  if (v.type.isClosure() && !v.type.isArray() &&
      (::osl::printStreamCode(call.name) >= 0 || call.name == "format")) {
    // Printed as OSL prints closures (the runtime walks the tree).
    operands.push_back(v);
    operandLocs.push_back(l);
    kinds += 'k';
    return true;
  }
  if (v.type.isArray() || !(v.type.isNumeric() || v.type.base == BaseType::Bool))
    return g.error(l, "'" + call.name + "' cannot format a value of type '" + v.type.str() +
                          "' yet");
  OslType as = v.type.isTriple() ? v.type
               : v.type.isFloat() ? OslType(BaseType::Float)
                                  : OslType(BaseType::Int);
  auto c = g.coerce(v, as, l, "for '" + call.name + "'");
  if (!c)
    return false;
  operands.push_back(*c);
  operandLocs.push_back(l);
  kinds += as.isTriple() ? 't' : as.isFloat() ? 'f' : 'i';
  return true;
}

std::optional<std::vector<::osl::StringValue>> StringCall::knownValues() {
  std::vector<::osl::StringValue> values;
  for (auto [v, kind] : llvm::zip(operands, kinds)) {
    ::osl::StringValue &known = values.emplace_back();
    known.kind = kind;
    if (kind == 's') {
      if (!v.isKnownString())
        return std::nullopt;
      known.s = v.str; // `operands` outlives the fold
    } else if (kind == 'i') {
      auto k = IRGen::getConstInt(v.value);
      if (!k)
        return std::nullopt;
      known.i = int32_t(*k);
    } else if (kind == 'f') {
      auto k = IRGen::getConstScalar(v.value);
      if (!k)
        return std::nullopt;
      known.f[0] = float(*k);
    } else {
      return std::nullopt; // triples are not folded
    }
  }
  return values;
}

/// Runs the call now, with the string functions the runtime runs. Its
/// errors (format, regex) were reported by checkConstantOperands, so it
/// cannot fail here.
RValue StringCall::fold(const std::vector<::osl::StringValue> &values, int32_t code) {
  std::string error;
  ::osl::StringResult result = ::osl::evalStringFunction(code, values, error);
  switch (::osl::kStringFunctions[code].result) {
  case 's':
    return RValue::string(result.text);
  case 'f': {
    float f;
    std::memcpy(&f, &result.bits, sizeof f);
    return RValue::num(OslType(BaseType::Float), g.constFloat(f, call.loc));
  }
  default:
    return RValue::num(OslType(BaseType::Int), g.constInt(result.bits, call.loc));
  }
}

SmallVector<Value> StringCall::materialize() {
  SmallVector<Value> values;
  for (auto [v, kind, l] : llvm::zip(operands, kinds, operandLocs))
    values.push_back(kind == 's' ? g.stringHandle(v, l) : v.value);
  return values;
}

/// A regular expression known now is checked now (reported at `l`).
bool checkKnownRegex(IRGen &g, const RValue &regex, SrcLoc l) {
  if (!regex.isKnownString())
    return true;
  std::string why = ::osl::regexError(regex.str);
  return why.empty() || g.error(l, why);
}

/// Regular expressions known now are checked now (format strings are, by
/// checkFormat).
bool StringCall::checkConstantOperands() {
  if (call.name == "regex_search" || call.name == "regex_match")
    return checkKnownRegex(g, args[1], call.args[1]->begin);
  return true;
}

bool StringCall::emitArgs() {
  // A variable argument is read where the call runs (OSL passes the
  // variable): printf("%d %d", n, f(n)) prints what f left in n.
  bool effects = llvm::any_of(call.args, [](const ExprPtr &a) { return mayHaveSideEffects(*a); });
  auto readLast = [&](const Expr &a) {
    return effects && g.isVariableRead(a);
  };
  std::vector<std::optional<RValue>> values(call.args.size());
  for (bool last : {false, true})
    for (size_t k = 0; k < call.args.size(); ++k) {
      if (readLast(*call.args[k]) != last)
        continue;
      if (!(values[k] = g.emitExpr(*call.args[k])))
        return false;
    }
  for (auto &v : values)
    args.push_back(*v);
  return true;
}

bool StringCall::checkFormat(size_t formatIndex) {
  RValue &format = operands[formatIndex];
  bool repeats = llvm::any_of(valueCounts, [](int n) { return n != 1; });
  SrcLoc l = call.args[formatIndex]->begin;
  if (format.isKnownString()) {
    if (repeats)
      format = RValue::string(::osl::repeatConversions(format.str, valueCounts));
    std::string why =
        ::osl::formatError(format.str, llvm::StringRef(kinds).drop_front(formatIndex + 1));
    return why.empty() || g.error(l, why);
  }
  return !repeats || g.error(l, "an array or matrix can be formatted only with a format "
                                "string known when the shader is compiled");
}

bool StringCall::addFormatted(size_t k) {
  const RValue &v = args[k];
  if (!v.type.hasElems() || v.type.isStructLike()) {
    valueCounts.push_back(1);
    return addFormatValue(k);
  }
  SrcLoc l = call.args[k]->begin;
  OslType elem = v.type.base == BaseType::Matrix ? OslType(BaseType::Float) : v.type.element();
  if (elem.isString()) {
    for (const RValue &f : v.fields)
      operands.push_back(f), operandLocs.push_back(l), kinds += 's';
    valueCounts.push_back(int(v.fields.size()));
    return true;
  }
  if (!elem.isNumeric() && !elem.isBool())
    return g.error(l, "'" + call.name + "' cannot format a value of type '" + v.type.str() + "'");
  for (Value e : v.elems) {
    operands.push_back(RValue::num(elem.isBool() ? OslType(BaseType::Int) : elem, e));
    operandLocs.push_back(l);
    kinds += elem.isTriple() ? 't' : elem.isFloat() ? 'f' : 'i';
  }
  valueCounts.push_back(int(v.elems.size()));
  return true;
}

std::optional<RValue> StringCall::emitPrint() {
  if (!emitArgs())
    return std::nullopt;
  int32_t stream = ::osl::printStreamCode(call.name);
  bool namesShader = ::osl::kPrintStreams[stream].namesShader;
  // The leading operands the call itself gives.
  size_t leading = std::strlen(::osl::kPrintStreams[stream].operands) - namesShader;
  if (args.size() < leading)
    return wrong(), std::nullopt;
  for (size_t k = 0; k < leading; ++k)
    if (!addOperand(k, 's'))
      return std::nullopt;
  for (size_t k = leading; k < args.size(); ++k)
    if (!addFormatted(k))
      return std::nullopt;
  if (!checkFormat(leading - 1))
    return std::nullopt;
  if (namesShader) {
    operands.insert(operands.begin(), RValue::string(g.shaderName().str()));
    operandLocs.insert(operandLocs.begin(), call.loc);
    kinds.insert(kinds.begin(), 's');
  }
  g.builder().create<PrintOp>(g.loc(call.loc), call.name, kinds, materialize(), Value());
  return RValue::voidValue();
}

/// hash(int), hash(float), hash(float, float), hash(point), hash(point,
/// float): osl.hash of the keys (ints become floats where OSL's overloads
/// take floats).
std::optional<RValue> StringCall::emitNumericHash() {
  auto isKey = [](const OslType &t, bool triple) {
    return !t.isArray() && (t.isInt() || t.isFloat() || (triple && t.isTriple()));
  };
  bool ok = args.size() <= 2 && isKey(args[0].type, true) &&
            (args.size() == 1 || isKey(args[1].type, false));
  if (!ok) {
    g.error(call.loc, "wrong arguments to 'hash'; candidates: int hash(string), int hash(int), "
                      "int hash(float), int hash(float, float), int hash(point), "
                      "int hash(point, float)");
    return std::nullopt;
  }
  SmallVector<Value> keys;
  bool varying = false;
  for (size_t k = 0; k < args.size(); ++k) {
    RValue key = args[k];
    if (key.type.isInt() && args.size() == 2) {
      auto f = g.coerce(key, OslType(BaseType::Float), call.args[k]->loc, "");
      if (!f)
        return std::nullopt;
      key = *f;
    }
    varying |= isVarying(key.value.getType());
    keys.push_back(key.value);
  }
  OpBuilder &b = g.builder();
  Type result = withUniformity(b.getI32Type(), varying);
  return RValue::num(OslType(BaseType::Int), b.create<HashOp>(g.loc(call.loc), result, keys));
}

std::optional<RValue> StringCall::emit() {
  if (!emitArgs())
    return std::nullopt;
  int32_t code = ::osl::stringFunctionCode(call.name);
  llvm::StringRef name = call.name;
  // Operand kinds by position; format's values take their own kinds.
  std::string pattern = ::osl::kStringFunctions[code].operands;
  bool ok = true;
  if (name == "format") {
    if (args.empty())
      ok = wrong();
    else
      ok = addOperand(0, 's');
    for (size_t k = 1; ok && k < args.size(); ++k)
      ok = addFormatted(k);
    ok = ok && checkFormat(0);
  } else if (name == "concat") {
    // OSL's concat takes 2 strings, and stdosl.h's overloads 3 to 6.
    if (args.size() < 2 || args.size() > 6)
      ok = wrong();
    for (size_t k = 0; ok && k < args.size(); ++k)
      ok = addOperand(k, 's');
  } else if (name == "hash" && !args.empty() && !args[0].type.isString()) {
    return emitNumericHash();
  } else {
    size_t required = 0, optional = 0;
    for (char c : pattern) {
      if (c != '?') {
        ++required;
        continue;
      }
      --required; // the letter before it is optional
      ++optional;
    }
    if (args.size() < required || args.size() > required + optional)
      ok = wrong();
    for (size_t k = 0; ok && k < args.size(); ++k)
      ok = addOperand(k, pattern[k]);
  }
  if (!ok || !checkConstantOperands())
    return std::nullopt;
  // (A dictionary is read when the shader runs: its node ids belong to that
  // process.)
  if (auto values = knownValues(); values && !::osl::isDictionaryFunction(name))
    return fold(*values, code);

  OpBuilder &b = g.builder();
  char result = ::osl::kStringFunctions[code].result;
  Type type = result == 'f' ? Type(b.getF32Type()) : Type(b.getI32Type());
  Value v = b.create<StringCallOp>(g.loc(call.loc), type, name, kinds, materialize());
  if (result == 's')
    return RValue::runtimeString(v);
  return RValue::num(OslType(result == 'f' ? BaseType::Float : BaseType::Int), v);
}

/// split(str, results[N], sep = "", maxsplit = N): the runtime counts the
/// pieces (at most maxsplit, kept within [0, N], as OSL's) and hands out
/// each; results[k] takes piece k where k is below the count and keeps its
/// value elsewhere. Returns the count.
std::optional<RValue> emitSplit(IRGen &g, const Expr &call) {
  const char *usageText = "int split(string str, output string results[], string sep, "
                          "int maxsplit), with sep and maxsplit optional";
  size_t n = call.args.size();
  if (n < 2 || n > 4) {
    g.error(call.loc, llvm::Twine("wrong arguments to 'split'; candidates: ") + usageText);
    return std::nullopt;
  }
  auto str = g.emitExpr(*call.args[0]);
  if (!str)
    return std::nullopt;
  auto dest = g.emitLValue(*call.args[1]);
  if (!dest)
    return std::nullopt;
  RValue sep = RValue::string("");
  if (n > 2) {
    auto s = g.emitExpr(*call.args[2]);
    if (!s)
      return std::nullopt;
    sep = *s;
  }
  Value maxsplit; // the results' length unless given
  if (n > 3) {
    auto m = g.emitExpr(*call.args[3]);
    if (!m)
      return std::nullopt;
    auto c = g.coerce(*m, OslType(BaseType::Int), call.args[3]->begin, "for 'split'");
    if (!c)
      return std::nullopt;
    maxsplit = c->value;
  }
  if (!str->type.isString() || !sep.type.isString() || dest->type.base != BaseType::String ||
      dest->type.arrayLen <= 0) {
    g.error(call.loc, llvm::Twine("wrong arguments to 'split'; candidates: ") + usageText);
    return std::nullopt;
  }
  OpBuilder &b = g.builder();
  Location l = g.loc(call.loc);
  Value strHandle = g.stringHandle(*str, call.loc);
  Value sepHandle = g.stringHandle(sep, call.loc);
  int length = dest->type.arrayLen;
  Value lengthValue = g.constInt(length, call.loc);
  if (!maxsplit)
    maxsplit = lengthValue;
  Value count = b.create<StringCallOp>(l, b.getI32Type(), "split:count", "ssii",
                                       ValueRange{strHandle, sepHandle, maxsplit, lengthValue})
                    .getResult();
  RValue results = g.loadLValue(*dest, call.loc);
  std::optional<int64_t> knownMaxsplit = IRGen::getConstInt(maxsplit);
  if (str->isKnownString() && sep.isKnownString() && knownMaxsplit) {
    // Known operands: split now and assign the whole array, the elements
    // past the pieces "" (OSL's optimizer folds split so; its run-time
    // split keeps them, as the code below does).
    auto known = [&](const char *function, int32_t last) {
      std::vector<::osl::StringValue> values(5);
      values[0].kind = values[1].kind = 's';
      values[0].s = str->str;
      values[1].s = sep.str;
      values[2].kind = values[3].kind = values[4].kind = 'i';
      values[2].i = int32_t(*knownMaxsplit);
      values[3].i = length;
      values[4].i = last;
      std::string error;
      return ::osl::evalStringFunction(::osl::stringFunctionCode(function), values, error);
    };
    int32_t pieces = known("split:count", length).bits; // (its fifth operand unused)
    for (int k = 0; k < length; ++k)
      results.fields[size_t(k)] = RValue::string(k < pieces ? known("split:piece", k).text : "");
    g.storeLValue(*dest, results, call.loc);
    return RValue::num(OslType(BaseType::Int), g.constInt(pieces, call.loc));
  }
  for (int k = 0; k < length; ++k) {
    Value piece = b.create<StringCallOp>(
                       l, b.getI32Type(), "split:piece", "ssiii",
                       ValueRange{strHandle, sepHandle, maxsplit, lengthValue,
                                  g.constInt(k, call.loc)})
                      .getResult();
    Value filled = g.cmp("lt", g.constInt(k, call.loc), count, call.loc);
    Value old = g.stringHandle(results.fields[size_t(k)], call.loc);
    results.fields[size_t(k)] = RValue::runtimeString(g.select(filled, piece, old, call.loc));
  }
  g.storeLValue(*dest, results, call.loc);
  return RValue::num(OslType(BaseType::Int), count);
}

/// regex_search / regex_match(subject, results[N], regex): the match's
/// result, and results[k] from the runtime's entry k (the groups' begin and
/// end positions; see "regex:result").
std::optional<RValue> emitRegexWithResults(IRGen &g, const Expr &call) {
  bool full = call.name == "regex_match";
  auto subject = g.emitExpr(*call.args[0]);
  if (!subject)
    return std::nullopt;
  auto dest = g.emitLValue(*call.args[1]);
  if (!dest)
    return std::nullopt;
  auto regex = g.emitExpr(*call.args[2]);
  if (!regex)
    return std::nullopt;
  if (!subject->type.isString() || !regex->type.isString() ||
      dest->type.base != BaseType::Int || dest->type.arrayLen <= 0) {
    g.error(call.loc, "wrong arguments to '" + call.name + "'; candidates: int " + call.name +
                          "(string subject, string regex); int " + call.name +
                          "(string subject, output int results[], string regex)");
    return std::nullopt;
  }
  if (!checkKnownRegex(g, *regex, call.args[2]->begin))
    return std::nullopt;
  OpBuilder &b = g.builder();
  Location l = g.loc(call.loc);
  Value subjectHandle = g.stringHandle(*subject, call.loc);
  Value regexHandle = g.stringHandle(*regex, call.loc);
  Value found = b.create<StringCallOp>(l, b.getI32Type(), call.name, "ss",
                                       ValueRange{subjectHandle, regexHandle})
                    .getResult();
  RValue results = g.loadLValue(*dest, call.loc);
  for (size_t k = 0; k < results.elems.size(); ++k)
    results.elems[k] =
        b.create<StringCallOp>(l, b.getI32Type(), "regex:result", "ssiii",
                               ValueRange{subjectHandle, regexHandle,
                                          g.constInt(full ? 1 : 0, call.loc),
                                          g.constInt(int(k), call.loc), results.elems[k]})
            .getResult();
  g.storeLValue(*dest, results, call.loc);
  return RValue::num(OslType(BaseType::Int), found);
}

/// dict_find(string dictionary, string query) or dict_find(int nodeID,
/// string query): the first matching node's id, 0 if none, -1 if the
/// dictionary cannot be read.
std::optional<RValue> emitDictFind(IRGen &g, const Expr &call) {
  const char *usageText = "int dict_find(string dictionary, string query); "
                          "int dict_find(int nodeID, string query)";
  auto evaluated = emitArgs(g, call);
  if (!evaluated)
    return std::nullopt;
  std::vector<RValue> &args = *evaluated;
  if (args.size() != 2 || !args[1].type.isString() ||
      !(args[0].type.isString() || args[0].type.isInt())) {
    g.error(call.loc, llvm::Twine("wrong arguments to 'dict_find'; candidates: ") + usageText);
    return std::nullopt;
  }
  OpBuilder &b = g.builder();
  bool below = args[0].type.isInt();
  Value first = below ? args[0].value : g.stringHandle(args[0], call.args[0]->begin);
  Value found = b.create<StringCallOp>(
                     g.loc(call.loc), b.getI32Type(), below ? "dict_find:node" : "dict_find",
                     below ? "is" : "ss",
                     ValueRange{first, g.stringHandle(args[1], call.args[1]->begin)})
                    .getResult();
  return RValue::num(OslType(BaseType::Int), found);
}

/// dict_value(int nodeID, string attribname, output T value): the node's
/// attribute as an int, float, string, triple or matrix (numbers separated
/// by spaces or commas). Returns 1 and writes value when the attribute
/// exists and reads as T; else 0, and value keeps its old value.
std::optional<RValue> emitDictValue(IRGen &g, const Expr &call) {
  const char *usageText = "int dict_value(int nodeID, string attribname, output "
                          "int|float|string|triple|matrix value)";
  if (call.args.size() != 3) {
    g.error(call.loc, llvm::Twine("wrong arguments to 'dict_value'; candidates: ") + usageText);
    return std::nullopt;
  }
  auto node = g.emitExpr(*call.args[0]);
  if (!node)
    return std::nullopt;
  auto name = g.emitExpr(*call.args[1]);
  if (!name)
    return std::nullopt;
  auto dest = g.emitLValue(*call.args[2]);
  if (!dest)
    return std::nullopt;
  OslType t = dest->type;
  if (!node->type.isInt() || !name->type.isString() ||
      !(t.isInt() || t.isFloat() || t.isString() || t.isTriple() || t.isMatrix())) {
    g.error(call.loc, llvm::Twine("wrong arguments to 'dict_value'; candidates: ") + usageText);
    return std::nullopt;
  }
  OpBuilder &b = g.builder();
  Location l = g.loc(call.loc);
  Value nameHandle = g.stringHandle(*name, call.args[1]->begin);
  int what = t.isInt() ? 0 : t.isFloat() ? 1 : t.isString() ? 2 : t.isTriple() ? 3 : 16;
  // One string call on (node, name[, k]): "dict_value:found|int|float|string".
  auto dictCall = [&](llvm::StringRef function, Type type, std::optional<int> k = {}) {
    SmallVector<Value> operands = {node->value, nameHandle};
    if (k)
      operands.push_back(g.constInt(*k, call.loc));
    return b.create<StringCallOp>(l, type, function, k ? "isi" : "is", operands).getResult();
  };
  Value found = dictCall("dict_value:found", b.getI32Type(), what);
  Value ok = g.cmp("ne", found, g.constInt(0, call.loc), call.loc);
  auto floatK = [&](int k) { return dictCall("dict_value:float", b.getF32Type(), k); };
  RValue old = g.loadLValue(*dest, call.loc);
  RValue value = old;
  if (t.isInt()) {
    value.value = g.select(ok, dictCall("dict_value:int", b.getI32Type()), old.value, call.loc);
  } else if (t.isString()) {
    value = RValue::runtimeString(g.select(ok, dictCall("dict_value:string", b.getI32Type()),
                                           g.stringHandle(old, call.loc), call.loc));
  } else if (t.isFloat()) {
    value.value = g.select(ok, floatK(0), old.value, call.loc);
  } else if (t.isTriple()) {
    Value v = b.create<ConstructOp>(l, floatK(0), floatK(1), floatK(2));
    value.value = g.select(ok, v, old.value, call.loc);
  } else { // a matrix: 16 floats, row-major
    for (int k = 0; k < 16; ++k)
      value.elems[size_t(k)] = g.select(ok, floatK(k), old.elems[size_t(k)], call.loc);
  }
  g.storeLValue(*dest, value, call.loc);
  return RValue::num(OslType(BaseType::Int), found);
}

} // namespace

namespace osl::frontend {

std::optional<RValue> emitStringBuiltin(IRGen &g, const Expr &call, bool &known) {
  if (call.name == "dict_find") {
    known = true;
    return emitDictFind(g, call);
  }
  if (call.name == "dict_value") {
    known = true;
    return emitDictValue(g, call);
  }
  if (call.name == "split") {
    known = true;
    return emitSplit(g, call);
  }
  if ((call.name == "regex_search" || call.name == "regex_match") && call.args.size() == 3) {
    known = true;
    return emitRegexWithResults(g, call);
  }
  known = ::osl::stringFunctionCode(call.name) >= 0;
  if (known)
    return StringCall(g, call).emit();
  known = ::osl::printStreamCode(call.name) >= 0;
  if (known)
    return StringCall(g, call).emitPrint();
  return std::nullopt;
}

} // namespace osl::frontend
