//===- Geometry.cpp - Spheres and quads -----------------------------------===//
#include "OslRender/Geometry.h"

#include <cmath>

namespace osl::render {
namespace {

constexpr float kPi = 3.14159265358979f;

} // namespace

float surfaceArea(const Primitive &prim) {
  // A sphere answers its silhouette's area, pi r^2, as testrender's does:
  // an emitter dividing its power by pi * surfacearea() then has
  // testrender's brightness.
  if (prim.kind == Primitive::Sphere)
    return kPi * (prim.radius * prim.radius);
  return length(cross(prim.edgeX, prim.edgeY));
}

} // namespace osl::render
