//===- ShaderInfo.cpp - A shader's interface, as oslinfo prints it --------===//
//
// Parameters' types and defaults and the metadata of a shader, read from
// its source without compiling it. Defaults are evaluated when they are
// constant expressions (literals, constructors, arithmetic, {...}); one
// computed from globals prints as zeros, since no point exists yet.
//
//===----------------------------------------------------------------------===//
#include "OslFrontend/Frontend.h"

#include "IRGen.h"
#include "Parser.h"
#include "Preprocessor.h"

#include "llvm/Support/Format.h"
#include "llvm/Support/JSON.h"

using namespace osl::frontend;

namespace {

/// A constant value: numbers (a triple's three and an array's elements,
/// flattened) or strings.
struct Constant {
  std::vector<double> numbers;
  std::vector<std::string> strings;
};

/// Values per element of `t`: 3 for triples, 16 for matrices, else 1.
size_t valuesPerElement(const OslType &t) {
  OslType e = t.element();
  return e.isTriple() ? 3 : e.isMatrix() ? 16 : 1;
}

std::optional<Constant> evaluate(const Expr &e) {
  Constant c;
  switch (e.kind) {
  case ExprKind::IntLit:
    c.numbers = {double(e.intValue)};
    return c;
  case ExprKind::FloatLit:
    c.numbers = {e.floatValue};
    return c;
  case ExprKind::StringLit:
    c.strings = {e.name};
    return c;
  case ExprKind::Ident: // M_PI and stdosl.h's other constants
    if (auto constant = lookupFloatConstant(e.name)) {
      c.numbers = {*constant};
      return c;
    }
    return std::nullopt;
  case ExprKind::Cast:
    return evaluate(*e.args[0]);
  case ExprKind::Unary: {
    auto v = evaluate(*e.args[0]);
    if (!v || !v->strings.empty() || (e.name != "-" && e.name != "+"))
      return std::nullopt;
    if (e.name == "-")
      for (double &d : v->numbers)
        d = -d;
    return v;
  }
  case ExprKind::Binary: {
    auto a = evaluate(*e.args[0]), b = evaluate(*e.args[1]);
    if (!a || !b || !a->strings.empty() || !b->strings.empty())
      return std::nullopt;
    size_t n = std::max(a->numbers.size(), b->numbers.size());
    if ((a->numbers.size() != n && a->numbers.size() != 1) ||
        (b->numbers.size() != n && b->numbers.size() != 1))
      return std::nullopt;
    for (size_t i = 0; i < n; ++i) {
      double x = a->numbers[a->numbers.size() == 1 ? 0 : i];
      double y = b->numbers[b->numbers.size() == 1 ? 0 : i];
      if (e.name == "+")
        c.numbers.push_back(x + y);
      else if (e.name == "-")
        c.numbers.push_back(x - y);
      else if (e.name == "*")
        c.numbers.push_back(x * y);
      else if (e.name == "/")
        c.numbers.push_back(y == 0 ? 0 : x / y);
      else
        return std::nullopt;
    }
    return c;
  }
  case ExprKind::Call: {
    // Type constructors: color(0.5) is three 0.5s, matrix(2) the diagonal.
    if (!e.isCtor)
      return std::nullopt;
    for (const auto &a : e.args) {
      auto v = evaluate(*a);
      if (!v || !v->strings.empty())
        return std::nullopt;
      c.numbers.insert(c.numbers.end(), v->numbers.begin(), v->numbers.end());
    }
    size_t per = valuesPerElement(e.castType);
    if (c.numbers.size() == 1 && per == 3)
      c.numbers.assign(3, c.numbers[0]);
    else if (c.numbers.size() == 1 && per == 16)
      for (int k = 1; k < 16; ++k)
        c.numbers.push_back(k % 5 == 0 ? c.numbers[0] : 0.0);
    return c;
  }
  case ExprKind::InitList:
    for (const auto &a : e.args) {
      auto v = evaluate(*a);
      if (!v)
        return std::nullopt;
      c.numbers.insert(c.numbers.end(), v->numbers.begin(), v->numbers.end());
      c.strings.insert(c.strings.end(), v->strings.begin(), v->strings.end());
    }
    return c;
  default:
    return std::nullopt;
  }
}


std::string number(double d, bool isInt) {
  if (isInt)
    return std::to_string(int64_t(d));
  std::string s;
  llvm::raw_string_ostream(s) << llvm::format("%g", d);
  return s;
}

/// The values of `c` as `type`, space separated (numbers widened to the
/// type's count when one is given for a triple or array).
std::vector<std::string> valueWords(const Constant &c, const OslType &type) {
  std::vector<std::string> words;
  if (type.base == BaseType::String) {
    for (const std::string &s : c.strings)
      words.push_back(osl::quotedOslString(s));
    return words;
  }
  for (double d : c.numbers)
    words.push_back(number(d, type.base == BaseType::Int));
  return words;
}

std::string join(const std::vector<std::string> &words) {
  std::string s;
  for (const std::string &w : words)
    s += (s.empty() ? "" : " ") + w;
  return s;
}

std::string metadataLine(const Metadatum &m) {
  std::string text = "\t\tmetadata: " + m.type.str() + " " + m.name + " = ";
  if (auto v = evaluate(*m.value))
    text += join(valueWords(*v, m.type));
  return text + "\n";
}

/// The values of `exprs` one after another, as an initializer list's.
std::optional<Constant> evaluateList(llvm::ArrayRef<const Expr *> exprs) {
  Constant c;
  for (const Expr *e : exprs) {
    auto v = e ? evaluate(*e) : std::nullopt;
    if (!v)
      return std::nullopt;
    c.numbers.insert(c.numbers.end(), v->numbers.begin(), v->numbers.end());
    c.strings.insert(c.strings.end(), v->strings.begin(), v->strings.end());
  }
  return c;
}

/// The default of a parameter of type `t` whose initializer evaluates to `v`, with as
/// many values as the type holds (a triple's one value widened, a matrix's
/// one value its diagonal); nullopt when it is not a constant (computed per
/// point).
std::optional<Constant> defaultValues(const OslType &t, std::optional<Constant> v) {
  size_t per = valuesPerElement(t);
  size_t count = t.arrayLen > 0 ? size_t(t.arrayLen) * per : per;
  if (t.arrayLen == 0)
    count = v ? std::max<size_t>(v->numbers.size() + v->strings.size(), 1) : per;
  if (!v)
    return std::nullopt;
  Constant c = *v;
  if (t.base == BaseType::String) {
    if (!c.numbers.empty())
      return std::nullopt;
    c.strings.resize(t.isArray() ? count : 1);
    return c;
  }
  if (c.numbers.size() == 1 && per == 16 && !t.isArray()) {
    double d = c.numbers[0]; // matrix m = 2: the diagonal
    c.numbers.assign(16, 0.0);
    for (size_t k = 0; k < 16; k += 5)
      c.numbers[k] = d;
  } else if (c.numbers.size() == 1 && count > 1 && per > 1 && !t.isArray()) {
    c.numbers.assign(count, c.numbers[0]); // color c = 0.5
  }
  if (c.numbers.size() != count || !c.strings.empty())
    return std::nullopt;
  return c;
}

/// Zeros (or empty strings) for a default not known before shading.
Constant unknownDefault(const OslType &t) {
  size_t per = valuesPerElement(t);
  size_t count = t.arrayLen > 0 ? size_t(t.arrayLen) * per : per;
  Constant c;
  if (t.base == BaseType::String)
    c.strings.resize(t.isArray() ? count : 1);
  else
    c.numbers.assign(count, 0.0);
  return c;
}

std::string defaultText(const Param &p) {
  const OslType &t = p.type;
  if (t.isStructLike() || t.base == BaseType::Closure)
    return "";
  Constant c = defaultValues(t, evaluate(*p.init)).value_or(unknownDefault(t));
  std::string words = join(valueWords(c, t));
  bool bracketed = t.isArray() || valuesPerElement(t) > 1;
  return "\t\tDefault value: " + (bracketed ? "[ " + words + " ]" : words) + "\n";
}

} // namespace

