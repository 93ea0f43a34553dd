//===- Bsdf.cpp - The simple lobes and the lobe mixture -------------------===//
//
// Diffuse, translucent, Oren-Nayar, Phong, Ward and the delta lobes as
// testrender evaluates and samples them (the microfacet family is in
// MicrofacetLobes.cpp), and testrender's mixture: lobes picked in
// proportion to what each carries of the path's weight, combined by the
// balance heuristic. Each returns a weight (f * cos / pdf) and the pdf, so
// a delta lobe's infinite pdf needs no special case.
//
//===----------------------------------------------------------------------===//
#include "OslRender/Bsdf.h"
#include "OslRender/Sampling.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace osl::render {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

/// Portsmouth's energy-conserving Oren-Nayar (MaterialX's with
/// energy_compensation): Fujii's single scattering plus a multiple
/// scattering term from the analytic directional albedo.
constexpr float kFon1 = float(0.5 - 2.0 / (3.0 * M_PI));
constexpr float kFon2 = float(2.0 / 3.0 - 28.0 / (15.0 * M_PI));

float fonAlbedo(float sigma, float mu) {
  float af = 1.0f / (1.0f + kFon1 * sigma);
  float bf = sigma * af;
  float si = std::sqrt(std::max(0.0f, 1.0f - mu * mu));
  // Mixed float and double as the model's reference implementation has it.
  float g = float(si * (fast::acos(mu) - si * mu) +
                  2.0 * ((si / mu) * (1.0 - si * si * si) - si) / 3.0f);
  return af + (bf * float(M_1_PI)) * g;
}

BsdfSample orenNayarEnergyEval(const Lobe &l, Vec3 wo, Vec3 wi) {
  float nl = dot(l.n, wi), nv = dot(l.n, wo);
  if (!(nl > 0 && nv > 0))
    return {};
  float s = dot(wo, wi) - nl * nv;
  const Vec3 rho = l.albedo;
  const float sigma = l.a;
  float af = 1.0f / (1.0f + kFon1 * sigma);
  float stinv = s > 0 ? s / std::max(nl, nv) : s;
  float fss = float(af * (1.0 + sigma * stinv));
  float efo = fonAlbedo(sigma, nv), efi = fonAlbedo(sigma, nl);
  float avgEf = af * (1.0f + kFon2 * sigma);
  float lost = std::max(0.0f, 1.0f - avgEf);
  Vec3 rhoMs = (rho * rho) * avgEf;
  rhoMs = {rhoMs.x / (1.0f - rho.x * lost), rhoMs.y / (1.0f - rho.y * lost),
           rhoMs.z / (1.0f - rho.z * lost)};
  float fms = std::max(1e-7f, 1.0f - efo) * std::max(1e-7f, 1.0f - efi) /
              std::max(1e-7f, 1.0f - avgEf);
  return {wi, rho * fss + rhoMs * fms, nl * float(M_1_PI), 1.0f};
}

BsdfSample phongEval(const Lobe &l, Vec3 wo, Vec3 wi) {
  float cosNI = dot(l.n, wi), cosNO = dot(l.n, wo);
  if (!(cosNI > 0 && cosNO > 0))
    return {};
  Vec3 r = (2 * cosNO) * l.n - wo;
  float cosRI = dot(r, wi);
  if (!(cosRI > 0))
    return {};
  float e = l.a;
  float pdf = (e + 1) * float(M_1_PI / 2) * fast::safePow(cosRI, e);
  float w = cosNI * (e + 2) / (e + 1);
  return {wi, Vec3(w, w, w), pdf, 1 / (1 + e)};
}

BsdfSample phongSample(const Lobe &l, Vec3 wo, float rx, float ry) {
  float cosNO = dot(l.n, wo);
  if (!(cosNO > 0))
    return {};
  Vec3 r = (2 * cosNO) * l.n - wo;
  TangentFrame tf(r);
  float sp, cp;
  fast::sincos(2 * kPiF * rx, sp, cp);
  float cosTheta = fast::safePow(ry, 1 / (l.a + 1));
  float sin2 = 1 - cosTheta * cosTheta;
  float sinTheta = sin2 > 0 ? std::sqrt(sin2) : 0;
  return phongEval(l, wo, tf.get(cp * sinTheta, sp * sinTheta, cosTheta));
}

/// Ward's anisotropic lobe: the half vector's pdf and the weight, shared
/// by evaluation and sampling (dotx, doty, dotn: the half vector in the
/// frame over the alphas).
BsdfSample wardWeight(const Lobe &l, Vec3 wi, float cosNI, float cosNO, float oh, float dotx,
                      float doty, float dotn) {
  float e = fast::exp(-(dotx * dotx + doty * doty) / (dotn * dotn));
  float c = float(4 * M_PI) * l.a * l.b;
  float k = oh * dotn * dotn * dotn;
  float w = k * std::sqrt(cosNI / cosNO);
  return {wi, Vec3(w, w, w), e / (c * k), std::max(l.a, l.b)};
}

