//===- TestScene.h - A small scene the render tests trace -------*- C++ -*-===//
#ifndef OSLRENDER_UNITTESTS_TESTSCENE_H
#define OSLRENDER_UNITTESTS_TESTSCENE_H

#include "OslRender/Scene.h"

#include <cstring>

namespace osl::render::testing {

/// Two spheres in front of the camera over a floor (y = -1), before a
/// back wall (z = -8).
inline Scene boxWithSpheres() {
  Scene scene;
  Primitive s;
  s.kind = Primitive::Sphere;
  s.center = Vec3(0, 0, -5);
  s.radius = 1;
  scene.prims.push_back(s);
  s.center = Vec3(1.5f, 0.5f, -3);
  s.radius = 0.5f;
  scene.prims.push_back(s);
  Primitive q;
  q.kind = Primitive::Quad; // the floor, y = -1
  q.corner = Vec3(-4, -1, -8);
  q.edgeX = Vec3(8, 0, 0);
  q.edgeY = Vec3(0, 0, 8);
  scene.prims.push_back(q);
  q.corner = Vec3(-4, -1, -8); // the back wall, z = -8
  q.edgeX = Vec3(0, 8, 0);
  q.edgeY = Vec3(8, 0, 0);
  scene.prims.push_back(q);
  return scene;
}

/// A point in the box around the spheres from three uniform numbers.
inline Vec3 pointInBox(Vec3 r) { return Vec3(4 * r.x - 2, 2 * r.y - 0.5f, -6 * r.z); }

inline bool sameBits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

} // namespace osl::render::testing

#endif // OSLRENDER_UNITTESTS_TESTSCENE_H
