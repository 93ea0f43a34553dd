//===- AttributeBuiltins.cpp - getattribute and testshade's user data -------===//
//
// What testshade's renderer answers: its camera, the shader's names, OSL's
// version and --userdata, all known when the shader is compiled, plus the
// per-point user data testshade invents (s, t, red, green, blue).
//
//===----------------------------------------------------------------------===//
#include "IRGen.h"

using namespace mlir;
using namespace mlir::osl;

namespace osl::frontend {
namespace {

/// The attributes testshade's renderer answers: its camera (an image of
/// the grid's size, testshade's defaults otherwise). Numbers, or a string.
struct RendererAttribute {
  std::vector<double> numbers;
  bool isInt = false;
  bool isTriple = false; // three numbers for a color, point, vector or normal
  std::string text;
};

bool isTripleTypeName(llvm::StringRef type) {
  return type == "color" || type == "point" || type == "vector" || type == "normal";
}

/// A --userdata datum as an attribute (numbers, or a string).
RendererAttribute userDatumAttribute(const ::osl::UserDatum &d) {
  RendererAttribute a;
  if (d.type == "string") {
    a.text = d.value;
    return a;
  }
  llvm::SmallVector<llvm::StringRef> words;
  llvm::StringRef(d.value).split(words, ',', -1, /*KeepEmpty=*/false);
  for (llvm::StringRef w : words) {
    double x = 0;
    if (!w.trim().getAsDouble(x))
      a.numbers.push_back(x);
  }
  a.isInt = d.type == "int";
  a.isTriple = isTripleTypeName(d.type);
  if (a.isTriple && a.numbers.size() == 1)
    a.numbers.assign(3, a.numbers[0]);
  return a;
}

std::optional<RendererAttribute> testshadeAttribute(const IRGen &g, llvm::StringRef name,
                                                   bool nameIsConstant) {
  RendererAttribute a;
  if (name.starts_with("shader:")) {
    // OSL answers these while it optimizes the group, so only for a name
    // known then (its testsuite checks that a name picked per point finds
    // nothing).
    if (!nameIsConstant)
      return std::nullopt;
    if (name == "shader:shadername")
      a.text = g.shaderName().str();
    else if (name == "shader:layername")
      a.text = g.layerName();
    else if (name == "shader:groupname")
      a.text = g.groupName();
    else
      return std::nullopt;
  } else if (name == "osl:version") {
    // The ShadingSystem's own attribute: the version the preprocessor's
    // OSL_VERSION names.
    a.numbers = {double(::osl::kOslVersion)};
    a.isInt = true;
  } else if (name == "camera:resolution") {
    a.numbers = {double(g.cameraImage().xres), double(g.cameraImage().yres)};
    a.isInt = true;
  } else if (name == "camera:projection") {
    a.text = "perspective";
  } else if (name == "camera:fov") {
    a.numbers = {90};
  } else if (name == "camera:pixelaspect") {
    a.numbers = {1};
  } else if (name == "camera:clip_near") {
    a.numbers = {0.1};
  } else if (name == "camera:clip_far") {
    a.numbers = {1000};
  } else if (name == "camera:clip") {
    a.numbers = {0.1, 1000};
  } else if (name == "camera:shutter_open") {
    a.numbers = {0};
  } else if (name == "camera:shutter_close") {
    a.numbers = {1};
  } else if (name == "camera:shutter") {
    a.numbers = {0, 1};
  } else if (name == "camera:screen_window") {
    a.numbers = {-1, -1, 1, 1};
  } else if (const ::osl::UserDatum *d = g.userDatum(name)) {
    a = userDatumAttribute(*d);
  } else {
    return std::nullopt;
  }
  return a;
}

/// What getattribute(object, attribute, dest) leaves in dest (its current
/// value where testshade has no such attribute) and returns (1 or 0).
std::pair<RValue, RValue> attributeValue(IRGen &g, const Expr &call, const std::string &object,
                                         const std::string &attribute, bool nameIsConstant,
                                         bool indexed, const LValue &destRef) {
  const LValue *dest = &destRef;
  std::optional<RendererAttribute> found =
      object.empty() ? testshadeAttribute(g, attribute, nameIsConstant) : std::nullopt;
  OslType t = dest->type;
  OslType element = t.isArray() ? t.element() : t;
  bool fits = found && !indexed;
  if (fits && !found->text.empty())
    fits = t.isString();
  else if (fits && found->isTriple)
    fits = t.isTriple() && !t.isArray() && found->numbers.size() == 3;
  else if (fits)
    fits = (found->isInt ? element.isInt() : element.isFloat()) &&
           int(found->numbers.size()) == (t.isArray() ? t.arrayLen : 1);
  if (!found && object.empty() && !indexed)
    // The renderer's per-point user data: found where it has it.
    if (auto data = testshadeUserdata(g, attribute, t, call.loc)) {
      RValue value = g.loadLValue(*dest, call.loc);
      value.value = g.select(data->first, data->second, value.value, call.loc);
      Value one = g.constInt(1, call.loc), zero = g.constInt(0, call.loc);
      return {value, RValue::num(OslType(BaseType::Int),
                                 g.select(data->first, one, zero, call.loc))};
    }
  if (!fits)
    return {g.loadLValue(*dest, call.loc),
            RValue::num(OslType(BaseType::Int), g.constInt(0, call.loc))};
  RValue value;
  if (t.isString()) {
    value = RValue::string(found->text);
  } else {
    value = g.loadLValue(*dest, call.loc);
    auto constant = [&](double x) {
      return found->isInt ? g.constInt(int(x), call.loc) : g.constFloat(float(x), call.loc);
    };
    if (found->isTriple)
      value.value = g.constTriple(float(found->numbers[0]), float(found->numbers[1]),
                                  float(found->numbers[2]), call.loc);
    else if (t.isArray())
      for (size_t k = 0; k < found->numbers.size(); ++k)
        value.elems[k] = constant(found->numbers[k]);
    else
      value.value = constant(found->numbers[0]);
  }
  return {value, RValue::num(OslType(BaseType::Int), g.constInt(1, call.loc))};
}

} // namespace

/// getattribute([object,] name, [index,] out dest): testshade's renderer
/// answers from constants, so a name known when the shader is compiled is
/// looked up then; dest is written only when the attribute exists and has
/// dest's type, and the result says whether it was.
std::optional<RValue> emitGetAttribute(IRGen &g, const Expr &call) {
  size_t n = call.args.size();
  if (n < 2 || n > 4) {
    g.error(call.loc, "wrong arguments to 'getattribute'; candidates: int getattribute(string "
                      "name, output T value); int getattribute(string object, string name, "
                      "output T value); with an int index before the value for arrays");
    return std::nullopt;
  }
  std::vector<RValue> names;
  for (size_t k = 0; k < n - 1; ++k) {
    auto v = g.emitExpr(*call.args[k]);
    if (!v)
      return std::nullopt;
    names.push_back(*v);
  }
  size_t nameCount = names.size() >= 2 && names[1].type.isString() ? 2 : 1;
  std::string object;
  if (nameCount == 2 && !stringArg(g, names[0], *call.args[0], "getattribute",
                                   "the object name", object))
    return std::nullopt;
  bool indexed = names.size() > nameCount;
  auto dest = g.emitLValue(*call.args[n - 1]);
  if (!dest)
    return std::nullopt;
  const RValue &attrName = names[nameCount - 1];
  if (!attrName.isStringChoice()) {
    std::string attribute;
    if (!stringArg(g, attrName, *call.args[nameCount - 1], "getattribute",
                   "the attribute name", attribute))
      return std::nullopt;
    auto [value, found] =
        attributeValue(g, call, object, attribute, /*nameIsConstant=*/true, indexed, *dest);
    g.storeLValue(*dest, value, call.loc);
    return found;
  }
  // A name chosen per point: every choice's answer (constants), then each
  // lane takes its own.
  std::vector<RValue> values, founds;
  for (const std::string &attribute : attrName.choices) {
    auto [value, found] =
        attributeValue(g, call, object, attribute, /*nameIsConstant=*/false, indexed, *dest);
    values.push_back(value);
    founds.push_back(found);
  }
  RValue value = values.back(), found = founds.back();
  if (dest->type.isString()) {
    value = g.stringChoice(values, attrName.value, call.loc);
  }
  for (size_t k = attrName.choices.size() - 1; k-- > 0;) {
    mlir::Value isK = g.cmp("eq", attrName.value, g.constInt(int(k), call.loc), call.loc);
    found.value = g.select(isK, founds[k].value, found.value, call.loc);
    if (dest->type.isString())
      continue;
    auto merged = g.selectFields(isK, values[k], value, call.loc);
    if (!merged)
      return std::nullopt;
    value = *merged;
  }
  g.storeLValue(*dest, value, call.loc);
  return found;
}

std::optional<std::string> testshadeStringUserdata(const IRGen &g, llvm::StringRef name) {
  if (const ::osl::UserDatum *d = g.userDatum(name))
    if (d->type == "string")
      return d->value;
  return std::nullopt;
}

std::optional<std::pair<Value, Value>> testshadeUserdata(IRGen &g, llvm::StringRef name,
                                                         const OslType &type, SrcLoc l) {
  // testshade's renderer has float user data "s" = u and "t" = v on every
  // point, "red" = u where u > 0.5, "green" = v where u < 0.5, and "blue" =
  // 1 - u on the rows where int(v * 12) is even (as testshade answers); it
  // looks there before the data given on the command line.
  if (type.isFloat() && !type.isArray() &&
      llvm::is_contained({"s", "t", "red", "green", "blue"}, name)) {
    OpBuilder &b = g.builder();
    Location ml = g.loc(l);
    Type f32 = b.getF32Type();
    Value u = g.getGlobal("u", f32, l), v = g.getGlobal("v", f32, l);
    Value half = g.constFloat(0.5f, l);
    Value value = name == "t" || name == "green" ? v : u;
    Value found = g.constBool(true, l);
    if (name == "red")
      found = b.create<CmpOp>(ml, "gt", u, half);
    else if (name == "green")
      found = b.create<CmpOp>(ml, "lt", u, half);
    if (name == "blue") {
      value = b.create<SubOp>(ml, g.constFloat(1, l), u);
      Value row = g.convert(b.create<MulOp>(ml, v, g.constFloat(12, l)), b.getI32Type(), l);
      Value odd = b.create<ModOp>(ml, row, g.constInt(2, l));
      found = b.create<CmpOp>(ml, "eq", odd, g.constInt(0, l));
    }
    return std::make_pair(found, value);
  }
  // Data given on the command line (--userdata) is the same on every point.
  if (const ::osl::UserDatum *d = g.userDatum(name)) {
    RendererAttribute a = userDatumAttribute(*d);
    bool fits = a.text.empty() && (a.isTriple ? type.isTriple() && a.numbers.size() == 3
                                              : a.numbers.size() == 1 &&
                                                    (a.isInt ? type.isInt() : type.isFloat()));
    if (fits && !type.isArray()) {
      Value value = a.isTriple ? g.constTriple(float(a.numbers[0]), float(a.numbers[1]),
                                               float(a.numbers[2]), l)
                    : a.isInt  ? g.constInt(int(a.numbers[0]), l)
                               : g.constFloat(float(a.numbers[0]), l);
      return std::make_pair(g.constBool(true, l), value);
    }
  }
  return std::nullopt;
}

} // namespace osl::frontend