BsdfSample wardEval(const Lobe &l, Vec3 wo, Vec3 wi) {
  float cosNO = dot(l.n, wo), cosNI = dot(l.n, wi);
  if (!(cosNI > 0 && cosNO > 0))
    return {};
  Vec3 h = normalize(wi + wo);
  TangentFrame tf(l.n, l.t);
  Vec3 hl = tf.toLocal(h);
  return wardWeight(l, wi, cosNI, cosNO, dot(h, wi), hl.x / l.a, hl.y / l.b, hl.z);
}

BsdfSample wardSample(const Lobe &l, Vec3 wo, float rx, float ry) {
  float cosNO = dot(l.n, wo);
  if (!(cosNO > 0))
    return {};
  TangentFrame tf(l.n, l.t);
  float sp, cp;
  fast::sincos(2 * kPiF * rx, sp, cp);
  float cosPhi = l.a * cp, sinPhi = l.b * sp;
  float k = 1 / std::sqrt(cosPhi * cosPhi + sinPhi * sinPhi);
  cosPhi *= k;
  sinPhi *= k;
  // Walter's inversion: tan^2(theta) of the half vector.
  float denom = (cosPhi * cosPhi) / (l.a * l.a) + (sinPhi * sinPhi) / (l.b * l.b);
  float tan2 = -fast::log(1 - ry) / denom;
  float cosTheta = 1 / std::sqrt(1 + tan2);
  float sinTheta = cosTheta * std::sqrt(tan2);
  Vec3 hl(sinTheta * cosPhi, sinTheta * sinPhi, cosTheta);
  float dotx = hl.x / l.a, doty = hl.y / l.b, dotn = hl.z;
  Vec3 h = tf.get(hl.x, hl.y, hl.z);
  float oh = dot(h, wo);
  Vec3 wi = 2 * oh * h - wo;
  float cosNI = dot(l.n, wi);
  if (!(cosNI > 0))
    return {};
  return wardWeight(l, wi, cosNI, cosNO, oh, dotx, doty, dotn);
}

} // namespace

float fresnelDielectric(float cosi, float eta) {
  if (eta == 0)
    return 1;
  if (cosi < 0.0f)
    eta = 1.0f / eta;
  float c = std::fabs(cosi);
  float g = eta * eta - 1 + c * c;
  if (!(g > 0))
    return 1.0f; // total internal reflection
  g = std::sqrt(g);
  float a = (g - c) / (g + c);
  float b = (c * (g + c) - 1) / (c * (g - c) + 1);
  return 0.5f * a * a * (1 + b * b);
}

float fresnelRefraction(Vec3 i, Vec3 n, float eta, Vec3 &t) {
  float cosi = -dot(i, n);
  Vec3 nn;
  float neta;
  if (cosi > 0) {
    neta = 1 / eta;
    nn = n;
  } else {
    cosi = -cosi;
    neta = eta;
    nn = -n;
  }
  float arg = 1.0f - (neta * neta * (1.0f - cosi * cosi));
  if (!(arg >= 0)) {
    t = Vec3();
    return 0;
  }
  float nk = (neta * cosi) - std::sqrt(arg);
  t = i * neta + nn * nk;
  return 1 - fresnelDielectric(cosi, eta);
}

BsdfSample evalLobe(const Lobe &l, Vec3 wo, Vec3 wi) {
  if (isMicrofacetLobe(l.model))
    return evalMicrofacetLobe(l, wo, wi);
  switch (l.model) {
  // Constant models: each case keeps only its own half of the selects.
  case Lobe::Diffuse: return cosineLobeEval(false, l.n, l.a, wo, wi);
  case Lobe::Translucent: return cosineLobeEval(false, -l.n, l.a, wo, wi);
  case Lobe::OrenNayar: return cosineLobeEval(true, l.n, l.a, wo, wi);
  case Lobe::OrenNayarEnergy: return orenNayarEnergyEval(l, wo, wi);
  case Lobe::Phong: return phongEval(l, wo, wi);
  case Lobe::Ward: return wardEval(l, wo, wi);
  default: return {}; // delta lobes
  }
}

