//===- ShaderGroup.cpp - Building a shader group, testshade's way ---------===//
#include "OslCompiler/ShaderGroup.h"

#include "llvm/ADT/STLExtras.h"
#include "llvm/ADT/StringExtras.h"
#include "llvm/ADT/StringRef.h"
#include "llvm/Support/Path.h"

#include <cctype>
#include <map>
#include <set>

using namespace osl;

const GroupLayer *ShaderGroup::findLayer(const std::string &name) const {
  for (const GroupLayer &l : layers)
    if (l.name == name)
      return &l;
  return nullptr;
}

void ShaderGroup::param(std::string name, std::string value, bool userdata) {
  if (userdata)
    pendingUserdata.push_back(name);
  pendingParams.push_back({std::move(name), std::move(value)});
}

bool ShaderGroup::shader(std::string shaderPath, std::string layerName, std::string &error) {
  if (findLayer(layerName)) {
    error = "layer '" + layerName + "' is declared twice";
    return false;
  }
  GroupLayer layer;
  layer.shaderPath = std::move(shaderPath);
  layer.name = std::move(layerName);
  layer.params = std::move(pendingParams);
  layer.userdata = std::move(pendingUserdata);
  pendingParams.clear();
  pendingUserdata.clear();
  layers.push_back(std::move(layer));
  return true;
}

bool ShaderGroup::reparam(const std::string &layerName, const std::string &name,
                          std::string value, std::string &error) {
  for (GroupLayer &l : layers) {
    if (l.name != layerName)
      continue;
    for (ParamOverride &p : l.params)
      if (p.name == name) {
        p.value = std::move(value);
        return true;
      }
    l.params.push_back({name, std::move(value)});
    return true;
  }
  error = "reparam: unknown layer '" + layerName + "'";
  return false;
}

bool ShaderGroup::useEntryOutputs(std::string &error) {
  // As testshade 1.13 runs them: only beside entry layers, in their place;
  // of the outputs' layers, in the outputs' order, those that are entry
  // layers run (OSL compiles no entry point for the others), and where
  // none is, no layer runs.
  if (entryOutputs.empty() || entries.empty())
    return true;
  std::vector<std::string> run;
  for (const std::string &output : entryOutputs) {
    // "name" alone is the root layer's.
    size_t dot = output.rfind('.');
    std::string layer = dot == std::string::npos ? layers.back().name : output.substr(0, dot);
    if (!llvm::any_of(layers, [&](const GroupLayer &l) { return l.name == layer; })) {
      error = "--entryoutput " + output + ": the group has no layer '" + layer + "'";
      return false;
    }
    if (llvm::is_contained(entries, layer) && !llvm::is_contained(run, layer))
      run.push_back(layer);
  }
  runsNoLayer = run.empty();
  namedEntries = entries;
  entries = std::move(run);
  return true;
}

bool ShaderGroup::validate(std::string &error) const {
  if (layers.empty()) {
    error = "the shader group has no layers";
    return false;
  }
  if (!pendingParams.empty()) {
    error = "parameter '" + pendingParams.front().name + "' is not followed by a shader";
    return false;
  }
  std::map<std::string, size_t> index;
  for (size_t i = 0; i < layers.size(); ++i)
    index[layers[i].name] = i;
  std::set<std::pair<std::string, std::string>> connectedInputs;
  for (const GroupConnection &c : connections) {
    auto from = index.find(c.fromLayer), to = index.find(c.toLayer);
    if (from == index.end() || to == index.end()) {
      error = "connect: unknown layer '" +
              (from == index.end() ? c.fromLayer : c.toLayer) + "'";
      return false;
    }
    if (from->second >= to->second) {
      error = "connect " + c.fromLayer + "." + c.fromOutput + " -> " + c.toLayer + "." +
              c.toInput + " would make a cycle: a layer may only read layers declared "
              "before it";
      return false;
    }
    if (!connectedInputs.insert({c.toLayer, c.toInput}).second) {
      error = "input '" + c.toLayer + "." + c.toInput + "' is connected twice";
      return false;
    }
  }
  for (const std::string &e : entries)
    if (!index.count(e)) {
      error = "--entry: unknown layer '" + e + "'";
      return false;
    }
  return true;
}

