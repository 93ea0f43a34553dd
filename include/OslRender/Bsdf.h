//===- Bsdf.h - Scattering for each closure, and their mixture ---*- C++ -*-===//
//
// A shading point's closure becomes a ShadingResult: emitted radiance,
// background radiance, and a mixture of up to eight lobes the integrator
// evaluates and samples. Each lobe scatters as testrender's BSDF of the
// same closure (the same formulas, warps and random-number use), so that
// osl-run --scene's paths are testrender's. Directions point away from the
// surface (wo toward the viewer, wi toward the light).
//
//===----------------------------------------------------------------------===//
#ifndef OSLRENDER_BSDF_H
#define OSLRENDER_BSDF_H

#include "OslRender/Sampling.h"
#include "OslRender/Vec3.h"
#include "OslRuntime/Closure.h"

#include <algorithm>
#include <cstdint>
#include <vector>

namespace osl::render {

/// A lobe's evaluation or sample: the direction, the BSDF times cosine
/// over the pdf ("weight"), the pdf (solid angle; infinite for a delta
/// lobe) and a roughness (testrender's ray spread).
struct BsdfSample {
  Vec3 wi;
  Vec3 weight;
  float pdf = 0;
  float roughness = 0;
};

/// One scattering lobe: a model with its parameters and closure weight.
struct Lobe {
  enum Model : int32_t {
    Diffuse,         // n
    Translucent,     // n (scatters to the other side)
    OrenNayar,       // n, a = sigma (qualitative Oren-Nayar)
    OrenNayarEnergy, // n, a = roughness, albedo: Fujii's with Portsmouth's multiple scattering
    Phong,           // n, a = exponent
    Ward,            // n, t, a, b = alpha x, y
    Microfacet,      // n, t = U, a, b = alpha x, y, eta, dist, refract 0/1/2
    MxDielectric,    // n, t = U, a, b = roughness x, y, tintR, tintT, eta = ior
    MxConductor,     // n, t = U, a, b = roughness x, y, ior, kappa
    MxSchlick,       // n, t = U, a, b = roughness x, y, tintR, tintT, f0, f90, exponent
    Reflection,      // n, eta (0: no Fresnel)
    Refraction,      // n, eta
    Transparent,     // straight through
    Burley,          // n, albedo, a = roughness
    Sheen,           // n, albedo, a = roughness
  };
  Model model = Diffuse;
  Vec3 weight;
  Vec3 n, t;
  float a = 0, b = 0, eta = 0, exponent = 5;
  /// Microfacet: 0 GGX, 1 Beckmann.
  int dist = 0;
  /// Microfacet: 0 reflection, 1 refraction, 2 both. MaterialX
  /// microfacets: 1 where the transmission lobe is on (a tinted
  /// transmission).
  int refract = 0;
  Vec3 albedo{1, 1, 1};
  Vec3 tintR{1, 1, 1}, tintT{1, 1, 1};
  Vec3 f0, f90, ior, kappa;
  /// MaterialX microfacets with transmission: the relative index of the
  /// medium entered (ShadingResult::refractionIor: the last the closure's
  /// medium pass found, anywhere in its tree).
  float refractionIor = 1;
  /// The probability of sampling this lobe (ShadingResult::prepare).
  float pick = 0;
};

/// The lobes whose sample is a cosine-weighted direction: sampled in lanes
/// (LaneKernels::sampleCosineLobes) as by sampleLobe, through
/// sampleCosineLobe.
inline bool isCosineLobe(Lobe::Model m) {
  return m == Lobe::Diffuse || m == Lobe::Translucent || m == Lobe::OrenNayar;
}

/// The normal a cosine lobe scatters about: a translucent lobe's turned to
/// the far side.
inline Vec3 cosineLobeNormal(const Lobe &l) { return l.model == Lobe::Translucent ? -l.n : l.n; }

/// testrender's Oren-Nayar (Fujii's simplification of the qualitative
/// model) about `n` with roughness `sigma`, toward wi; nothing below
/// either side. Selects, not branches: lane loops vectorize it.
[[gnu::always_inline]] inline BsdfSample orenNayarEval(Vec3 n, float sigma, Vec3 wo, Vec3 wi) {
  float nl = dot(n, wi), nv = dot(n, wo);
  bool above = nl > 0 && nv > 0;
  float s = dot(wo, wi) - nl * nv;
  float s2 = sigma * sigma;
  float a = 1 - 0.50f * s2 / (s2 + 0.33f);
  float b = 0.45f * s2 / (s2 + 0.09f);
  float stinv = s > 0 ? s / std::max(nl, nv) : 0.0f;
  float f = a + b * stinv;
  BsdfSample r;
  r.wi = select(above, wi, Vec3());
  r.weight = select(above, Vec3(f, f, f), Vec3());
  r.pdf = above ? nl * float(M_1_PI) : 0.0f;
  r.roughness = above ? 1.0f : 0.0f;
  return r;
}

/// A cosine lobe's evaluation about `n` (a translucent lobe's n turned):
/// Oren-Nayar's, or Lambert's (weight 1, whatever the side: the pdf is 0
/// below). Selects, not branches: lane loops vectorize it.
[[gnu::always_inline]] inline BsdfSample cosineLobeEval(bool orenNayar, Vec3 n, float sigma,
                                                        Vec3 wo, Vec3 wi) {
  BsdfSample on = orenNayarEval(n, sigma, wo, wi);
  BsdfSample r;
  r.wi = select(orenNayar, on.wi, wi);
  r.weight = select(orenNayar, on.weight, Vec3(1, 1, 1));
  r.pdf = orenNayar ? on.pdf : std::max(dot(n, wi), 0.0f) * float(M_1_PI);
  r.roughness = orenNayar ? on.roughness : 1.0f;
  return r;
}

/// A cosine lobe's sample about `n` (a translucent lobe's n turned):
/// the cosine-weighted direction, and for Oren-Nayar its evaluation there.
[[gnu::always_inline]] inline BsdfSample sampleCosineLobe(bool orenNayar, Vec3 n, float sigma,
                                                          Vec3 wo, float rx, float ry) {
  float pdf;
  Vec3 wi = sampleCosineHemisphere(n, rx, ry, pdf);
  BsdfSample on = orenNayarEval(n, sigma, wo, wi);
  BsdfSample r;
  r.wi = select(orenNayar, on.wi, wi);
  r.weight = select(orenNayar, on.weight, Vec3(1, 1, 1));
  r.pdf = orenNayar ? on.pdf : pdf;
  r.roughness = orenNayar ? on.roughness : 1.0f;
  return r;
}

/// testrender's BSDF of `l` alone (its weight not applied).
BsdfSample evalLobe(const Lobe &l, Vec3 wo, Vec3 wi);
BsdfSample sampleLobe(const Lobe &l, Vec3 wo, float rx, float ry, float rz);
/// What the lobe reflects toward wo, as testrender estimates it to choose
/// among lobes (1 for most).
Vec3 lobeAlbedo(const Lobe &l, Vec3 wo);

/// The microfacet family and the MaterialX sheen and Burley lobes
/// (MicrofacetLobes.cpp), which the three functions above call.
BsdfSample evalMicrofacetLobe(const Lobe &l, Vec3 wo, Vec3 wi);
BsdfSample sampleMicrofacetLobe(const Lobe &l, Vec3 wo, float rx, float ry, float rz);
Vec3 microfacetLobeAlbedo(const Lobe &l, Vec3 wo);
bool isMicrofacetLobe(Lobe::Model m);

struct ShadingResult {
  static constexpr size_t kMaxLobes = 8;
  Vec3 emission;
  Vec3 background;
  std::vector<Lobe> lobes;
  /// The relative index of refraction the closure's medium declares (1:
  /// none), for the MaterialX lobes with transmission made after it.
  float refractionIor = 1;
  /// The bytes testrender's mixture pool holds for the lobes added.
  int poolBytes = 0;

