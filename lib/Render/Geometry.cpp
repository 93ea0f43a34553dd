//===- Geometry.cpp - Spheres and quads -----------------------------------===//
#include "OslRender/Geometry.h"
#include "OslRender/RenderMath.h"

#include <algorithm>
#include <cmath>

namespace osl::render {
namespace {

constexpr float kPi = 3.14159265358979f;

} // namespace

LightSample sampleLight(const Primitive &prim, Vec3 x, float rx, float ry) {
  LightSample s;
  if (prim.kind == Primitive::Sphere) {
    Vec3 toC = prim.center - x;
    float d2 = dot(toC, toC), r2 = prim.radius * prim.radius;
    if (d2 <= r2)
      return s; // inside the light: not sampled
    float cosMax = std::sqrt(std::max(0.0f, 1 - r2 / d2));
    float cosT = 1 - rx * (1 - cosMax), sinT = std::sqrt(std::max(0.0f, 1 - cosT * cosT));
    float sinPhi, cosPhi;
    polySinCos(2 * kPi * ry, sinPhi, cosPhi);
    Frame f(toC / std::sqrt(d2));
    s.dir = f.toWorld(Vec3(sinT * cosPhi, sinT * sinPhi, cosT));
    s.pdf = 1 / (2 * kPi * (1 - cosMax));
    return s;
  }
  Vec3 p = prim.corner + prim.edgeX * rx + prim.edgeY * ry;
  Vec3 d = p - x;
  float d2 = dot(d, d);
  if (!(d2 > 0))
    return s;
  s.dir = d / std::sqrt(d2);
  s.pdf = lightPdf(prim, x, p);
  return s;
}

float surfaceArea(const Primitive &prim) {
  // A sphere answers its silhouette's area, pi r^2, as testrender's does:
  // an emitter dividing its power by pi * surfacearea() then has
  // testrender's brightness.
  if (prim.kind == Primitive::Sphere)
    return kPi * prim.radius * prim.radius;
  return length(cross(prim.edgeX, prim.edgeY));
}

float lightPdf(const Primitive &prim, Vec3 x, Vec3 p) {
  if (prim.kind == Primitive::Sphere) {
    Vec3 toC = prim.center - x;
    float d2 = dot(toC, toC), r2 = prim.radius * prim.radius;
    if (d2 <= r2)
      return 0;
    float cosMax = std::sqrt(std::max(0.0f, 1 - r2 / d2));
    return 1 / (2 * kPi * (1 - cosMax));
  }
  Vec3 n = cross(prim.edgeX, prim.edgeY);
  float area = length(n);
  Vec3 d = p - x;
  float d2 = dot(d, d);
  float cosL = std::fabs(dot(n / area, d / std::sqrt(d2)));
  return cosL > 1e-6f ? d2 / (area * cosL) : 0;
}

} // namespace osl::render
