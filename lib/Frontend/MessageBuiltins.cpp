//===- MessageBuiltins.cpp - setmessage, getmessage and trace ------------===//
//
// A message is a named value one layer leaves for the later layers of the
// same point. The value travels as a list of operands, one per number,
// string handle, triple or closure (a matrix's 16 floats, an array's
// elements), as osl.print's operands do; osl.get_message gives back the
// same list, which is put together again as the destination's type.
//
// testshade's renderer has no geometry: trace() hits nothing and
// getmessage("trace", ...) finds nothing, which is what OSL's testshade
// answers.
//
//===----------------------------------------------------------------------===//
#include "IRGen.h"

using namespace mlir;
using namespace mlir::osl;

namespace osl::frontend {
namespace {

/// The message name: known when the shader is compiled (or chosen among
/// such names per point).
std::optional<RValue> messageName(IRGen &g, const Expr &arg, llvm::StringRef function) {
  auto name = g.emitExpr(arg);
  if (!name)
    return std::nullopt;
  if (!name->type.isString()) {
    g.error(arg.loc, "'" + function + "' needs a string message name, got '" +
                         name->type.str() + "'");
    return std::nullopt;
  }
  if (!g.compileTimeStrings(*name, arg.loc, "the message name"))
    return std::nullopt;
  return name;
}

std::optional<RValue> emitSetMessage(IRGen &g, const Expr &call) {
  if (call.args.size() != 2) {
    g.error(call.loc, "wrong arguments to 'setmessage'; candidates: void setmessage(string "
                      "name, T value)");
    return std::nullopt;
  }
  auto name = messageName(g, *call.args[0], "setmessage");
  if (!name)
    return std::nullopt;
  auto value = g.emitExpr(*call.args[1]);
  if (!value)
    return std::nullopt;
  auto ops = rowOperands(g, *value, call.args[1]->loc, "setmessage");
  if (!ops)
    return std::nullopt;
  auto done = g.forEachStringChoice(
      *name, call.loc,
      [&](const std::string &n) {
        g.builder().create<SetMessageOp>(g.loc(call.loc), n, value->type.str(), ops->kinds,
                                         ops->values, Value());
        return std::optional<RValue>(RValue::voidValue());
      },
      {}, /*wantValue=*/false);
  if (!done)
    return std::nullopt;
  return RValue::voidValue();
}

std::optional<RValue> emitGetMessage(IRGen &g, const Expr &call) {
  size_t n = call.args.size();
  if (n != 2 && n != 3) {
    g.error(call.loc, "wrong arguments to 'getmessage'; candidates: int getmessage(string "
                      "name, output T value); int getmessage(string source, string name, "
                      "output T value)");
    return std::nullopt;
  }
  std::string source;
  if (n == 3) {
    auto s = g.emitExpr(*call.args[0]);
    if (!s)
      return std::nullopt;
    if (!s->isKnownString()) {
      g.valueError(call.args[0]->loc, "'getmessage' needs its message source known when the "
                                      "shader is compiled");
      return std::nullopt;
    }
    source = s->str;
  }
  auto name = messageName(g, *call.args[n - 2], "getmessage");
  if (!name)
    return std::nullopt;
  auto dest = g.emitLValue(*call.args[n - 1]);
  if (!dest)
    return std::nullopt;
  RValue current = g.loadLValue(*dest, call.loc);
  auto ops = rowOperands(g, current, call.args[n - 1]->loc, "getmessage");
  if (!ops)
    return std::nullopt;
  if (!source.empty()) // a trace's messages: testshade traces nothing
    return RValue::num(OslType(BaseType::Int), g.constInt(0, call.loc));
  OpBuilder &b = g.builder();
  SmallVector<Type> types;
  for (Value v : ops->values)
    types.push_back(VaryingType::get(getUniformType(v.getType())));
  Type foundType = VaryingType::get(b.getI32Type());
  // A name chosen per point: each choice stores into the destination under
  // its own condition, and the destination merges per lane.
  llvm::StringSet<> assigned;
  assigned.insert(rootName(*call.args[n - 1]));
  bool stored = true;
  auto found = g.forEachStringChoice(
      *name, call.loc,
      [&](const std::string &nm) {
        auto get = b.create<GetMessageOp>(g.loc(call.loc), foundType, types, nm,
                                          current.type.str(), ops->kinds, ops->values, Value());
        stored &= g.storeLValue(*dest, fromRowOperands(current, get.getValues()), call.loc);
        return std::optional<RValue>(RValue::num(OslType(BaseType::Int), get.getFound()));
      },
      assigned);
  if (!found || !stored)
    return std::nullopt;
  return found;
}

/// trace(pos, dir, options...): testshade's renderer has no geometry, so
/// no ray hits anything.
std::optional<RValue> emitTrace(IRGen &g, const Expr &call) {
  auto evaluated = emitArgs(g, call);
  if (!evaluated)
    return std::nullopt;
  std::vector<RValue> &args = *evaluated;
  bool ok = args.size() >= 2 && args.size() % 2 == 0 && args[0].type.isTriple() &&
            args[1].type.isTriple();
  for (size_t k = 2; ok && k < args.size(); k += 2)
    ok = args[k].isKnownString();
  if (!ok) {
    g.error(call.loc, "wrong arguments to 'trace'; candidates: int trace(point pos, vector "
                      "dir, ...) with (\"name\", value) options");
    return std::nullopt;
  }
  return RValue::num(OslType(BaseType::Int), g.constInt(0, call.loc));
}

} // namespace

std::optional<RValue> emitMessageBuiltin(IRGen &g, const Expr &call, bool &known) {
  known = true;
  if (call.name == "setmessage")
    return emitSetMessage(g, call);
  if (call.name == "getmessage")
    return emitGetMessage(g, call);
  if (call.name == "trace")
    return emitTrace(g, call);
  known = false;
  return std::nullopt;
}

} // namespace osl::frontend
