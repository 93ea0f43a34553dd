//===- CosineLobes.h - Lobes sampled by cosine, one lane or many -*- C++ -*-===//
//
// Private to lib/Render. The lobes whose sampling is the cosine-weighted
// hemisphere (Lambert, translucent, qualitative and energy-preserving
// Oren-Nayar, Burley): their evaluation and sampling as inline code of plain
// float operations and selects, which Bsdf.cpp runs for one lobe and the
// lane kernels (LaneKernelsImpl.h) run for a batch of sampled lobes of one
// model, with the same bits.
//
//===----------------------------------------------------------------------===//
#ifndef OSLRENDER_COSINELOBES_H
#define OSLRENDER_COSINELOBES_H

#include "OslRender/Bsdf.h"
#include "OslRender/RenderMath.h"
#include "OslRender/Vec3.h"

#include <cmath>
#include <optional>
#include <type_traits>

namespace osl::render {

/// The models of CosineLobes.h; Translucent is Lambert on the other side.
enum class CosineModel { Lambert, OrenNayar, Burley, EnergyOrenNayar };

/// One lobe's parameters: its normal, sigma or roughness (`a`), the albedo
/// of the energy-preserving Oren-Nayar (`rho`), and whether it scatters
/// through the surface (translucent).
struct CosineLobe {
  Vec3 n;
  float a = 0;
  Vec3 rho{1, 1, 1};
  bool through = false;
};

/// f*cos toward wi and the pdf of sampling it.
struct CosineEval {
  Vec3 value;
  float pdf = 0;
};

inline constexpr float kCosineInvPi = 1.0f / kRenderPi;

/// A direction about +z with density cos(theta) / pi.
[[gnu::always_inline]] inline Vec3 cosineHemisphere(float rx, float ry) {
  float r = std::sqrt(rx), s, c;
  polySinCos(2 * kRenderPi * ry, s, c);
  return {r * c, r * s, std::sqrt(std::fmax(0.0f, 1 - rx))};
}

/// Qualitative Oren-Nayar's f, local directions.
[[gnu::always_inline]] inline float orenNayarF(float sigma, Vec3 wo, Vec3 wi) {
  float s2 = sigma * sigma;
  float A = 1 - 0.5f * s2 / (s2 + 0.33f), B = 0.45f * s2 / (s2 + 0.09f);
  float s = dot(wo, wi) - wo.z * wi.z;
  float stinv = s > 0 ? s / std::fmax(wo.z, wi.z) : 0.0f;
  return (A + B * stinv) * kCosineInvPi;
}

/// Burley's diffuse f, local directions: Schlick-like retro-reflection
/// (the fifth power multiplied out).
[[gnu::always_inline]] inline float burleyF(float roughness, Vec3 wo, Vec3 wi) {
  Vec3 h = normalize(wo + wi);
  float hi = dot(wi, h);
  float fd90 = 0.5f + 2 * roughness * hi * hi;
  auto schlick = [&](float c) {
    float m = 1 - c, m2 = m * m;
    return 1 + (fd90 - 1) * (m2 * m2 * m);
  };
  return schlick(wi.z) * schlick(wo.z) * kCosineInvPi;
}

/// Energy-preserving Oren-Nayar (Portsmouth, Kutz and Hill, as OpenPBR and
/// testrender use it) times pi: Fujii's single-scattering lobe with
/// A = 1 / (1 + (1/2 - 2/(3 pi)) sigma), B = sigma A, plus a multiple-
/// scattering lobe that returns what the single one loses at albedo 1.
/// Local directions, both above the surface.
[[gnu::always_inline]] inline Vec3 energyOrenNayar(float sigma, Vec3 rho, Vec3 wo, Vec3 wi) {
  const float c1 = float(0.5 - 2.0 / (3.0 * M_PI));
  const float c2 = float(2.0 / 3.0 - 28.0 / (15.0 * M_PI));
  float a = 1 / (1 + c1 * sigma), b = sigma * a;
  // The single lobe's albedo toward a direction at cos(theta) mu.
  auto albedo = [&](float mu) {
    float sinT = std::sqrt(std::fmax(0.0f, 1 - mu * mu));
    float g = sinT * (polyAcos(mu) - sinT * mu) +
              2 * ((sinT / mu) * (1 - sinT * sinT * sinT) - sinT) / 3;
    return a + b * kCosineInvPi * g;
  };
  float s = dot(wo, wi) - wo.z * wi.z;
  float stinv = s > 0 ? s / std::fmax(wo.z, wi.z) : s;
  float single = a * (1 + sigma * stinv);
  float mean = a * (1 + c2 * sigma); // the single lobe's mean albedo
  auto lost = [](float e) { return std::fmax(1e-7f, 1 - e); };
  float multiple = lost(albedo(wo.z)) * lost(albedo(wi.z)) / lost(mean);
  // The multiple lobe's albedo: its light bounces again off rho.
  float kept = std::fmax(0.0f, 1 - mean);
  auto bounced = [&](float r) { return r * r * mean / (1 - r * kept); };
  return rho * single + Vec3(bounced(rho.x), bounced(rho.y), bounced(rho.z)) * multiple;
}

/// f*cos and pdf of lobe `l` of model M, world directions.
template <CosineModel M>
[[gnu::always_inline]] inline CosineEval evalCosineLobe(const CosineLobe &l, Vec3 woWorld,
                                                        Vec3 wiWorld) {
  Frame frame(l.n);
  Vec3 wo = frame.toLocal(woWorld), wi = frame.toLocal(wiWorld);
  wi.z = l.through ? -wi.z : wi.z;
  Vec3 f;
  if constexpr (M == CosineModel::Lambert)
    f = Vec3(1, 1, 1) * kCosineInvPi;
  else if constexpr (M == CosineModel::OrenNayar)
    f = Vec3(1, 1, 1) * orenNayarF(l.a, wo, wi);
  else if constexpr (M == CosineModel::Burley)
    f = Vec3(1, 1, 1) * burleyF(l.a, wo, wi);
  else
    f = energyOrenNayar(l.a, l.rho, wo, wi) * kCosineInvPi;
  bool above = wo.z > 0 && wi.z > 0;
  CosineEval r;
  r.value = select(above, f * wi.z, Vec3());
  r.pdf = above ? wi.z * kCosineInvPi : 0.0f;
  return r;
}

/// A sampled direction of lobe `l` (world) with its evaluation.
struct CosineSample {
  Vec3 wi;
  CosineEval eval;
};

template <CosineModel M>
[[gnu::always_inline]] inline CosineSample sampleCosineLobe(const CosineLobe &l, Vec3 woWorld,
                                                            float rx, float ry) {
  Vec3 local = cosineHemisphere(rx, ry);
  local.z = l.through ? -local.z : local.z;
  CosineSample s;
  s.wi = Frame(l.n).toWorld(local);
  s.eval = evalCosineLobe<M>(l, woWorld, s.wi);
  return s;
}

/// The cosine model of lobe `l`, if it has one (Sheen, Phong, Ward,
/// microfacets and deltas sample otherwise).
inline std::optional<CosineModel> cosineModelOf(const Lobe &l) {
  switch (l.model) {
  case Lobe::Diffuse:
  case Lobe::Translucent: return CosineModel::Lambert;
  case Lobe::OrenNayar: return CosineModel::OrenNayar;
  case Lobe::Burley: return CosineModel::Burley;
  case Lobe::OrenNayarEnergy: return CosineModel::EnergyOrenNayar;
  default: return std::nullopt;
  }
}

inline CosineLobe cosineLobeOf(const Lobe &l) {
  CosineLobe c;
  c.n = l.n;
  c.a = l.a;
  c.rho = l.tintR;
  c.through = l.model == Lobe::Translucent;
  return c;
}

/// fn(std::integral_constant<CosineModel, M>()) for model `m`.
template <typename Fn> decltype(auto) atCosineModel(CosineModel m, Fn fn) {
  switch (m) {
  case CosineModel::OrenNayar:
    return fn(std::integral_constant<CosineModel, CosineModel::OrenNayar>());
  case CosineModel::Burley:
    return fn(std::integral_constant<CosineModel, CosineModel::Burley>());
  case CosineModel::EnergyOrenNayar:
    return fn(std::integral_constant<CosineModel, CosineModel::EnergyOrenNayar>());
  default:
    return fn(std::integral_constant<CosineModel, CosineModel::Lambert>());
  }
}

} // namespace osl::render

#endif // OSLRENDER_COSINELOBES_H