BsdfSample sampleLobe(const Lobe &l, Vec3 wo, float rx, float ry, float rz) {
  if (isMicrofacetLobe(l.model))
    return sampleMicrofacetLobe(l, wo, rx, ry, rz);
  switch (l.model) {
  case Lobe::Diffuse:
  case Lobe::Translucent:
  case Lobe::OrenNayar:
    return sampleCosineLobe(l.model == Lobe::OrenNayar, cosineLobeNormal(l), l.a, wo, rx, ry);
  case Lobe::OrenNayarEnergy: {
    float pdf;
    return evalLobe(l, wo, sampleCosineHemisphere(l.n, rx, ry, pdf));
  }
  case Lobe::Phong: return phongSample(l, wo, rx, ry);
  case Lobe::Ward: return wardSample(l, wo, rx, ry);
  case Lobe::Reflection: {
    float cosNO = dot(l.n, wo);
    if (!(cosNO > 0))
      return {};
    float f = fresnelDielectric(cosNO, l.eta);
    return {(2 * cosNO) * l.n - wo, Vec3(f, f, f), kInf, 0};
  }
  case Lobe::Refraction: {
    Vec3 wi;
    float ft = fresnelRefraction(-wo, l.n, l.eta, wi);
    return {wi, Vec3(ft, ft, ft), kInf, 0};
  }
  case Lobe::Transparent: return {-wo, Vec3(1, 1, 1), kInf, 0};
  default: return {};
  }
}

Vec3 lobeAlbedo(const Lobe &l, Vec3 wo) {
  if (isMicrofacetLobe(l.model))
    return microfacetLobeAlbedo(l, wo);
  switch (l.model) {
  case Lobe::Reflection: {
    float cosNO = dot(l.n, wo);
    float f = cosNO > 0 ? fresnelDielectric(cosNO, l.eta) : 1.0f;
    return {f, f, f};
  }
  case Lobe::Refraction: {
    float f = 1 - fresnelDielectric(dot(l.n, wo), l.eta);
    return {f, f, f};
  }
  default: return {1, 1, 1};
  }
}

//===----------------------------------------------------------------------===//
// The mixture
//===----------------------------------------------------------------------===//

/// The bytes testrender's mixture stores each model's BSDF in: its pool
/// holds 1024, so a ninth lobe, or one past the pool, is dropped there.
static int testrenderBytes(Lobe::Model m) {
  switch (m) {
  case Lobe::Transparent: return 8;
  case Lobe::Ward: return 40;
  case Lobe::Burley:
  case Lobe::Sheen: return 48;
  case Lobe::OrenNayarEnergy: return 56;
  case Lobe::Microfacet: return 96;
  case Lobe::MxConductor: return 128;
  case Lobe::MxDielectric: return 136;
  case Lobe::MxSchlick: return 160;
  default: return 24;
  }
}

bool ShadingResult::keepNext() {
  constexpr int kPoolBytes = 1024;
  int bytes = testrenderBytes(lobes.back().model);
  if (lobes.size() > kMaxLobes || poolBytes + bytes > kPoolBytes) {
    dropNext();
    return false;
  }
  poolBytes += bytes;
  return true;
}

void ShadingResult::prepare(Vec3 wo, Vec3 pathWeight, bool absorb) {
  float total = 0;
  for (Lobe &l : lobes) {
    l.pick = dot(l.weight, pathWeight * lobeAlbedo(l, wo)) /
             (pathWeight.x + pathWeight.y + pathWeight.z);
    total += l.pick;
  }
  if ((!absorb && total > 0) || total > 1)
    for (Lobe &l : lobes)
      l.pick /= total;
}

Vec3 ShadingResult::albedo(Vec3 wo) const {
  Vec3 sum;
  for (const Lobe &l : lobes)
    sum += l.weight * lobeAlbedo(l, wo);
  return sum;
}

BsdfSample ShadingResult::eval(Vec3 wo, Vec3 wi) const {
  BsdfSample s;
  for (const Lobe &l : lobes) {
    BsdfSample b = evalLobe(l, wo, wi);
    b.weight *= l.weight;
    misUpdate(s.weight, s.pdf, b.weight, b.pdf, l.pick);
    s.roughness += b.roughness * l.pick;
  }
  return s;
}

int ShadingResult::pick(float &rx) const {
  float accum = 0;
  for (size_t i = 0; i < lobes.size(); ++i) {
    const Lobe &l = lobes[i];
    if (!(rx < l.pick + accum)) {
      accum += l.pick;
      continue;
    }
    rx = std::min((rx - accum) / l.pick, 0.99999994f);
    return int(i);
  }
  return -1;
}

BsdfSample ShadingResult::mixSample(size_t i, BsdfSample s, Vec3 wo) const {
  const Lobe &l = lobes[i];
  s.weight *= l.weight * (1 / l.pick);
  s.pdf *= l.pick;
  if (s.pdf == 0.0f)
    return {};
  // The other lobes toward the sampled direction.
  for (size_t j = 0; j < lobes.size(); ++j)
    if (j != i) {
      BsdfSample b = evalLobe(lobes[j], wo, s.wi);
      b.weight *= lobes[j].weight;
      misUpdate(s.weight, s.pdf, b.weight, b.pdf, lobes[j].pick);
    }
  return s;
}

BsdfSample ShadingResult::sample(Vec3 wo, float rx, float ry, float rz) const {
  int i = pick(rx);
  if (i < 0)
    return {};
  return mixSample(size_t(i), sampleLobe(lobes[size_t(i)], wo, rx, ry, rz), wo);
}

} // namespace osl::render
