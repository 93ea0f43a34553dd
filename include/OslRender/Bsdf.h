//===- Bsdf.h - Scattering for each closure, and their mixture ---*- C++ -*-===//
//
// A shading point's flattened closure (OslRuntime/Closure.h) becomes a
// ShadingResult: emitted radiance, background radiance, and a mixture of
// lobes the integrator evaluates and samples. Directions point away from
// the surface (wo toward the viewer, wi toward the light).
//
//===----------------------------------------------------------------------===//
#ifndef OSLRENDER_BSDF_H
#define OSLRENDER_BSDF_H

#include "OslRender/Vec3.h"
#include "OslRuntime/Closure.h"

#include <cstdint>
#include <limits>
#include <vector>

namespace osl::render {

/// One scattering lobe: a model with its parameters and closure weight.
struct Lobe {
  enum Model : int32_t {
    Diffuse,      // Lambert
    OrenNayar,    // a = sigma (qualitative Oren-Nayar)
    Translucent,  // Lambert through the surface
    Phong,        // a = exponent
    Ward,         // a, b = alpha x, y; t = tangent
    Microfacet,   // a, b = alpha x, y; eta; dist 0 GGX, 1 Beckmann; refract 0/1/2;
                  // fresnel: 0 dielectric(eta), 1 conductor(ior, k), 2 Schlick(f0, f90, e)
    Reflection,   // eta (0: no Fresnel)
    Refraction,   // eta
    Transparent,  // straight through
    Burley,       // a = roughness
    Sheen,        // a = roughness
    OrenNayarEnergy, // a = sigma, tintR = albedo: Fujii's Oren-Nayar with Portsmouth's
                     // multiple-scattering term (energy_compensation)
  };
  Model model = Diffuse;
  Vec3 weight;
  Vec3 n, t;
  float a = 0, b = 0, eta = 0, exponent = 5;
  int dist = 0, refract = 0, fresnel = 0;
  Vec3 tintR{1, 1, 1}, tintT{1, 1, 1}; // microfacet reflection and transmission tints
  Vec3 f0, f90, ior, kappa;      // Schlick and conductor Fresnel
  float pick = 0;               // probability of sampling this lobe

  bool isDelta() const {
    return model == Reflection || model == Refraction || model == Transparent;
  }
};

/// f * cos(theta_i) and the pdf (solid angle) of sampling wi.
struct BsdfEval {
  Vec3 value;
  float pdf = 0;
};

struct BsdfSample {
  Vec3 wi;
  Vec3 value;     // the lobe's own f * cos toward wi (not for a delta lobe)
  Vec3 weight;    // f * cos / pdf, times the lobe's weight over its pick probability
  float pdf = 0;  // infinity for a specular (delta) lobe
  bool delta = false;
  bool diffuse = false; // from a diffuse lobe (Lambert, Oren-Nayar, translucent, Burley)
};

struct ShadingResult {
  Vec3 emission;
  Vec3 background;
  std::vector<Lobe> lobes;
  /// Primitives the renderer does not scatter with (volumes, holdout, debug).
  int ignored = 0;

  void clear() {
    emission = background = Vec3();
    lobes.clear();
    ignored = 0;
  }
  /// Sets each lobe's pick probability (by weight luminance times its
  /// albedo toward wo); false when nothing scatters.
  bool prepare(Vec3 wo);
  BsdfEval eval(Vec3 wo, Vec3 wi) const;
  /// How many lobes eval() sums (non-delta, with a chance of being picked).
  int evaluatedLobes() const;
  /// Picks a lobe with `s`, then samples it with (`rx`, `ry`): pick(),
  /// sampleLobe() and finish() in turn.
  BsdfSample sample(Vec3 wo, float rx, float ry, float s) const;

  /// A lobe chosen by its pick probability, and what is left of the
  /// uniform number that chose it, rescaled (a fresh number for the lobe's
  /// own choice). No lobe when none can be picked.
  struct Pick {
    const Lobe *lobe = nullptr;
    float rz = 0;
  };
  Pick pick(float s) const;
  /// The mixture's sample from `picked`'s own sample toward wi: its weight
  /// is the mixture's f*cos over the mixture's pdf (one-sample MIS).
  BsdfSample finish(Vec3 wo, const Pick &picked, BsdfSample lobeSample) const;
};

/// Where a closure is interpreted: toward the viewer (wo), the shading
/// normal (for closures without one), and which side was hit (MaterialX
/// dielectrics invert their index inside).
struct ShadingPoint {
  Vec3 wo, n;
  bool backfacing = false;
};

/// Appends the lobes and emission of closure `handle` (built in `arena`)
/// scaled by `scale` to `result`. layer() weighs its base by what its top
/// lets through toward wo.
void addClosure(const ClosureArena &arena, int32_t handle, const ShadingPoint &at,
                ShadingResult &result, Vec3 scale = Vec3(1, 1, 1));

/// One lobe on its own, for tests: value and pdf, and sampling.
BsdfEval evalLobe(const Lobe &lobe, Vec3 wo, Vec3 wi);
BsdfSample sampleLobe(const Lobe &lobe, Vec3 wo, float rx, float ry, float rz = 0.5f);
/// A lobe's sample toward `wi` (world) with its evaluation there: weight
/// f*cos/pdf, or no sample where the pdf vanishes.
BsdfSample sampledDirection(Vec3 wi, const BsdfEval &e);
/// Dielectric Fresnel reflectance for cos(theta) `cosi` and relative index
/// `eta` (0: 1, no Fresnel term).
float fresnelDielectric(float cosi, float eta);

} // namespace osl::render

#endif // OSLRENDER_BSDF_H
