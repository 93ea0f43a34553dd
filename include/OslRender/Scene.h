//===- Scene.h - OSL testrender's XML scenes --------------------*- C++ -*-===//
//
// What osl-run --scene reads: a camera, spheres and quads each shaded by the
// shader group before it, an optional background group, and which
// primitives are lights (is_light="1"). Parameters come as XML attributes
// (`<Parameter Cd="color 0.8 0.8 0.8"/>`) or as the group's text in
// testshade's group syntax (`color Cd 0.8 0.8 0.8; shader matte ball;`). A
// group may have several layers wired by connections (`<ConnectShaders
// srclayer= srcparam= dstlayer= dstparam=/>` or `connect a.out b.in;`);
// the last layer is the root, whose Ci shades.
//
//===----------------------------------------------------------------------===//
#ifndef OSLRENDER_SCENE_H
#define OSLRENDER_SCENE_H

#include "OslCompiler/ShaderGroup.h"
#include "OslFrontend/Frontend.h"
#include "OslRender/Vec3.h"

#include <string>
#include <vector>

namespace osl::render {

struct Camera {
  Vec3 eye{0, 0, 0};
  /// The view direction: dir="...", or look_at minus eye (as testrender).
  Vec3 dir{0, 0, -1};
  Vec3 up{0, 1, 0};
  float fovDegrees = 90;
};

/// One shader instance: the shader's name (found as NAME.osl), its layer
/// name and its instance parameter values.
struct ShaderInstance {
  std::string shader;
  std::string layer;
  std::vector<ParamOverride> params;
};

/// A <ShaderGroup>: its layers in order and their connections.
struct SceneGroup {
  std::vector<ShaderInstance> layers;
  std::vector<GroupConnection> connections;
  int line = 0; // where the group starts in the scene file
};

struct Primitive {
  enum Kind { Sphere, Quad } kind = Sphere;
  Vec3 center; // Sphere
  float radius = 0;
  Vec3 corner, edgeX, edgeY; // Quad
  int shader = -1;           // index into Scene::shaders, -1: none
  bool isLight = false;
};

struct Scene {
  Camera camera;
  std::vector<SceneGroup> shaders;
  std::vector<Primitive> prims;
  int background = -1; // the shader escaping rays see
  /// <Background resolution="N"/>: the side of the table that importance
  /// samples the background (testrender's default 1024; 0: the background
  /// is not sampled, only seen).
  int backgroundResolution = 1024;
  /// <Option max_bounces="int N"/>, -1 when the scene does not say.
  int maxBounces = -1;
};

/// Reads a testrender scene. On error returns false with "FILE:LINE: why"
/// in `error`.
bool loadScene(const std::string &path, Scene &scene, std::string &error);

} // namespace osl::render

#endif // OSLRENDER_SCENE_H
