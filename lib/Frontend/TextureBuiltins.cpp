//===- TextureBuiltins.cpp - texture(), texture3d(), environment() --------===//
//
// A lookup is one osl.texture op: coordinates, their derivatives (the
// explicit arguments, or Dx/Dy/Dz of the coordinates, resolved only for
// lookups that need them), the per-point options as values, and the options
// OpenImageIO takes once per call (file, wrap modes, interp, subimage name)
// as choices among compile-time strings, so a string chosen per point is
// split into lane groups later (osl-lane-group-filter).
//
//===----------------------------------------------------------------------===//
#include "IRGen.h"

#include "llvm/ADT/StringSwitch.h"

using namespace osl::frontend;
using namespace mlir;
using namespace mlir::osl;

namespace {

/// The shape of one lookup function.
struct TextureForm {
  mlir::osl::TextureKind kind;
  bool tripleCoord;  // one triple (P, R) rather than s, t
  int derivArgs;     // explicit derivative arguments
  const char *usage; // its signatures, for errors
};

std::optional<TextureForm> textureForm(llvm::StringRef name) {
  if (name == "texture")
    return TextureForm{mlir::osl::TextureKind::texture, false, 4,
                       "texture(string file, float s, float t, [float dsdx, float dtdx, "
                       "float dsdy, float dtdy,] options...)"};
  if (name == "texture3d")
    return TextureForm{mlir::osl::TextureKind::texture3d, true, 3,
                       "texture3d(string file, point p, [vector dpdx, vector dpdy, "
                       "vector dpdz,] options...)"};
  if (name == "environment")
    return TextureForm{mlir::osl::TextureKind::environment, true, 2,
                       "environment(string file, vector R, [vector dRdx, vector dRdy,] "
                       "options...)"};
  return std::nullopt;
}

// Indices into osl.texture's float options and string choices.
enum FloatOption { SBlur, TBlur, RBlur, SWidth, TWidth, RWidth, Fill, MissingAlpha,
                   MissingColorR, MissingColorG, MissingColorB, NumFloatOptions };
enum ChoiceOption { File, SWrap, TWrap, RWrap, Interp, SubimageName, NumChoices };

/// Builds one lookup from a call's arguments.
class TextureCall {
public:
  TextureCall(IRGen &g, const Expr &call, TextureForm form)
      : g(g), call(call), form(form) {}

  std::optional<RValue> emit(const OslType *expected);

private:
  bool wrong() {
    return g.error(call.loc, "wrong arguments to '" + call.name + "'; candidates: " +
                                 form.usage);
  }
  SrcLoc argLoc(size_t k) const { return call.args[k]->loc; }
  std::optional<Value> floatArg(size_t k, const char *what);
  std::optional<Value> tripleArg(size_t k, const char *what);
  bool stringChoice(size_t k, ChoiceOption which);
  bool option(size_t nameArg);
  Value component(Value triple, int64_t i) {
    Type f32 = g.builder().getF32Type();
    return g.builder().create<ExtractOp>(g.loc(call.loc),
                                         withUniformity(f32, isVarying(triple.getType())),
                                         triple, i);
  }
  Value deriv(Value v, const char *axis) {
    return g.builder().create<DerivOp>(g.loc(call.loc), v.getType(), v,
                                         *symbolizeDerivAxis(axis));
  }

