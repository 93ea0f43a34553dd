//===- SceneXml.cpp - Reading testrender's XML scenes ---------------------===//
#include "OslRender/Scene.h"

#define PUGIXML_NO_XPATH
#define PUGIXML_NO_EXCEPTIONS
#include <OpenImageIO/detail/pugixml/pugixml.hpp>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <sstream>

namespace osl::render {
namespace {

struct Reader {
  std::string path;
  std::string text;
  std::string error;

  int lineOf(ptrdiff_t offset) const {
    if (offset < 0)
      return 0;
    return 1 + int(std::count(text.begin(), text.begin() + std::min<size_t>(offset, text.size()),
                              '\n'));
  }
  bool fail(const pugi::xml_node &node, const std::string &why) {
    error = path + ":" + std::to_string(lineOf(node.offset_debug())) + ": " + why;
    return false;
  }
};

std::vector<std::string> splitWords(const std::string &s) {
  std::vector<std::string> words;
  std::string cur;
  for (char c : s) {
    if (c == ',' || std::isspace(static_cast<unsigned char>(c))) {
      if (!cur.empty())
        words.push_back(cur);
      cur.clear();
    } else {
      cur += c;
    }
  }
  if (!cur.empty())
    words.push_back(cur);
  return words;
}

bool parseFloat(const std::string &s, float &out) {
  char *end = nullptr;
  out = std::strtof(s.c_str(), &end);
  return !s.empty() && end == s.c_str() + s.size() && std::isfinite(out);
}

bool parseVec3(Reader &r, const pugi::xml_node &node, const char *attr, Vec3 &out,
               bool required) {
  pugi::xml_attribute a = node.attribute(attr);
  if (!a)
    return required ? r.fail(node, std::string("<") + node.name() + "> needs " + attr) : true;
  std::vector<std::string> w = splitWords(a.value());
  float v[3];
  if (w.size() != 3 || !parseFloat(w[0], v[0]) || !parseFloat(w[1], v[1]) ||
      !parseFloat(w[2], v[2]))
    return r.fail(node, std::string(attr) + "=\"" + a.value() + "\" is not three numbers");
  out = Vec3(v[0], v[1], v[2]);
  return true;
}

bool parseScalar(Reader &r, const pugi::xml_node &node, const char *attr, float &out,
                 bool required) {
  pugi::xml_attribute a = node.attribute(attr);
  if (!a)
    return required ? r.fail(node, std::string("<") + node.name() + "> needs " + attr) : true;
  if (!parseFloat(a.value(), out))
    return r.fail(node, std::string(attr) + "=\"" + a.value() + "\" is not a number");
  return true;
}

const char *const kTypeNames[] = {"int", "float", "color", "point", "vector", "normal", "string"};

bool isTypeName(const std::string &w) {
  return std::find_if(std::begin(kTypeNames), std::end(kTypeNames),
                      [&](const char *t) { return w == t; }) != std::end(kTypeNames);
}

/// A parameter value as ParamOverride text: numbers as written, triples
/// "a,b,c", strings without quotes. `words` may start with a type name.
bool paramText(std::vector<std::string> words, std::string &text, std::string &why) {
  std::string type;
  if (!words.empty() && isTypeName(words[0])) {
    type = words[0];
    words.erase(words.begin());
  }
  if (words.empty()) {
    why = "has no value";
    return false;
  }
  if (type == "string") {
    std::string s;
    for (size_t i = 0; i < words.size(); ++i)
      s += (i ? " " : "") + words[i];
    if (s.size() >= 2 && s.front() == '"' && s.back() == '"')
      s = s.substr(1, s.size() - 2);
    text = s;
    return true;
  }
  bool triple = type == "color" || type == "point" || type == "vector" || type == "normal";
  if (triple && words.size() == 1)
    words.assign(3, words[0]);
  if ((triple && words.size() != 3) || (!triple && !type.empty() && words.size() != 1)) {
    why = "needs " + std::string(triple ? "3 values" : "1 value") + " for type " + type;
    return false;
  }
  text.clear();
  for (size_t i = 0; i < words.size(); ++i)
    text += (i ? "," : "") + words[i];
  return true;
}

/// The group's statements in testshade's syntax: `TYPE NAME VALUES;`
/// (optionally after `param`), `shader NAME LAYER;`.
bool parseGroupText(Reader &r, const pugi::xml_node &node, ShaderInstance &inst, int &layers) {
  std::stringstream ss(node.text().get());
  std::string stmt;
  std::vector<ParamOverride> pending;
  while (std::getline(ss, stmt, ';')) {
    std::vector<std::string> w = splitWords(stmt);
    if (w.empty())
      continue;
    if (w[0] == "shader") {
      if (w.size() != 3)
        return r.fail(node, "'shader' takes a shader name and a layer name: '" + stmt + "'");
      inst.shader = w[1];
      inst.layer = w[2];
      inst.params = pending;
      ++layers;
      continue;
    }
    if (w[0] == "connect")
      return r.fail(node, "connections between layers are not supported by --scene yet");
    if (w[0] == "param")
      w.erase(w.begin());
    if (w.size() < 3 || !isTypeName(w[0]))
      return r.fail(node, "expected 'TYPE NAME VALUE...;' or 'shader NAME LAYER;', got '" +
                              stmt + "'");
    std::string name = w[1];
    w.erase(w.begin() + 1);
    std::string text, why;
    if (!paramText(w, text, why))
      return r.fail(node, "parameter '" + name + "' " + why);
    pending.push_back({name, text});
  }
  return true;
}

bool parseGroup(Reader &r, const pugi::xml_node &group, ShaderInstance &inst) {
  inst.line = r.lineOf(group.offset_debug());
  int layers = 0;
  std::vector<ParamOverride> pending;
  for (pugi::xml_node c : group.children()) {
    if (c.type() == pugi::node_pcdata) {
      if (!parseGroupText(r, group, inst, layers))
        return false;
      continue;
    }
    if (c.type() != pugi::node_element)
      continue;
    if (!std::strcmp(c.name(), "Parameter")) {
      for (pugi::xml_attribute a : c.attributes()) {
        std::string text, why;
        if (!paramText(splitWords(a.value()), text, why))
          return r.fail(c, "parameter '" + std::string(a.name()) + "' " + why);
        pending.push_back({a.name(), text});
      }
    } else if (!std::strcmp(c.name(), "Shader")) {
      inst.shader = c.attribute("name").value();
      inst.layer = c.attribute("layer").value();
      if (inst.shader.empty())
        return r.fail(c, "<Shader> needs name");
      inst.params = pending;
      pending.clear();
      ++layers;
    } else if (!std::strcmp(c.name(), "ConnectShaders")) {
      return r.fail(c, "connections between layers are not supported by --scene yet");
    } else {
      return r.fail(c, std::string("unknown element <") + c.name() + "> in <ShaderGroup>");
    }
  }
  if (layers == 0)
    return r.fail(group, "<ShaderGroup> names no shader");
  if (layers > 1)
    return r.fail(group, "<ShaderGroup> with several layers is not supported by --scene yet");
  return true;
}

} // namespace

bool loadScene(const std::string &path, Scene &scene, std::string &error) {
  Reader r;
  r.path = path;
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    error = path + ": cannot open the scene file";
    return false;
  }
  r.text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  pugi::xml_document doc;
  pugi::xml_parse_result parsed = doc.load_buffer(r.text.data(), r.text.size());
  if (!parsed) {
    error = path + ":" + std::to_string(r.lineOf(parsed.offset)) + ": " + parsed.description();
    return false;
  }
  pugi::xml_node world = doc.child("World");
  if (!world) {
    error = path + ": no <World> element";
    return false;
  }
  scene = Scene();
  int currentShader = -1;
  bool ok = true;
  for (pugi::xml_node node : world.children()) {
    if (node.type() != pugi::node_element)
      continue;
    std::string name = node.name();
    if (name == "Camera") {
      ok = parseVec3(r, node, "eye", scene.camera.eye, false) &&
           parseVec3(r, node, "look_at", scene.camera.lookAt, false) &&
           parseVec3(r, node, "up", scene.camera.up, false) &&
           parseScalar(r, node, "fov", scene.camera.fovDegrees, false);
      if (ok && !(scene.camera.fovDegrees > 0 && scene.camera.fovDegrees < 180))
        ok = r.fail(node, "fov must be between 0 and 180 degrees");
    } else if (name == "ShaderGroup") {
      ShaderInstance inst;
      ok = parseGroup(r, node, inst);
      scene.shaders.push_back(inst);
      currentShader = int(scene.shaders.size()) - 1;
    } else if (name == "Background") {
      if (currentShader < 0)
        ok = r.fail(node, "<Background> needs a <ShaderGroup> before it");
      scene.background = currentShader;
    } else if (name == "Sphere" || name == "Quad") {
      Primitive p;
      p.shader = currentShader;
      p.isLight = node.attribute("is_light").as_int(0) != 0;
      if (name == "Sphere") {
        p.kind = Primitive::Sphere;
        ok = parseVec3(r, node, "center", p.center, true) &&
             parseScalar(r, node, "radius", p.radius, true);
        if (ok && !(p.radius > 0))
          ok = r.fail(node, "radius must be positive");
      } else {
        p.kind = Primitive::Quad;
        ok = parseVec3(r, node, "corner", p.corner, true) &&
             parseVec3(r, node, "edge_x", p.edgeX, true) &&
             parseVec3(r, node, "edge_y", p.edgeY, true);
        if (ok && !(length(cross(p.edgeX, p.edgeY)) > 0))
          ok = r.fail(node, "the quad's edges are parallel");
      }
      scene.prims.push_back(p);
    } else {
      ok = r.fail(node, "unknown element <" + name + ">");
    }
    if (!ok) {
      error = r.error;
      return false;
    }
  }
  if (scene.prims.empty()) {
    error = path + ": the scene has no primitives";
    return false;
  }
  return true;
}

} // namespace osl::render
