//===- SceneXmlTest.cpp - testrender scenes and their errors --------------===//
#include "OslRender/Scene.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>

using namespace osl::render;

namespace {

std::string writeScene(const std::string &text) {
  char name[] = "/tmp/osl-scene-XXXXXX";
  int fd = mkstemp(name);
  if (fd >= 0)
    close(fd);
  std::ofstream(name) << text;
  return name;
}

TEST(SceneXmlTest, ReadsCameraGroupsPrimitivesAndBackground) {
  std::string path = writeScene(R"(<World>
  <Camera eye="0, 1, 4" look_at="0,0.5,0" fov="45" />
  <ShaderGroup>color zenith 0.1 0.2 0.3; shader sky env;</ShaderGroup>
  <Background />
  <ShaderGroup>
    <Parameter Cd="color 0.5 0.6 0.7" />
    <Parameter distribution="ggx" />
    <Parameter octaves="int 4" />
    <Shader name="matte" layer="ball" />
  </ShaderGroup>
  <Sphere center="0, 0.6, 0" radius="0.6" />
  <Quad corner="-1,0,-1" edge_x="2,0,0" edge_y="0,0,2" is_light="1" />
</World>)");
  Scene scene;
  std::string error;
  ASSERT_TRUE(loadScene(path, scene, error)) << error;
  std::remove(path.c_str());
  EXPECT_FLOAT_EQ(scene.camera.fovDegrees, 45);
  EXPECT_FLOAT_EQ(scene.camera.eye.y, 1);
  ASSERT_EQ(scene.shaders.size(), 2u);
  EXPECT_EQ(scene.background, 0);
  ASSERT_EQ(scene.shaders[0].layers.size(), 1u);
  const ShaderInstance &sky = scene.shaders[0].layers[0];
  EXPECT_EQ(sky.shader, "sky");
  ASSERT_EQ(sky.params.size(), 1u);
  EXPECT_EQ(sky.params[0].value, "0.1,0.2,0.3");
  ASSERT_EQ(scene.shaders[1].layers.size(), 1u);
  const ShaderInstance &ball = scene.shaders[1].layers[0];
  EXPECT_EQ(ball.layer, "ball");
  ASSERT_EQ(ball.params.size(), 3u);
  EXPECT_EQ(ball.params[0].value, "0.5,0.6,0.7");
  EXPECT_EQ(ball.params[1].value, "ggx");
  EXPECT_EQ(ball.params[2].value, "4");
  ASSERT_EQ(scene.prims.size(), 2u);
  EXPECT_EQ(scene.prims[0].kind, Primitive::Sphere);
  EXPECT_EQ(scene.prims[0].shader, 1);
  EXPECT_TRUE(scene.prims[1].isLight);
}

TEST(SceneXmlTest, ReadsLayersAndConnectionsInBothSyntaxes) {
  std::string path = writeScene(R"(<World>
  <ShaderGroup>
    param float scale 4; shader checker tex;
    shader matte surf; connect tex.Cout surf.Cd;
  </ShaderGroup>
  <ShaderGroup>
    <Parameter scale="float 2" />
    <Shader name="checker" layer="tex" />
    <Shader name="matte" />
    <ConnectShaders srclayer="tex" srcparam="Cout" dstlayer="layer1" dstparam="Cd" />
  </ShaderGroup>
  <Sphere center="0, 0.6, 0" radius="0.6" />
</World>)");
  Scene scene;
  std::string error;
  ASSERT_TRUE(loadScene(path, scene, error)) << error;
  std::remove(path.c_str());
  ASSERT_EQ(scene.shaders.size(), 2u);
  for (const SceneGroup &g : scene.shaders) {
    ASSERT_EQ(g.layers.size(), 2u);
    EXPECT_EQ(g.layers[0].layer, "tex");
    ASSERT_EQ(g.layers[0].params.size(), 1u);
    EXPECT_TRUE(g.layers[1].params.empty());
    ASSERT_EQ(g.connections.size(), 1u);
    EXPECT_EQ(g.connections[0].fromLayer, "tex");
    EXPECT_EQ(g.connections[0].fromOutput, "Cout");
    EXPECT_EQ(g.connections[0].toLayer, g.layers[1].layer);
    EXPECT_EQ(g.connections[0].toInput, "Cd");
  }
  EXPECT_EQ(scene.shaders[1].layers[1].layer, "layer1");
}

TEST(SceneXmlTest, ErrorsNameTheFileAndLine) {
  struct Case {
    const char *text, *expected;
  } cases[] = {
      {"<World>\n<Sphere center=\"0,0,0\" radius=\"-1\"/>\n</World>", ":2: radius must be positive"},
      {"<World>\n\n<Sphere center=\"0,0\" radius=\"1\"/>\n</World>", ":3: center=\"0,0\" is not three numbers"},
      {"<World>\n<Cube/>\n</World>", ":2: unknown element <Cube>"},
      {"<World>\n<Background/>\n</World>", ":2: <Background> needs a <ShaderGroup>"},
      {"<World>\n<ShaderGroup>float Kd; shader matte m;</ShaderGroup>\n</World>",
       "expected 'TYPE NAME VALUE...;'"},
      {"<World>\n<ShaderGroup>shader a x; shader b y; connect x.o z.i;</ShaderGroup>\n</World>",
       ":2: connect: unknown layer 'z'"},
      {"<World>\n<ShaderGroup>shader a x; connect x y.i;</ShaderGroup>\n</World>",
       "'connect' takes LAYER.OUTPUT LAYER.INPUT"},
      {"<World>\n<ShaderGroup>shader a x; shader b x;</ShaderGroup>\n</World>",
       "layer 'x' is declared twice"},
      {"<World>\n<ShaderGroup><Shader name=\"a\"/><ConnectShaders srclayer=\"layer0\"/>"
       "</ShaderGroup>\n</World>",
       "<ConnectShaders> needs srclayer, srcparam, dstlayer and dstparam"},
      {"<World><Sphere center=\"0,0,0\" radius=\"1\">", ":1: "},
      {"<Scene/>", "no <World> element"},
  };
  for (const Case &c : cases) {
    std::string path = writeScene(c.text);
    Scene scene;
    std::string error;
    EXPECT_FALSE(loadScene(path, scene, error)) << c.text;
    std::remove(path.c_str());
    EXPECT_NE(error.find(c.expected), std::string::npos) << error;
    EXPECT_EQ(error.rfind(path, 0), 0u) << error;
  }
  Scene scene;
  std::string error;
  EXPECT_FALSE(loadScene("/nonexistent/scene.xml", scene, error));
  EXPECT_NE(error.find("cannot open"), std::string::npos);
}

} // namespace