namespace {

/// The shader declared in `source`, parsed without compiling it.
std::optional<Program> parseInterface(llvm::StringRef source, llvm::StringRef filename,
                                      llvm::raw_ostream &errs,
                                      llvm::ArrayRef<std::string> includePaths,
                                      llvm::ArrayRef<std::string> defines) {
  Diagnostics diags(filename, errs);
  std::vector<Token> tokens;
  Program program;
  if (!lexAndPreprocess(source, diags, tokens, includePaths, defines) ||
      !parseProgram(tokens, diags, program) || !program.shader)
    return std::nullopt;
  return program;
}

} // namespace

std::optional<std::string>
osl::shaderInfoText(llvm::StringRef source, llvm::StringRef filename, llvm::raw_ostream &errs,
                    llvm::ArrayRef<std::string> includePaths,
                    llvm::ArrayRef<std::string> defines) {
  std::optional<Program> program =
      parseInterface(source, filename, errs, includePaths, defines);
  if (!program)
    return std::nullopt;
  const ShaderDecl &shader = *program->shader;
  std::string text = shader.shaderType + " " + osl::quotedOslString(shader.name) + "\n";
  for (const Metadatum &m : shader.metadata)
    text += metadataLine(m);
  for (const Param &p : shader.params) {
    text += "    " + osl::quotedOslString(p.name) + " " +
            osl::quotedOslString((p.isOutput ? "output " : "") + p.type.str()) + "\n";
    text += defaultText(p);
    for (const Metadatum &m : p.metadata)
      text += metadataLine(m);
  }
  return text;
}