  void clear() {
    emission = background = Vec3();
    lobes.clear();
    refractionIor = 1;
    poolBytes = 0;
  }
  /// Room for the next lobe, built in place (a lobe is 160 bytes), then
  /// kept or dropped by keepNext.
  Lobe &next() { return lobes.emplace_back(); }
  /// Keeps next()'s lobe unless the mixture is full (as testrender's, which
  /// drops the ninth lobe, or one its 1024-byte pool has no room for); false
  /// when it was dropped.
  bool keepNext();
  void dropNext() { lobes.pop_back(); }
  /// Each lobe's pick probability: its weight times its albedo toward wo,
  /// as a share of what the path carries. Unless `absorb`, they are
  /// normalized; otherwise what they leave below 1 is the chance the path
  /// ends (Russian roulette).
  void prepare(Vec3 wo, Vec3 pathWeight, bool absorb);
  Vec3 albedo(Vec3 wo) const;
  /// The mixture toward wi: each lobe's weight combined by the balance
  /// heuristic over the pick probabilities.
  BsdfSample eval(Vec3 wo, Vec3 wi) const;
  /// Picks a lobe with rx (rescaled for it), samples it with (rx, ry, rz),
  /// and folds the other lobes' evaluations in. A zero pdf: no sample.
  BsdfSample sample(Vec3 wo, float rx, float ry, float rz) const;
  /// sample()'s two halves, for lobes sampled elsewhere (in lanes): the
  /// lobe rx picks (-1: none) with rx rescaled for it, and what lobe i's
  /// own sample `s` becomes in the mixture.
  int pick(float &rx) const;
  BsdfSample mixSample(size_t i, BsdfSample s, Vec3 wo) const;
};

/// Where a closure is interpreted: toward the viewer (wo) and which side
/// was hit (MaterialX dielectrics invert their index inside).
struct ShadingPoint {
  Vec3 wo;
  bool backfacing = false;
};

/// Adds the lobes and emission of closure `handle` (built in `arena`), as
/// testrender's process_closure does; `lightOnly`: the emission alone.
void addClosure(const ClosureArena &arena, int32_t handle, const ShadingPoint &at,
                ShadingResult &result, bool lightOnly = false);
/// The background radiance of closure `handle`.
Vec3 backgroundOf(const ClosureArena &arena, int32_t handle);

/// Dielectric Fresnel reflectance for cos(theta) `cosi` and relative index
/// `eta` (0: 1, no Fresnel term).
float fresnelDielectric(float cosi, float eta);
/// Fresnel reflectance of a conductor of index `n` and extinction `k`.
Vec3 fresnelConductor(float cosTheta, Vec3 n, Vec3 k);
/// Schlick's approximation generalized to an exponent.
Vec3 fresnelGeneralizedSchlick(float cosTheta, Vec3 f0, Vec3 f90, float exponent);
/// The direction refracted from incident `i` through normal `n` (either
/// side) and the transmitted fraction (0 at total internal reflection).
float fresnelRefraction(Vec3 i, Vec3 n, float eta, Vec3 &t);

} // namespace osl::render

#endif // OSLRENDER_BSDF_H