namespace {

/// Splits on whitespace, keeping "quoted strings" (without quotes) and
/// `[[...]]` annotations as single tokens; `#` and `//` start comments.
/// A comma ends a statement as `;` does (OSL's group strings take either).
std::vector<std::string> tokenize(llvm::StringRef text) {
  std::vector<std::string> tokens;
  size_t i = 0;
  while (i < text.size()) {
    char c = text[i];
    if (isspace(static_cast<unsigned char>(c))) {
      ++i;
    } else if (c == '#' || text.substr(i).starts_with("//")) {
      // A comment runs to the end of the line (group files).
      size_t end = text.find('\n', i);
      i = end == llvm::StringRef::npos ? text.size() : end + 1;
    } else if (c == ';' || c == ',') {
      tokens.push_back(";");
      ++i;
    } else if (c == '"') {
      size_t end = text.find('"', i + 1);
      if (end == llvm::StringRef::npos)
        end = text.size();
      tokens.push_back(("\"" + text.slice(i + 1, end)).str());
      i = end + 1;
    } else if (text.substr(i).starts_with("[[")) {
      size_t end = text.find("]]", i);
      end = end == llvm::StringRef::npos ? text.size() : end + 2;
      tokens.push_back(text.slice(i, end).str());
      i = end;
    } else {
      size_t end = i;
      while (end < text.size() && !isspace(static_cast<unsigned char>(text[end])) &&
             text[end] != ';' && text[end] != ',')
        ++end;
      tokens.push_back(text.slice(i, end).str());
      i = end;
    }
  }
  return tokens;
}


} // namespace

bool osl::splitLayerDotName(const std::string &s, std::string &layer, std::string &name) {
  size_t dot = s.rfind('.');
  if (dot == std::string::npos || dot == 0 || dot + 1 == s.size())
    return false;
  layer = s.substr(0, dot);
  name = s.substr(dot + 1);
  return true;
}

bool ShaderGroup::parseStatements(const std::string &text, const std::string &shaderDir,
                                  std::string &error) {
  std::vector<std::string> tokens = tokenize(text);
  size_t i = 0;
  while (i < tokens.size()) {
    size_t end = i;
    while (end < tokens.size() && tokens[end] != ";")
      ++end;
    std::vector<std::string> s(tokens.begin() + long(i), tokens.begin() + long(end));
    i = end + 1;
    if (s.empty())
      continue;
    std::string statement;
    for (const std::string &t : s)
      statement += (statement.empty() ? "" : " ") + t;
    auto bad = [&](const std::string &why) {
      error = "group statement '" + statement + "': " + why;
      return false;
    };
    if (s[0] == "param") {
      bool userdata = false;
      if (!s.empty() && llvm::StringRef(s.back()).starts_with("[[")) {
        userdata = llvm::StringRef(s.back()).contains("lockgeom=0");
        s.pop_back();
      }
      if (s.size() < 4)
        return bad("expected 'param TYPE NAME VALUE... ;'");
      std::string value;
      if (s[1] == "string") {
        value = llvm::StringRef(s[3]).ltrim('"').str();
      } else {
        // Several numbers make a triple, array or matrix. A triple given
        // fewer is filled with zeros, as OSL reads a group's values (a
        // value on testshade's command line fills all three instead).
        std::vector<std::string> numbers(s.begin() + 3, s.end());
        bool triple = s[1] == "color" || s[1] == "point" || s[1] == "vector" ||
                      s[1] == "normal";
        if (triple && numbers.size() < 3)
          numbers.resize(3, "0");
        value = llvm::join(numbers, ",");
      }
      param(s[2], value, userdata);
    } else if (s[0] == "shader") {
      if (s.size() == 2)
        s.push_back(s[1]); // an unnamed layer is named after its shader
      if (s.size() != 3)
        return bad("expected 'shader NAME [LAYER] ;'");
      std::string path = s[1];
      if (!llvm::StringRef(path).ends_with(".osl"))
        path += ".osl";
      if (!shaderDir.empty() && llvm::sys::path::is_relative(path))
        path = (llvm::Twine(shaderDir) + "/" + path).str();
      if (!shader(path, s[2], error))
        return false;
    } else if (s[0] == "connect") {
      GroupConnection c;
      if (s.size() != 3 || !splitLayerDotName(s[1], c.fromLayer, c.fromOutput) ||
          !splitLayerDotName(s[2], c.toLayer, c.toInput))
        return bad("expected 'connect FROMLAYER.OUTPUT TOLAYER.INPUT ;'");
      c.statement = statement;
      connect(std::move(c));
    } else {
      return bad("unknown statement '" + s[0] + "' (expected param, shader or connect)");
    }
  }
  return true;
}