std::optional<std::vector<osl::ShaderParamInfo>>
osl::shaderParams(llvm::StringRef source, llvm::StringRef filename, llvm::raw_ostream &errs,
                  llvm::ArrayRef<std::string> includePaths,
                  llvm::ArrayRef<std::string> defines) {
  std::optional<Program> program =
      parseInterface(source, filename, errs, includePaths, defines);
  if (!program)
    return std::nullopt;
  std::vector<ShaderParamInfo> params;
  for (const Param &p : program->shader->params)
    params.push_back({p.name, p.type.str(), p.isOutput, !p.intMetadataIsZero("allowconnect")});
  return params;
}

namespace {

/// A constant's values as JSON: numbers as written (the reader knows the
/// type), floats rounded to float as the shader holds them.
llvm::json::Array jsonValues(const Constant &c, const OslType &t) {
  llvm::json::Array values;
  for (const std::string &s : c.strings)
    values.push_back(s);
  for (double d : c.numbers) {
    if (t.base == BaseType::Int)
      values.push_back(int64_t(d));
    else
      values.push_back(double(float(d)));
  }
  return values;
}

/// A triple or matrix constructor's space name: point("world", 1, 2, 3).
std::string spaceNameOf(const Expr *init, const OslType &t) {
  if (!init || init->kind != ExprKind::Call || !init->isCtor || t.isArray() ||
      init->args.empty() || init->args[0]->kind != ExprKind::StringLit)
    return "";
  if (!t.isTriple() && !t.isMatrix())
    return "";
  return init->args[0]->name;
}

llvm::json::Object queryEntry(const std::string &name, const OslType &t, bool isOutput,
                              const Expr *init, const std::vector<Metadatum> &metadata,
                              std::optional<Constant> given = std::nullopt);

llvm::json::Array queryMetadata(const std::vector<Metadatum> &metadata) {
  llvm::json::Array list;
  for (const Metadatum &m : metadata)
    list.push_back(queryEntry(m.name, m.type, false, m.value.get(), {}));
  return list;
}

/// One parameter or metadatum; its value is `init`'s, or `given` when
/// there is no single initializer (a field of an array of structs).
llvm::json::Object queryEntry(const std::string &name, const OslType &t, bool isOutput,
                              const Expr *init, const std::vector<Metadatum> &metadata,
                              std::optional<Constant> given) {
  llvm::json::Object entry{{"name", name},
                           {"type", t.str()},
                           {"isoutput", isOutput},
                           {"isclosure", t.base == BaseType::Closure},
                           {"isstruct", t.isStructLike()},
                           {"varlenarray", t.arrayLen == 0},
                           {"metadata", queryMetadata(metadata)}};
  if (t.isStructLike() || t.base == BaseType::Closure) {
    entry["validdefault"] = false;
    return entry;
  }
  // The space of point("world", ...) is not a value.
  std::string space = spaceNameOf(init, t);
  if (!space.empty()) {
    std::vector<const Expr *> rest;
    for (size_t i = 1; i < init->args.size(); ++i)
      rest.push_back(init->args[i].get());
    given = evaluateList(rest);
  } else if (init) {
    given = evaluate(*init);
  }
  std::optional<Constant> value = defaultValues(t, given);
  entry["validdefault"] = value.has_value();
  entry["value"] = jsonValues(value.value_or(unknownDefault(t)), t);
  entry["spacename"] = space;
  return entry;
}

/// The initializer of field `index` of a struct value written as {...} or
/// as the struct's constructor; null when it is neither.
const Expr *fieldInit(const Expr *init, const StructDecl &decl, size_t index) {
  if (!init)
    return nullptr;
  bool list = init->kind == ExprKind::InitList ||
              (init->kind == ExprKind::Call && init->name == decl.name);
  if (!list || index >= init->args.size())
    return nullptr;
  return init->args[index].get();
}

/// A struct parameter, then one entry per field named PARAM.FIELD (nested
/// structs in turn), as oslc lays them out. An array of structs has arrays
/// of fields.
void appendStructParam(llvm::json::Array &params, const std::string &name, const OslType &t,
                       bool isOutput, const Expr *init, const std::vector<Metadatum> &metadata) {
  const StructDecl &decl = *t.structDecl;
  llvm::json::Object entry = queryEntry(name, t, isOutput, nullptr, metadata);
  entry["structname"] = decl.name;
  llvm::json::Array fields;
  for (const StructField &f : decl.fields)
    fields.push_back(f.name);
  entry["fields"] = std::move(fields);
  params.push_back(std::move(entry));
  for (size_t i = 0; i < decl.fields.size(); ++i) {
    OslType fieldType = decl.fields[i].type;
    std::string fieldName = name + "." + decl.fields[i].name;
    if (t.isArray() && !fieldType.isArray()) {
      // The elements' initializers of this field, gathered into one list.
      fieldType.arrayLen = t.arrayLen;
      std::vector<const Expr *> elements;
      if (init && init->kind == ExprKind::InitList)
        for (const auto &e : init->args)
          elements.push_back(fieldInit(e.get(), decl, i));
      if (fieldType.arrayLen == 0)
        fieldType.arrayLen = int(elements.size());
      params.push_back(queryEntry(fieldName, fieldType, isOutput, nullptr, {},
                                  evaluateList(elements)));
      continue;
    }
    const Expr *f = t.isArray() ? nullptr : fieldInit(init, decl, i);
    if (fieldType.isStructLike())
      appendStructParam(params, fieldName, fieldType, isOutput, f, {});
    else
      params.push_back(queryEntry(fieldName, fieldType, isOutput, f, {}));
  }
}

} // namespace

