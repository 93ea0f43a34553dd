//===- GroupSummary.cpp - The group as testshade -v prints it -------------===//
#include "GroupSummary.h"

#include "OslFrontend/Frontend.h"

#include "llvm/ADT/StringExtras.h"
#include "llvm/Support/Format.h"
#include "llvm/Support/MemoryBuffer.h"
#include "llvm/Support/Path.h"

#include <cstdlib>

using namespace osl;

namespace {

bool isTripleType(llvm::StringRef type) {
  return type == "color" || type == "point" || type == "vector" || type == "normal";
}

/// An instance value as OSL serializes it: each number to 9 significant
/// digits (ints whole); one value of a triple (testshade's --param) is
/// all three.
std::string serializedValue(const ShaderParamInfo &param, const std::string &value) {
  llvm::StringRef type(param.type);
  if (type.starts_with("string"))
    return " " + quotedOslString(value);
  llvm::SmallVector<llvm::StringRef> words;
  llvm::SplitString(value, words, " ,");
  if (isTripleType(type) && words.size() == 1)
    words.assign(3, words[0]);
  std::string out;
  llvm::raw_string_ostream os(out);
  for (llvm::StringRef w : words) {
    double d = std::strtod(w.str().c_str(), nullptr);
    if (type.starts_with("int"))
      os << " " << int64_t(d);
    else
      os << " " << llvm::format("%.9g", double(float(d)));
  }
  return out;
}

std::vector<ShaderParamInfo> paramsOf(const GroupLayer &layer, const RunOptions &options) {
  auto source = llvm::MemoryBuffer::getFile(layer.shaderPath, /*IsText=*/true);
  if (!source)
    return {};
  // A source that does not parse is reported when it compiles.
  std::string ignored;
  llvm::raw_string_ostream quiet(ignored);
  auto params = shaderParams((*source)->getBuffer(), layer.shaderPath, quiet,
                             options.compile.includePaths, options.compile.defines);
  return params ? *params : std::vector<ShaderParamInfo>();
}

} // namespace

void osl::printGroupSummary(const RunOptions &options, llvm::raw_ostream &out) {
  ShaderGroup expressionGroup;
  if (!options.expression.empty()) {
    GroupLayer &layer = expressionGroup.layers.emplace_back();
    layer.shaderName = kExprShaderName;
    layer.name = std::string(kExprShaderName) + "_0";
  }
  const ShaderGroup &group = options.expression.empty() ? options.group : expressionGroup;
  std::string groupName = groupNameOrDefault(options.compile.groupName);
  std::vector<std::vector<ShaderParamInfo>> params;
  out << "Shader group:\n---\n";
  for (const GroupLayer &layer : group.layers) {
    params.push_back(paramsOf(layer, options));
    // Instance values of parameters the shader has (others were warned of).
    for (const ParamOverride &p : layer.params)
      for (const ShaderParamInfo &info : params.back())
        if (info.name == p.name)
          out << "param " << info.type << " " << p.name << serializedValue(info, p.value)
              << " ;\n";
    // The shader as testshade is given it: a name, not a file.
    std::string shader =
        llvm::sys::path::stem(layer.shaderName.empty() ? layer.shaderPath : layer.shaderName)
            .str();
    out << "shader " << shader << " " << layer.name << " ;\n";
    for (const GroupConnection &c : group.connections)
      if (c.toLayer == layer.name)
        out << "connect " << c.fromLayer << "." << c.fromOutput << " " << c.toLayer << "."
            << c.toInput << " ;\n";
  }
  out << "\n---\n\nShader group \"" << groupName << "\" layers are:\n";
  for (size_t i = 0; i < group.layers.size(); ++i) {
    out << "    " << group.layers[i].name << "\n";
    if (options.oslquery)
      for (const ShaderParamInfo &p : params[i])
        out << "\t" << (p.isOutput ? "output " : "") << p.type << " " << p.name << "\n";
  }
  out << "\n";
}
