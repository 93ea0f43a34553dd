//===- PointCloudBuiltins.cpp - pointcloud_search, _get and _write --------===//
//
// Each is one osl.pointcloud op (OslAbi/PointCloud.h lays out its operands):
// the inputs, then the current elements of the output arrays, which come
// back as the op's values and are stored to the arrays. As OSL's, a search
// fills at most as many elements as its shortest array holds, and a get at
// most as many as its index and data arrays hold.
//
//===----------------------------------------------------------------------===//
#include "IRGen.h"

#include "OslAbi/PointCloud.h"

using namespace mlir;
using namespace mlir::osl;

namespace osl::frontend {
namespace {

/// An output array of a lookup: where it is, its value now, and its rows.
struct OutputArray {
  LValue place;
  RValue current;
  RowOperands rows;
};

/// The attribute name at `arg`, known when the shader is compiled.
std::optional<std::string> attributeName(IRGen &g, const Expr &arg, llvm::StringRef function) {
  auto name = g.emitExpr(arg);
  if (!name)
    return std::nullopt;
  if (!name->isKnownString()) {
    g.error(arg.loc, "'" + function +
                         "' needs attribute names known when the shader is "
                         "compiled, got " +
                         (name->type.isString() ? std::string("one computed at run time")
                                                : "'" + name->type.str() + "'"));
    return std::nullopt;
  }
  if (name->str.find(';') != std::string::npos) {
    g.error(arg.loc, "'" + function + "': an attribute name cannot hold ';'");
    return std::nullopt;
  }
  return name->str;
}

/// The array `arg` names as an output of `function`; nullopt after
/// reporting it is not an array of int, float, triple or string.
std::optional<OutputArray> outputArray(IRGen &g, const Expr &arg, llvm::StringRef function,
                                       llvm::StringRef attribute) {
  auto place = g.emitLValue(arg);
  if (!place)
    return std::nullopt;
  const OslType &t = place->type;
  OslType element = t.isArray() ? t.element() : t;
  if (!t.isArray() ||
      !(element.isInt() || element.isFloat() || element.isTriple() || element.isString())) {
    g.error(arg.loc, "'" + function + "' needs an array of int, float, triple or string for \"" +
                         attribute + "\", got '" + t.str() + "'");
    return std::nullopt;
  }
  RValue current = g.loadLValue(*place, arg.loc);
  auto rows = rowOperands(g, current, arg.loc, function);
  if (!rows)
    return std::nullopt;
  if (rows->values.empty()) {
    g.error(arg.loc,
            "'" + function + "' needs an array of at least one element for \"" + attribute + "\"");
    return std::nullopt;
  }
  return OutputArray{*place, current, std::move(*rows)};
}

/// The file name operand (a string handle).
std::optional<Value> fileName(IRGen &g, const Expr &arg, llvm::StringRef function) {
  auto file = g.emitExpr(arg);
  if (!file)
    return std::nullopt;
  if (!file->type.isString()) {
    g.error(arg.loc, "'" + function + "' needs a string file name, got '" + file->type.str() + "'");
    return std::nullopt;
  }
  return g.stringHandle(*file, arg.loc);
}

/// Input `what` of `function` converted to `type`, nullopt after reporting.
std::optional<Value> input(IRGen &g, const Expr &arg, OslType type, llvm::StringRef function,
                           llvm::StringRef what) {
  auto v = g.emitExpr(arg, &type);
  if (!v)
    return std::nullopt;
  auto converted = g.coerce(*v, type, arg.loc, "for " + what + " of '" + function + "'");
  if (!converted)
    return std::nullopt;
  return converted->value;
}

/// Builds the op and stores its values to `outputs`; returns its status.
RValue emitLookup(IRGen &g, const Expr &call, llvm::StringRef function,
                  const std::vector<PointCloudArray> &layout, std::string kinds,
                  SmallVector<Value> inputs, std::vector<OutputArray> &outputs) {
  OpBuilder &b = g.builder();
  SmallVector<Value> current;
  SmallVector<Type> types;
  for (OutputArray &o : outputs) {
    kinds += o.rows.kinds;
    for (Value v : o.rows.values) {
      current.push_back(v);
      types.push_back(VaryingType::get(getUniformType(v.getType())));
    }
  }
  Type i32 = VaryingType::get(b.getI32Type());
  auto op =
      b.create<PointCloudOp>(g.loc(call.loc), i32, i32, types, function,
                             ::osl::pointCloudLayout(layout), kinds, inputs, current, Value());
  size_t next = 0;
  for (OutputArray &o : outputs) {
    size_t n = o.rows.values.size();
    g.storeLValue(o.place, fromRowOperands(o.current, op.getValues().slice(next, n)), call.loc);
    next += n;
  }
  return RValue::num(OslType(BaseType::Int), op.getStatus());
}

/// pointcloud_search(file, center, radius, maxpoints, [sort,] "name",
/// array, ...).
std::optional<RValue> emitSearch(IRGen &g, const Expr &call) {
  const auto &args = call.args;
  size_t first = args.size() % 2 ? 5 : 4; // an odd count has `sort`
  if (args.size() < 4) {
    g.error(call.loc, "wrong arguments to 'pointcloud_search'; candidates: int "
                      "pointcloud_search(string file, point center, float radius, int "
                      "maxpoints, [int sort,] \"attribute\", output array, ...)");
    return std::nullopt;
  }
  auto file = fileName(g, *args[0], "pointcloud_search");
  auto center = input(g, *args[1], OslType(BaseType::Point), "pointcloud_search", "the center");
  auto radius = input(g, *args[2], OslType(BaseType::Float), "pointcloud_search", "the radius");
  auto maxPoints =
      input(g, *args[3], OslType(BaseType::Int), "pointcloud_search", "the point count");
  std::optional<Value> sort =
      first == 5 ? input(g, *args[4], OslType(BaseType::Int), "pointcloud_search", "sort")
                 : std::optional<Value>(g.constInt(0, call.loc));
  if (!file || !center || !radius || !maxPoints || !sort)
    return std::nullopt;
  std::vector<PointCloudArray> layout;
  std::vector<OutputArray> outputs;
  int32_t capacity = INT32_MAX;
  for (size_t k = first; k + 1 < args.size(); k += 2) {
    auto name = attributeName(g, *args[k], "pointcloud_search");
    if (!name)
      return std::nullopt;
    auto out = outputArray(g, *args[k + 1], "pointcloud_search", *name);
    if (!out)
      return std::nullopt;
    int32_t length = int32_t(out->rows.values.size());
    layout.push_back({*name, rowKindOf(out->current.type.element()), length});
    capacity = std::min(capacity, length);
    outputs.push_back(std::move(*out));
  }
  // The runtime fills at most `capacity` elements; a constant asking for
  // more is a mistake worth a word, as oslc's runtime gives it.
  auto asked = IRGen::getConstInt(*maxPoints);
  if (asked && *asked > capacity &&
      !g.diagnostics().warning(
          call.loc, "arrays too small for pointcloud lookup: " + std::to_string(*asked) +
                        " points asked for, at most " + std::to_string(capacity) + " fit"))
    return std::nullopt;
  return emitLookup(g, call, "search", layout, "stfii",
                    {*file, *center, *radius, *maxPoints, *sort}, outputs);
}

/// pointcloud_get(file, int indices[], count, attribute, output array).
std::optional<RValue> emitGet(IRGen &g, const Expr &call) {
  const auto &args = call.args;
  if (args.size() != 5) {
    g.error(call.loc, "wrong arguments to 'pointcloud_get'; candidates: int "
                      "pointcloud_get(string file, int indices[], int count, string "
                      "attribute, output array)");
    return std::nullopt;
  }
  auto file = fileName(g, *args[0], "pointcloud_get");
  auto indices = g.emitExpr(*args[1]);
  auto count = input(g, *args[2], OslType(BaseType::Int), "pointcloud_get", "the count");
  auto attribute = g.emitExpr(*args[3]);
  if (!file || !indices || !count || !attribute)
    return std::nullopt;
  if (!indices->type.isArray() || indices->type.base != BaseType::Int) {
    g.error(args[1]->loc,
            "'pointcloud_get' needs an int array of indices, got '" + indices->type.str() + "'");
    return std::nullopt;
  }
  if (!attribute->type.isString()) {
    g.error(args[3]->loc,
            "'pointcloud_get' needs a string attribute name, got '" + attribute->type.str() + "'");
    return std::nullopt;
  }
  auto out = outputArray(g, *args[4], "pointcloud_get", "the attribute");
  if (!out)
    return std::nullopt;
  std::vector<PointCloudArray> layout = {
      {"", rowKindOf(out->current.type.element()), int32_t(out->rows.values.size())}};
  SmallVector<Value> inputs = {*file, *count, g.stringHandle(*attribute, args[3]->loc)};
  llvm::append_range(inputs, indices->elems);
  std::vector<OutputArray> outputs;
  outputs.push_back(std::move(*out));
  return emitLookup(g, call, "get", layout, "sis" + std::string(indices->elems.size(), 'i'), inputs,
                    outputs);
}

/// pointcloud_write(file, position, "name", value, ...).
std::optional<RValue> emitWrite(IRGen &g, const Expr &call) {
  const auto &args = call.args;
  if (args.size() < 2 || args.size() % 2) {
    g.error(call.loc, "wrong arguments to 'pointcloud_write'; candidates: int "
                      "pointcloud_write(string file, point position, \"attribute\", value, "
                      "...)");
    return std::nullopt;
  }
  auto file = fileName(g, *args[0], "pointcloud_write");
  auto position = input(g, *args[1], OslType(BaseType::Point), "pointcloud_write", "the position");
  if (!file || !position)
    return std::nullopt;
  std::vector<PointCloudArray> layout;
  SmallVector<Value> inputs = {*file, *position};
  std::string kinds = "st";
  for (size_t k = 2; k + 1 < args.size(); k += 2) {
    auto name = attributeName(g, *args[k], "pointcloud_write");
    auto value = g.emitExpr(*args[k + 1]);
    if (!name || !value)
      return std::nullopt;
    const OslType &t = value->type;
    if (!(t.isInt() || t.isFloat() || t.isTriple() || t.isString())) {
      g.error(args[k + 1]->loc, "'pointcloud_write' writes int, float, triple or string "
                                "attributes, got '" +
                                    t.str() + "' for \"" + *name + "\"");
      return std::nullopt;
    }
    auto rows = rowOperands(g, *value, args[k + 1]->loc, "pointcloud_write");
    if (!rows)
      return std::nullopt;
    layout.push_back({*name, rows->kinds[0], 1});
    kinds += rows->kinds;
    inputs.push_back(rows->values[0]);
  }
  std::vector<OutputArray> none;
  return emitLookup(g, call, "write", layout, kinds, inputs, none);
}

} // namespace

std::optional<RValue> emitPointCloudBuiltin(IRGen &g, const Expr &call, bool &known) {
  known = true;
  if (call.name == "pointcloud_search")
    return emitSearch(g, call);
  if (call.name == "pointcloud_get")
    return emitGet(g, call);
  if (call.name == "pointcloud_write")
    return emitWrite(g, call);
  known = false;
  return std::nullopt;
}

} // namespace osl::frontend