std::optional<std::string>
osl::shaderQueryJson(llvm::StringRef source, llvm::StringRef filename, llvm::raw_ostream &errs,
                     llvm::ArrayRef<std::string> includePaths,
                     llvm::ArrayRef<std::string> defines) {
  std::optional<Program> program =
      parseInterface(source, filename, errs, includePaths, defines);
  if (!program)
    return std::nullopt;
  const ShaderDecl &shader = *program->shader;
  llvm::json::Array params;
  for (const Param &p : shader.params) {
    if (p.type.isStructLike())
      appendStructParam(params, p.name, p.type, p.isOutput, p.init.get(), p.metadata);
    else
      params.push_back(queryEntry(p.name, p.type, p.isOutput, p.init.get(), p.metadata));
  }
  llvm::json::Value query = llvm::json::Object{{"shadertype", shader.shaderType},
                                               {"shadername", shader.name},
                                               {"metadata", queryMetadata(shader.metadata)},
                                               {"params", std::move(params)}};
  std::string text;
  llvm::raw_string_ostream(text) << query << "\n";
  return text;
}

std::string osl::quotedOslString(llvm::StringRef s) {
  std::string out = "\"";
  for (char ch : s) {
    switch (ch) {
    case '\n': out += "\\n"; break;
    case '\t': out += "\\t"; break;
    case '"': out += "\\\""; break;
    case '\\': out += "\\\\"; break;
    default: out += ch;
    }
  }
  return out + "\"";
}

std::optional<std::vector<std::string>>
osl::unconnectableParams(llvm::StringRef source, llvm::StringRef filename,
                         llvm::raw_ostream &errs, llvm::ArrayRef<std::string> includePaths,
                         llvm::ArrayRef<std::string> defines) {
  auto params = shaderParams(source, filename, errs, includePaths, defines);
  if (!params)
    return std::nullopt;
  std::vector<std::string> names;
  for (const ShaderParamInfo &p : *params)
    if (!p.connectable)
      names.push_back(p.name);
  return names;
}
