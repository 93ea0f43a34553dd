//===- Bsdf.cpp - Lobe models and their mixture ---------------------------===//
//
// Each model gives f*cos and the pdf of its own sampling, so the mixture
// can combine lobes with one-sample MIS (the pdf of a direction is the
// pick-weighted sum of every lobe's pdf). Specular lobes (reflection,
// refraction, transparent) are deltas: sampled only, never evaluated.
//
//===----------------------------------------------------------------------===//
#include "OslRender/Bsdf.h"
#include "CosineLobes.h"
#include "OslRender/RenderMath.h"

#include <algorithm>
#include <cmath>

namespace osl::render {
namespace {

constexpr float kPi = 3.14159265358979f;
constexpr float kInvPi = 1.0f / kPi;
constexpr float kInf = std::numeric_limits<float>::infinity();

Vec3 reflect(Vec3 wo, Vec3 n) { return n * (2 * dot(wo, n)) - wo; }

/// Refraction of wo (on n's side) into the other side for relative index
/// eta (transmitted over incident); false at total internal reflection.
bool refract(Vec3 wo, Vec3 n, float eta, Vec3 &wi) {
  float cosi = dot(wo, n);
  float sin2t = (1 - cosi * cosi) / (eta * eta);
  if (sin2t >= 1)
    return false;
  float cost = std::sqrt(1 - sin2t);
  wi = normalize(-wo / eta + n * (cosi / eta - cost));
  return true;
}

float sqr(float x) { return x * x; }

float conductorChannel(float c, float n, float k) {
  float c2 = c * c, s2 = 1 - c2;
  float t0 = n * n - k * k - s2;
  float a2b2 = std::sqrt(std::max(0.0f, t0 * t0 + 4 * n * n * k * k));
  float a = std::sqrt(std::max(0.0f, 0.5f * (a2b2 + t0)));
  float t1 = a2b2 + c2, t2 = 2 * c * a;
  float rs = (t1 - t2) / (t1 + t2);
  float t3 = c2 * a2b2 + s2 * s2, t4 = t2 * s2;
  float rp = rs * (t3 - t4) / (t3 + t4);
  return 0.5f * (rs + rp);
}

/// A microfacet lobe's Fresnel reflectance at cos(wo, m).
Vec3 microfacetFresnel(const Lobe &l, float cosom) {
  switch (l.fresnel) {
  case 1:
    return {conductorChannel(cosom, l.ior.x, l.kappa.x),
            conductorChannel(cosom, l.ior.y, l.kappa.y),
            conductorChannel(cosom, l.ior.z, l.kappa.z)};
  case 2: {
    float k = std::pow(std::max(0.0f, 1 - cosom), l.exponent);
    return l.f0 + (l.f90 - l.f0) * k;
  }
  default: {
    float f = fresnelDielectric(cosom, l.eta);
    return {f, f, f};
  }
  }
}

//===----------------------------------------------------------------------===//
// Microfacet distributions (local frame: z = normal)
//===----------------------------------------------------------------------===//

float microfacetD(const Lobe &l, Vec3 m) {
  if (m.z <= 0)
    return 0;
  float ax = l.a, ay = l.b;
  float e = sqr(m.x / ax) + sqr(m.y / ay);
  float z2 = m.z * m.z;
  if (l.dist == 0)
    return 1 / (kPi * ax * ay * sqr(e + z2));
  return std::exp(-e / z2) / (kPi * ax * ay * z2 * z2);
}

float smithLambda(const Lobe &l, Vec3 v) {
  float z2 = v.z * v.z;
  if (z2 <= 0)
    return 0;
  float a2 = (sqr(v.x * l.a) + sqr(v.y * l.b)) / z2; // tan^2 * alpha^2
  if (l.dist == 0)
    return 0.5f * (-1 + std::sqrt(1 + a2));
  if (a2 <= 0)
    return 0;
  float a = 1 / std::sqrt(a2);
  return a < 1.6f ? (1 - 1.259f * a + 0.396f * a * a) / (3.535f * a + 2.181f * a * a) : 0;
}

/// A normal drawn with density D(m) cos(m), by sampling slopes.
Vec3 sampleMicrofacetNormal(const Lobe &l, float rx, float ry) {
  float phi = 2 * kPi * ry;
  float r = l.dist == 0 ? std::sqrt(rx / std::max(1e-7f, 1 - rx))
                        : std::sqrt(-std::log(std::max(1e-7f, 1 - rx)));
  float s, c;
  polySinCos(phi, s, c);
  float sx = r * c * l.a, sy = r * s * l.b;
  return normalize(Vec3(-sx, -sy, 1));
}

/// f*cos and pdf of a microfacet lobe, local wo and wi.
BsdfEval evalMicrofacet(const Lobe &l, Vec3 wo, Vec3 wi) {
  BsdfEval r;
  if (wo.z <= 0 || wi.z == 0)
    return r;
  bool reflect = wi.z > 0;
  if ((reflect && l.refract == 1) || (!reflect && l.refract == 0))
    return r;
  Vec3 m = reflect ? normalize(wo + wi) : normalize(-(wo + wi * l.eta));
  if (m.z < 0)
    m = -m;
  float cosom = dot(wo, m), cosim = dot(wi, m);
  if (cosom <= 0 || (reflect ? cosim <= 0 : cosim >= 0))
    return r;
  float d = microfacetD(l, m);
  float g2 = 1 / (1 + smithLambda(l, wo) + smithLambda(l, wi));
  Vec3 f = microfacetFresnel(l, cosom);
  float pickR = l.refract == 2 ? std::clamp(luminance(f), 0.0f, 1.0f) : l.refract == 0 ? 1 : 0;
  float pdfM = d * m.z;
  if (reflect) {
    r.value = l.tintR * f * (d * g2 / (4 * wo.z));
    r.pdf = pickR * pdfM / (4 * cosom);
  } else {
    float denom = sqr(cosom + l.eta * cosim);
    float jac = l.eta * l.eta * std::fabs(cosim) / denom;
    // Throughput-conserving (eta^2 folded in): paths that enter and leave
    // an object carry radiance unchanged, as testrender's do.
    r.value = l.tintT * (Vec3(1, 1, 1) - f) * (d * g2 * cosom * jac / wo.z);
    r.pdf = (1 - pickR) * pdfM * jac;
  }
  return r;
}

BsdfSample sampleMicrofacet(const Lobe &l, Vec3 wo, float rx, float ry, float rz,
                            const Frame &frame) {
  BsdfSample s;
  if (wo.z <= 0)
    return s;
  Vec3 m = sampleMicrofacetNormal(l, rx, ry);
  float cosom = dot(wo, m);
  if (cosom <= 0)
    return s;
  Vec3 f = microfacetFresnel(l, cosom);
  bool reflectIt = l.refract == 0;
  if (l.refract == 2)
    reflectIt = rz < std::clamp(luminance(f), 0.0f, 1.0f);
  Vec3 wi;
  if (reflectIt) {
    wi = reflect(wo, m);
    if (wi.z <= 0)
      return s;
  } else if (!refract(wo, m, l.eta, wi) || wi.z >= 0) {
    return s;
  }
  return sampledDirection(frame.toWorld(wi), evalMicrofacet(l, wo, wi));
}

//===----------------------------------------------------------------------===//
// Ward (Walter's normalisation)
//===----------------------------------------------------------------------===//

BsdfEval evalWard(const Lobe &l, Vec3 wo, Vec3 wi) {
  BsdfEval r;
  if (wo.z <= 0 || wi.z <= 0)
    return r;
  Vec3 h = normalize(wo + wi);
  float e = (sqr(h.x / l.a) + sqr(h.y / l.b)) / (h.z * h.z);
  float k = std::exp(-e) / (4 * kPi * l.a * l.b);
  float f = k / std::sqrt(wo.z * wi.z);
  r.value = Vec3(1, 1, 1) * (f * wi.z);
  r.pdf = k / (dot(wo, h) * h.z * h.z * h.z);
  return r;
}

BsdfSample sampleWard(const Lobe &l, Vec3 wo, float rx, float ry, const Frame &frame) {
  float s0, c0, c, sn;
  polySinCos(2 * kPi * ry, s0, c0);
  polySinCos(polyAtan2(l.b * s0, l.a * c0), sn, c);
  float tan2 = -std::log(std::max(1e-7f, 1 - rx)) / (sqr(c / l.a) + sqr(sn / l.b));
  float cosh = 1 / std::sqrt(1 + tan2), sinh = std::sqrt(tan2) * cosh;
  Vec3 h(sinh * c, sinh * sn, cosh);
  Vec3 wi = reflect(wo, h);
  return sampledDirection(frame.toWorld(wi), evalWard(l, wo, wi));
}

//===----------------------------------------------------------------------===//
// Diffuse-like lobes: cosine sampled on their side
//===----------------------------------------------------------------------===//

/// The Charlie sheen distribution's f with Neubelt and Pettineo's
/// visibility, local directions on the same side.
float sheenF(const Lobe &l, Vec3 wo, Vec3 wi) {
  Vec3 h = normalize(wo + wi);
  float r = std::max(l.a, 1e-3f), inv = 1 / r;
  float sin2 = std::max(0.0f, 1 - h.z * h.z);
  float d = (2 + inv) * std::pow(sin2, 0.5f * inv) / (2 * kPi);
  float v = 1 / (4 * (wi.z + wo.z - wi.z * wo.z));
  return d * v;
}

} // namespace

BsdfSample sampledDirection(Vec3 wiWorld, const BsdfEval &e) {
  BsdfSample s;
  if (!(e.pdf > 0))
    return s;
  s.wi = wiWorld;
  s.value = e.value;
  s.pdf = e.pdf;
  s.weight = e.value / e.pdf;
  return s;
}

float fresnelDielectric(float cosi, float eta) {
  if (eta == 0)
    return 1;
  if (cosi < 0)
    eta = 1 / eta;
  float c = std::fabs(cosi);
  float g = eta * eta - 1 + c * c;
  if (g <= 0)
    return 1; // total internal reflection
  g = std::sqrt(g);
  float a = (g - c) / (g + c);
  float b = (c * (g + c) - 1) / (c * (g - c) + 1);
  return 0.5f * a * a * (1 + b * b);
}

BsdfEval evalLobe(const Lobe &l, Vec3 woWorld, Vec3 wiWorld) {
  BsdfEval r;
  if (l.isDelta())
    return r;
  if (std::optional<CosineModel> m = cosineModelOf(l)) {
    CosineEval e = atCosineModel(*m, [&](auto model) {
      return evalCosineLobe<decltype(model)::value>(cosineLobeOf(l), woWorld, wiWorld);
    });
    r.value = e.value;
    r.pdf = e.pdf;
    return r;
  }
  Frame frame(l.n, l.t);
  Vec3 wo = frame.toLocal(woWorld), wi = frame.toLocal(wiWorld);
  switch (l.model) {
  case Lobe::Microfacet:
    return evalMicrofacet(l, wo, wi);
  case Lobe::Ward:
    return evalWard(l, wo, wi);
  case Lobe::Phong: {
    if (wo.z <= 0 || wi.z <= 0)
      return r;
    float cosri = dot(reflect(wo, Vec3(0, 0, 1)), wi);
    if (cosri <= 0)
      return r;
    float common = 0.5f * kInvPi * std::pow(cosri, l.a);
    r.value = Vec3(1, 1, 1) * ((l.a + 2) * common * wi.z);
    r.pdf = (l.a + 1) * common;
    return r;
  }
  case Lobe::Sheen: {
    if (wo.z <= 0 || wi.z <= 0)
      return r;
    r.value = Vec3(1, 1, 1) * (sheenF(l, wo, wi) * wi.z);
    r.pdf = 0.5f * kInvPi;
    return r;
  }
  default: // cosine lobes, above
    return r;
  }
}

BsdfSample sampleLobe(const Lobe &l, Vec3 woWorld, float rx, float ry, float rz) {
  BsdfSample s;
  if (std::optional<CosineModel> m = cosineModelOf(l)) {
    CosineSample c = atCosineModel(*m, [&](auto model) {
      return sampleCosineLobe<decltype(model)::value>(cosineLobeOf(l), woWorld, rx, ry);
    });
    return sampledDirection(c.wi, {c.eval.value, c.eval.pdf});
  }
  Frame frame(l.n, l.t);
  Vec3 wo = frame.toLocal(woWorld);
  switch (l.model) {
  case Lobe::Reflection:
    if (wo.z <= 0)
      return s;
    s.wi = reflect(woWorld, l.n);
    s.weight = Vec3(1, 1, 1) * fresnelDielectric(wo.z, l.eta);
    s.pdf = kInf;
    s.delta = true;
    return s;
  case Lobe::Refraction: {
    if (wo.z <= 0 || !refract(woWorld, l.n, l.eta, s.wi))
      return s;
    s.weight = Vec3(1, 1, 1) * (1 - fresnelDielectric(wo.z, l.eta));
    s.pdf = kInf;
    s.delta = true;
    return s;
  }
  case Lobe::Transparent:
    s.wi = -woWorld;
    s.weight = Vec3(1, 1, 1);
    s.pdf = kInf;
    s.delta = true;
    return s;
  case Lobe::Microfacet:
    return sampleMicrofacet(l, wo, rx, ry, rz, frame);
  case Lobe::Ward:
    return sampleWard(l, wo, rx, ry, frame);
  case Lobe::Phong: {
    if (wo.z <= 0)
      return s;
    float cosa = std::pow(rx, 1 / (l.a + 1)), sina = std::sqrt(std::max(0.0f, 1 - cosa * cosa));
    float phi = 2 * kPi * ry;
    Frame lobe(reflect(woWorld, l.n));
    float sinPhi, cosPhi;
    polySinCos(phi, sinPhi, cosPhi);
    s.wi = lobe.toWorld(Vec3(sina * cosPhi, sina * sinPhi, cosa));
    break;
  }
  case Lobe::Sheen: {
    float z = rx, r = std::sqrt(std::max(0.0f, 1 - z * z)), phi = 2 * kPi * ry;
    float sinPhi, cosPhi;
    polySinCos(phi, sinPhi, cosPhi);
    s.wi = frame.toWorld(Vec3(r * cosPhi, r * sinPhi, z));
    break;
  }
  default: // cosine lobes, above
    return s;
  }
  return sampledDirection(s.wi, evalLobe(l, woWorld, s.wi));
}

//===----------------------------------------------------------------------===//
// The mixture
//===----------------------------------------------------------------------===//

bool ShadingResult::prepare(Vec3 wo) {
  float total = 0;
  for (Lobe &l : lobes) {
    float albedo = 1;
    float cosO = dot(l.n, wo);
    if (l.model == Lobe::Reflection)
      albedo = fresnelDielectric(cosO, l.eta);
    else if (l.model == Lobe::OrenNayarEnergy)
      albedo = std::max(0.0f, luminance(l.tintR));
    else if (l.model == Lobe::Refraction)
      albedo = 1 - fresnelDielectric(cosO, l.eta);
    l.pick = std::max(0.0f, luminance(l.weight)) * albedo;
    if (!std::isfinite(l.pick))
      l.pick = 0;
    total += l.pick;
  }
  if (!(total > 0))
    return false;
  for (Lobe &l : lobes)
    l.pick /= total;
  return true;
}

int ShadingResult::evaluatedLobes() const {
  int n = 0;
  for (const Lobe &l : lobes)
    n += !l.isDelta() && l.pick > 0;
  return n;
}

BsdfEval ShadingResult::eval(Vec3 wo, Vec3 wi) const {
  BsdfEval sum;
  for (const Lobe &l : lobes) {
    if (l.isDelta() || l.pick <= 0)
      continue;
    BsdfEval e = evalLobe(l, wo, wi);
    sum.value += l.weight * e.value;
    sum.pdf += l.pick * e.pdf;
  }
  return sum;
}

ShadingResult::Pick ShadingResult::pick(float s) const {
  Pick picked;
  for (const Lobe &l : lobes) {
    if (l.pick <= 0)
      continue;
    picked.lobe = &l;
    if (s < l.pick)
      break;
    s -= l.pick;
  }
  if (picked.lobe)
    picked.rz = std::clamp(s / picked.lobe->pick, 0.0f, 0.99999994f);
  return picked;
}

BsdfSample ShadingResult::finish(Vec3 wo, const Pick &picked, BsdfSample smp) const {
  const Lobe *chosen = picked.lobe;
  if (!chosen)
    return BsdfSample();
  smp.diffuse = cosineModelOf(*chosen).has_value(); // the diffuse lobes are the cosine ones
  if (smp.delta) {
    smp.weight = smp.weight * chosen->weight / chosen->pick;
    return smp;
  }
  if (!(smp.pdf > 0))
    return BsdfSample();
  // The mixture's f*cos and pdf toward wi: the sampled lobe's own when no
  // other lobe is evaluated (the common single-lobe material).
  BsdfEval all;
  if (evaluatedLobes() == 1) {
    all.value += chosen->weight * smp.value;
    all.pdf += chosen->pick * smp.pdf;
  } else {
    all = eval(wo, smp.wi);
  }
  if (!(all.pdf > 0))
    return BsdfSample();
  smp.weight = all.value / all.pdf;
  smp.pdf = all.pdf;
  return smp;
}

BsdfSample ShadingResult::sample(Vec3 wo, float rx, float ry, float s) const {
  Pick picked = pick(s);
  if (!picked.lobe)
    return BsdfSample();
  return finish(wo, picked, sampleLobe(*picked.lobe, wo, rx, ry, picked.rz));
}

} // namespace osl::render
