//===- SceneXml.cpp - Reading testrender's XML scenes ---------------------===//
#include "OslRender/Scene.h"

// Configured as Dictionaries.cpp configures it (one definition of pugixml).
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

/// Adds a layer; unnamed layers are called after their position.
bool addLayer(Reader &r, const pugi::xml_node &node, SceneGroup &group, std::string shader,
              std::string layer, std::vector<ParamOverride> &pending) {
  if (layer.empty())
    layer = "layer" + std::to_string(group.layers.size());
  for (const ShaderInstance &l : group.layers)
    if (l.layer == layer)
      return r.fail(node, "layer '" + layer + "' is declared twice in the group");
  group.layers.push_back({std::move(shader), std::move(layer), std::move(pending)});
  pending.clear();
  return true;
}

bool addConnection(Reader &r, const pugi::xml_node &node, SceneGroup &group,
                   GroupConnection c) {
  for (const std::string *name : {&c.fromLayer, &c.toLayer})
    if (std::none_of(group.layers.begin(), group.layers.end(),
                     [&](const ShaderInstance &l) { return l.layer == *name; }))
      return r.fail(node, "connect: unknown layer '" + *name +
                              "' (layers must be declared before they are connected)");
  group.connections.push_back(std::move(c));
  return true;
}

/// The group's statements in testshade's syntax: `TYPE NAME VALUES;`
/// (optionally after `param`), `shader NAME LAYER;`, `connect A.OUT B.IN;`.
bool parseGroupText(Reader &r, const pugi::xml_node &node, SceneGroup &group,
                    std::vector<ParamOverride> &pending) {
  std::stringstream ss(node.text().get());
  std::string stmt;
  while (std::getline(ss, stmt, ';')) {
    std::vector<std::string> w = splitWords(stmt);
    if (w.empty())
      continue;
    if (w[0] == "shader") {
      if (w.size() != 3)
        return r.fail(node, "'shader' takes a shader name and a layer name: '" + stmt + "'");
      if (!addLayer(r, node, group, w[1], w[2], pending))
        return false;
      continue;
    }
    if (w[0] == "connect") {
      GroupConnection c;
      if (w.size() != 3 || !splitLayerDotName(w[1], c.fromLayer, c.fromOutput) ||
          !splitLayerDotName(w[2], c.toLayer, c.toInput))
        return r.fail(node, "'connect' takes LAYER.OUTPUT LAYER.INPUT: '" + stmt + "'");
      if (!addConnection(r, node, group, std::move(c)))
        return false;
      continue;
    }
    if (w[0] == "param")
      w.erase(w.begin());
    if (w.size() < 3 || !isTypeName(w[0]))
      return r.fail(node, "expected 'TYPE NAME VALUE...;', 'shader NAME LAYER;' or "
                          "'connect A.OUT B.IN;', got '" + stmt + "'");
    std::string name = w[1];
    w.erase(w.begin() + 1);
    std::string text, why;
    if (!paramText(w, text, why))
      return r.fail(node, "parameter '" + name + "' " + why);
    pending.push_back({name, text});
  }
  return true;
}

bool parseGroup(Reader &r, const pugi::xml_node &node, SceneGroup &group) {
  group.line = r.lineOf(node.offset_debug());
  std::vector<ParamOverride> pending;
  for (pugi::xml_node c : node.children()) {
    if (c.type() == pugi::node_pcdata) {
      if (!parseGroupText(r, node, group, pending))
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
      std::string name = c.attribute("name").value();
      if (name.empty())
        return r.fail(c, "<Shader> needs name");
      if (!addLayer(r, c, group, name, c.attribute("layer").value(), pending))
        return false;
    } else if (!std::strcmp(c.name(), "ConnectShaders")) {
      GroupConnection conn{c.attribute("srclayer").value(), c.attribute("srcparam").value(),
                           c.attribute("dstlayer").value(), c.attribute("dstparam").value()};
      if (conn.fromLayer.empty() || conn.fromOutput.empty() || conn.toLayer.empty() ||
          conn.toInput.empty())
        return r.fail(c, "<ConnectShaders> needs srclayer, srcparam, dstlayer and dstparam");
      if (!addConnection(r, c, group, std::move(conn)))
        return false;
    } else {
      return r.fail(c, std::string("unknown element <") + c.name() + "> in <ShaderGroup>");
    }
  }
  if (group.layers.empty())
    return r.fail(node, "<ShaderGroup> names no shader");
  if (!pending.empty())
    return r.fail(node, "parameter '" + pending.front().name + "' comes after the last shader");
  return true;
}

/// <Option NAME="TYPE VALUE"/>: the renderer settings a scene may fix.
bool parseOption(Reader &r, const pugi::xml_node &node, Scene &scene) {
  for (pugi::xml_attribute a : node.attributes()) {
    std::vector<std::string> w = splitWords(a.value());
    if (!w.empty() && isTypeName(w[0]))
      w.erase(w.begin());
    if (std::string(a.name()) != "max_bounces")
      return r.fail(node, "unknown option '" + std::string(a.name()) +
                              "' (osl-run --scene knows max_bounces)");
    char *end = nullptr;
    long n = w.size() == 1 ? std::strtol(w[0].c_str(), &end, 10) : -1;
    if (w.size() != 1 || *end || n < 0 || n > 1000000)
      return r.fail(node, "max_bounces needs a whole number from 0 to 1000000");
    scene.maxBounces = int(n);
  }
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
      // look_at="x,y,z", or dir="x,y,z" (the view direction).
      Vec3 dir = scene.camera.dir, lookAt;
      bool hasDir = bool(node.attribute("dir")), hasLookAt = bool(node.attribute("look_at"));
      ok = parseVec3(r, node, "eye", scene.camera.eye, false) &&
           parseVec3(r, node, "look_at", lookAt, false) &&
           parseVec3(r, node, "dir", dir, false) &&
           parseVec3(r, node, "up", scene.camera.up, false) &&
           parseScalar(r, node, "fov", scene.camera.fovDegrees, false);
      if (ok && !(scene.camera.fovDegrees > 0 && scene.camera.fovDegrees < 180))
        ok = r.fail(node, "fov must be between 0 and 180 degrees");
      if (ok && !hasDir && hasLookAt)
        dir = lookAt - scene.camera.eye;
      if (ok && !(length(dir) > 0))
        ok = r.fail(node, hasDir ? "dir must not be zero" : "look_at must not be the eye");
      scene.camera.dir = dir;
    } else if (name == "Option") {
      ok = parseOption(r, node, scene);
    } else if (name == "ShaderGroup") {
      SceneGroup group;
      ok = parseGroup(r, node, group);
      scene.shaders.push_back(std::move(group));
      currentShader = int(scene.shaders.size()) - 1;
    } else if (name == "Background") {
      if (currentShader < 0)
        ok = r.fail(node, "<Background> needs a <ShaderGroup> before it");
      scene.background = currentShader;
      float resolution = float(scene.backgroundResolution);
      ok = ok && parseScalar(r, node, "resolution", resolution, false);
      scene.backgroundResolution = int(resolution);
    } else if (name == "Sphere" || name == "Quad") {
      Primitive p;
      p.shader = currentShader;
      // is_light="1" or "yes" (testrender's scenes write both).
      p.isLight = node.attribute("is_light").as_bool(false);
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