  IRGen &g;
  const Expr &call;
  TextureForm form;
  std::vector<Value> coords, derivs;
  Value floats[NumFloatOptions];
  Value choice[NumChoices];
  std::vector<std::string> candidates[NumChoices];
  Value firstChannel, subimage;
  Value fileHandle; // a file name computed at run time
  bool hasMissingColor = false, hasMissingAlpha = false;
  std::optional<LValue> alphaOut;
  std::optional<LValue> errorOut; // "errormessage"
};

std::optional<Value> TextureCall::floatArg(size_t k, const char *what) {
  OslType f(BaseType::Float);
  auto v = g.emitExpr(*call.args[k], &f);
  if (!v)
    return std::nullopt;
  auto c = g.coerce(*v, f, call.args[k]->begin,
                    "for " + llvm::Twine(what) + " of '" + call.name + "'");
  if (!c)
    return std::nullopt;
  return c->value;
}

std::optional<Value> TextureCall::tripleArg(size_t k, const char *what) {
  OslType t(BaseType::Vector);
  auto v = g.emitExpr(*call.args[k], &t);
  if (!v)
    return std::nullopt;
  if (!v->type.isTriple()) {
    g.error(argLoc(k), "'" + call.name + "' needs a point or vector for " + what + ", got '" +
                           v->type.str() + "'");
    return std::nullopt;
  }
  return v->value;
}

/// A string option: a known string, or one chosen per point among several.
bool TextureCall::stringChoice(size_t k, ChoiceOption which) {
  auto v = g.emitExpr(*call.args[k]);
  if (!v)
    return false;
  if (!v->type.isString())
    return g.error(argLoc(k), "'" + call.name + "' expects a string here, got '" +
                                  v->type.str() + "'");
  if (which == File && v->isRuntimeString()) {
    // Each lane looks up the file it names.
    fileHandle = v->value;
    candidates[which] = {""};
    choice[which] = g.constInt(0, call.loc);
    return true;
  }
  if (!g.compileTimeStrings(*v, argLoc(k), "a texture's string option"))
    return false;
  if (v->isStringChoice()) {
    candidates[which] = v->choices;
    choice[which] = v->value;
  } else {
    candidates[which] = {v->str};
    choice[which] = g.constInt(0, call.loc);
  }
  return true;
}

/// The option named by argument `nameArg`, with its value after it.
bool TextureCall::option(size_t nameArg) {
  const Expr &nameExpr = *call.args[nameArg];
  if (nameExpr.kind != ExprKind::StringLit)
    return g.valueError(nameExpr.loc, "'" + call.name +
                                          "' expects an option name (a string literal) here");
  std::string name = nameExpr.name;
  if (nameArg + 1 >= call.args.size())
    return g.valueError(nameExpr.loc, "texture option '" + name + "' needs a value");
  size_t k = nameArg + 1;
  auto setFloats = [&](std::initializer_list<FloatOption> which) {
    auto v = floatArg(k, name.c_str());
    if (!v)
      return false;
    for (FloatOption o : which)
      floats[o] = *v;
    return true;
  };
  auto setChoices = [&](std::initializer_list<ChoiceOption> which) {
    if (!stringChoice(k, *which.begin()))
      return false;
    for (ChoiceOption o : which) {
      candidates[o] = candidates[*which.begin()];
      choice[o] = choice[*which.begin()];
    }
    return true;
  };
  auto intOption = [&](Value &out, bool perPoint) {
    OslType i(BaseType::Int);
    auto v = g.emitExpr(*call.args[k], &i);
    if (!v)
      return false;
    if (!v->type.isInt())
      return g.error(argLoc(k), "texture option '" + name + "' needs an int, got '" +
                                    v->type.str() + "'");
    if (!perPoint && isVarying(v->value.getType()))
      return g.valueError(argLoc(k), "texture option '" + name +
                                         "' must be the same for every point (OpenImageIO takes "
                                         "it once per lookup)");
    out = v->value;
    return true;
  };
  if (name == "blur")
    return setFloats({SBlur, TBlur, RBlur});
  if (name == "sblur")
    return setFloats({SBlur});
  if (name == "tblur")
    return setFloats({TBlur});
  if (name == "rblur")
    return setFloats({RBlur});
  if (name == "width")
    return setFloats({SWidth, TWidth, RWidth});
  if (name == "swidth")
    return setFloats({SWidth});
  if (name == "twidth")
    return setFloats({TWidth});
  if (name == "rwidth")
    return setFloats({RWidth});
  if (name == "fill")
    return setFloats({Fill});
  if (name == "missingalpha") {
    hasMissingAlpha = true;
    return setFloats({MissingAlpha});
  }
  if (name == "time") // motion-blurred textures: none here
    return bool(floatArg(k, "time"));
  if (name == "wrap")
    return setChoices({SWrap, TWrap, RWrap});
  if (name == "swrap")
    return setChoices({SWrap});
  if (name == "twrap")
    return setChoices({TWrap});
  if (name == "rwrap")
    return setChoices({RWrap});
  if (name == "interp")
    return setChoices({Interp});
  if (name == "firstchannel") // per point: each lane is looked up alone
    return intOption(firstChannel, /*perPoint=*/true);
  if (name == "missingcolor") {
    OslType c(BaseType::Color);
    auto v = g.emitExpr(*call.args[k], &c);
    if (!v)
      return false;
    auto cv = g.coerce(*v, c, call.args[k]->begin, "for 'missingcolor'");
    if (!cv)
      return false;
    hasMissingColor = true;
    for (int i = 0; i < 3; ++i)
      floats[MissingColorR + i] = component(cv->value, i);
    return true;
  }
  if (name == "subimage") {
    if (call.args[k]->kind == ExprKind::StringLit || call.args[k]->kind == ExprKind::Ident) {
      auto v = g.emitExpr(*call.args[k]);
      if (!v)
        return false;
      if (v->type.isString()) {
        if (!g.compileTimeStrings(*v, argLoc(k), "the subimage name"))
          return false;
        candidates[SubimageName] = v->isStringChoice() ? v->choices
                                                       : std::vector<std::string>{v->str};
        choice[SubimageName] = v->isStringChoice() ? v->value : g.constInt(0, call.loc);
        return true;
      }
    }
    return intOption(subimage, /*perPoint=*/false);
  }
  if (name == "alpha") {
    alphaOut = g.emitLValue(*call.args[k]);
    if (!alphaOut)
      return false;
    if (!alphaOut->type.isFloat())
      return g.error(argLoc(k), "texture option 'alpha' needs a float variable, got '" +
                                    alphaOut->type.str() + "'");
    return true;
  }
  if (name == "errormessage") {
    errorOut = g.emitLValue(*call.args[k]);
    if (!errorOut)
      return false;
    if (!errorOut->type.isString())
      return g.error(argLoc(k), "texture option 'errormessage' needs a string variable, got '" +
                                    errorOut->type.str() + "'");
    return true;
  }
  // OSL reports an option it does not know when the shader runs, ignores
  // it and shades on (a newer OSL's option in an older one's renderer);
  // osl-run also warns where it is written (a misspelt "blurr").
  if (!g.diagnostics().warning(nameExpr.loc, "unknown texture option '" + name +
                                                 "': OSL ignores it (with an error when "
                                                 "the shader runs)"))
    return false;
  auto value = g.emitExpr(*call.args[k]);
  if (!value)
    return false;
  g.reportAtRunTime("Unknown texture optional argument: \"" + name + "\", <" +
                        value->type.str() + "> (" + g.fileLine(call.loc) + ")",
                    call.loc);
  return true;
}

std::optional<RValue> TextureCall::emit(const OslType *expected) {
  size_t n = call.args.size();
  size_t coordArgs = form.tripleCoord ? 1 : 2;
  if (n < 1 + coordArgs)
    {
    wrong();
    return std::nullopt;
  }
  // Positional arguments end at the first option name.
  size_t firstOption = 1 + coordArgs;
  while (firstOption < n && call.args[firstOption]->kind != ExprKind::StringLit)
    ++firstOption;
  size_t explicitDerivs = firstOption - 1 - coordArgs;
  if (explicitDerivs != 0 && explicitDerivs != size_t(form.derivArgs))
    {
    wrong();
    return std::nullopt;
  }

  if (!stringChoice(0, File))
    return std::nullopt;
  if (form.tripleCoord) {
    auto p = tripleArg(1, "the lookup point");
    if (!p)
      return std::nullopt;
    for (int i = 0; i < 3; ++i)
      coords.push_back(component(*p, i));
    const char *axes[3] = {"x", "y", "z"};
    for (int d = 0; d < form.derivArgs; ++d) {
      Value dv;
      if (explicitDerivs) {
        auto v = tripleArg(1 + coordArgs + d, "a derivative");
        if (!v)
          return std::nullopt;
        dv = *v;
      } else {
        dv = deriv(*p, axes[d]);
      }
      for (int i = 0; i < 3; ++i)
        derivs.push_back(component(dv, i));
    }
  } else {
    for (size_t k = 1; k <= 2; ++k) {
      auto c = floatArg(k, k == 1 ? "s" : "t");
      if (!c)
        return std::nullopt;
      coords.push_back(*c);
    }
    if (explicitDerivs) {
      for (int d = 0; d < 4; ++d) {
        auto v = floatArg(3 + d, "a derivative");
        if (!v)
          return std::nullopt;
        derivs.push_back(*v);
      }
    } else { // ds/dx, dt/dx, ds/dy, dt/dy
      derivs = {deriv(coords[0], "x"), deriv(coords[1], "x"), deriv(coords[0], "y"),
                deriv(coords[1], "y")};
    }
  }

  // OpenImageIO's defaults.
  for (int o = 0; o < NumFloatOptions; ++o)
    floats[o] = g.constFloat(o == SWidth || o == TWidth || o == RWidth || o == MissingAlpha
                                 ? 1.0f
                                 : 0.0f,
                             call.loc);
  for (int c = 1; c < NumChoices; ++c) {
    candidates[c] = {c == Interp ? "smartcubic" : c == SubimageName ? "" : "default"};
    choice[c] = g.constInt(0, call.loc);
  }
  firstChannel = g.constInt(0, call.loc);
  subimage = g.constInt(0, call.loc);
  for (size_t k = firstOption; k < n; k += 2)
    if (!option(k))
      return std::nullopt;

  OpBuilder &b = g.builder();
  bool color = !(expected && (expected->isFloat() || expected->isInt()));
  OslType resultType = color ? OslType(BaseType::Color) : OslType(BaseType::Float);
  Type result = withUniformity(irType(b, resultType), true);
  Type alpha = withUniformity(b.getF32Type(), true);
  SmallVector<Attribute> lists;
  SmallVector<Value> choices;
  for (int c = 0; c < NumChoices; ++c) {
    SmallVector<Attribute> names;
    for (const std::string &s : candidates[c])
      names.push_back(b.getStringAttr(s));
    lists.push_back(b.getArrayAttr(names));
    choices.push_back(choice[c]);
  }
  Type errorType = withUniformity(b.getI32Type(), true);
  auto op = b.create<TextureOp>(g.loc(call.loc), result, alpha, errorType, form.kind,
                                uint32_t(color ? 3 : 1), hasMissingColor, hasMissingAlpha,
                                errorOut.has_value(), b.getArrayAttr(lists), coords, derivs,
                                ArrayRef<Value>(floats), firstChannel, subimage, choices,
                                fileHandle, /*mask=*/Value());
  if (alphaOut)
    g.storeLValue(*alphaOut, RValue::num(OslType(BaseType::Float), op.getAlpha()), call.loc);
  if (errorOut)
    g.storeLValue(*errorOut, RValue::runtimeString(op.getErrorMessage()), call.loc);
  return RValue::num(resultType, op.getResult());
}

/// The texture system's answer about one file and name, merged into the
/// destination's old value (kept where it does not know the answer).
struct TextureInfoAnswer {
  Value found; // i32
  RValue value;
};

/// `fileHandle`, when set, is the file's name computed at run time.
TextureInfoAnswer askTextureInfo(IRGen &g, const Expr &call, const std::string &file,
                                 const std::string &name, const OslType &t, const RValue &old,
                                 Value fileHandle) {
  OslType element = t.isArray() ? t.element() : t;
  bool isString = t.isString();
  bool isFloat = element.isFloat() || element.isTriple() || t.isMatrix();
  int perElement = element.isTriple() ? 3 : t.isMatrix() ? 16 : 1;
  int count = (t.isArray() ? t.arrayLen : 1) * perElement;
  OpBuilder &b = g.builder();
  Location loc = g.loc(call.loc);
  Type scalar = isFloat ? Type(b.getF32Type()) : Type(b.getI32Type());
  auto op = b.create<GetTextureInfoOp>(loc, b.getI32Type(),
                                       SmallVector<Type>(size_t(count), scalar), file, name,
                                       isFloat, isString, fileHandle);
  Value found = b.create<CmpOp>(loc, "ne", op.getFound(), g.constInt(0, call.loc));
  ValueRange v = op.getValues();
  RValue updated = old;
  if (isString) { // the answer's handle, or the old string's
    updated = RValue::runtimeString(
        b.create<SelectOp>(loc, found, v[0], g.stringHandle(old, call.loc)));
  } else if (t.isArray() || t.isMatrix()) {
    for (size_t k = 0; k < updated.elems.size(); ++k)
      updated.elems[k] = b.create<SelectOp>(loc, found, v[k], old.elems[k]);
  } else {
    Value answer = perElement == 3 ? Value(b.create<ConstructOp>(loc, v[0], v[1], v[2]))
                                   : v[0];
    updated.value = b.create<SelectOp>(loc, found, answer, old.value);
  }
  return {op.getFound(), updated};
}

/// gettextureinfo's s and t, as floats.
std::optional<std::pair<Value, Value>> udimCoordinates(IRGen &g, const Expr &call) {
  Value st[2];
  for (int k = 0; k < 2; ++k) {
    const Expr &arg = *call.args[1 + k];
    auto v = g.emitExpr(arg);
    if (!v)
      return std::nullopt;
    if (!v->type.isFloat() && !v->type.isInt()) {
      g.error(arg.loc, std::string("'gettextureinfo' expects a float ") + (k ? "t" : "s") +
                           " here, got '" + v->type.str() + "'");
      return std::nullopt;
    }
    st[k] = g.convert(v->value, g.builder().getF32Type(), arg.loc);
  }
  return std::make_pair(st[0], st[1]);
}

/// gettextureinfo(file, [s, t,] name, output dest): the destination's
/// type says what to ask for; it is left unchanged when the texture system
/// does not know the answer, as in OSL. With s and t, a UDIM pattern's file
/// is its tile at (s, t). A file or name chosen per point (among strings
/// known when the shader is compiled) asks about each choice, and each
/// point takes its own answer.
std::optional<RValue> emitGetTextureInfo(IRGen &g, const Expr &call) {
  const char *usage = "wrong arguments to 'gettextureinfo'; candidates: int gettextureinfo("
                      "string file, string name, output int|float|triple|string|matrix|int[]|"
                      "float[] dest); int gettextureinfo(string file, float s, float t, "
                      "string name, output ... dest)";
  if (call.args.size() != 3 && call.args.size() != 5) {
    g.error(call.loc, usage);
    return std::nullopt;
  }
  bool atST = call.args.size() == 5;
  const size_t argOf[2] = {0, atST ? 3u : 1u}; // the file's and the name's
  const Expr &destArg = *call.args.back();
  std::vector<std::string> choices[2];
  Value index[2];
  Value fileHandle; // a file name computed at run time
  for (int k = 0; k < 2; ++k) {
    const Expr &arg = *call.args[argOf[k]];
    auto v = g.emitExpr(arg);
    if (!v)
      return std::nullopt;
    if (!v->type.isString()) {
      g.error(arg.loc, usage);
      return std::nullopt;
    }
    if (k == 0 && atST) {
      // The tile's file, known per point at run time.
      auto st = udimCoordinates(g, call);
      if (!st)
        return std::nullopt;
      Value handle = g.stringHandle(*v, arg.loc);
      Type type = withUniformity(g.builder().getI32Type(),
                                 isVarying(handle.getType()) || isVarying(st->first.getType()) ||
                                     isVarying(st->second.getType()));
      fileHandle = g.builder().create<UdimTileOp>(g.loc(call.loc), type, handle, st->first,
                                                  st->second);
      choices[k] = {""};
      continue;
    }
    // A file computed at run time, or chosen per point: each point asks of
    // its own file only (asking of every choice would open, and report,
    // files no point uses, and leave a broken file's first error to an
    // earlier batch's query).
    if (k == 0 && (v->isRuntimeString() || v->isStringChoice())) {
      fileHandle = v->isRuntimeString() ? v->value : g.stringHandle(*v, arg.loc);
      choices[k] = {""};
      continue;
    }
    if (v->isRuntimeString()) {
      g.valueError(arg.loc, "'gettextureinfo' needs the name of what it asks known when "
                                      "the shader is compiled (or chosen per point among such "
                                      "strings); this one is computed at run time");
      return std::nullopt;
    }
    if (v->isStringChoice()) {
      choices[k] = v->choices;
      index[k] = v->value;
    } else {
      choices[k] = {v->str};
    }
  }
  auto dest = g.emitLValue(destArg);
  if (!dest)
    return std::nullopt;
  OslType t = dest->type;
  OslType element = t.isArray() ? t.element() : t;
  bool numeric = element.isInt() || element.isFloat() || element.isTriple();
  if (!(t.isString() || t.isMatrix() || numeric) || (t.isArray() && element.isTriple())) {
    g.error(destArg.loc, "'gettextureinfo' cannot answer into a '" + t.str() + "'");
    return std::nullopt;
  }
  RValue old = g.loadLValue(*dest, call.loc);
  std::optional<TextureInfoAnswer> merged;
  for (size_t i = 0; i < choices[0].size(); ++i)
    for (size_t j = 0; j < choices[1].size(); ++j) {
      TextureInfoAnswer a =
          askTextureInfo(g, call, choices[0][i], choices[1][j], t, old, fileHandle);
      if (!merged) {
        merged = a;
        continue;
      }
      // This choice where the point chose it, the earlier ones elsewhere.
      Value chosen = g.constBool(true, call.loc);
      for (int k = 0; k < 2; ++k)
        if (index[k])
          chosen = g.builder().create<AndOp>(
              g.loc(call.loc), chosen,
              g.cmp("eq", index[k], g.constInt(int(k == 0 ? i : j), call.loc), call.loc));
      merged->found = g.select(chosen, a.found, merged->found, call.loc);
      if (t.isString()) {
        merged->value = RValue::runtimeString(g.select(
            chosen, a.value.value, merged->value.value, call.loc));
      } else {
        auto both = g.selectFields(chosen, a.value, merged->value, call.loc);
        if (!both)
          return std::nullopt;
        merged->value = *both;
      }
    }
  g.storeLValue(*dest, merged->value, call.loc);
  return RValue::num(OslType(BaseType::Int), merged->found);
}

} // namespace

namespace osl::frontend {

std::optional<RValue> emitTextureBuiltin(IRGen &g, const Expr &call, const OslType *expected,
                                         bool &known) {
  if (call.name == "gettextureinfo") {
    known = true;
    return emitGetTextureInfo(g, call);
  }
  std::optional<TextureForm> form = textureForm(call.name);
  known = form.has_value();
  if (!form)
    return std::nullopt;
  return TextureCall(g, call, *form).emit(expected);
}

} // namespace osl::frontend
