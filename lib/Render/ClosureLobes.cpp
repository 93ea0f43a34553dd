//===- ClosureLobes.cpp - From a flattened closure to lobes --------------===//
//
// Maps each closure of OSL's standard library to a lobe model with its
// parameters, as testrender interprets them. Approximations, documented in
// README.md ("Closures and the render mode"): subsurface closures scatter as Lambert times their
// albedo; volumes (anisotropic_vdf, medium_vdf) are ignored, as are
// holdout and debug; layer() weighs its base by one minus its top's
// reflectance toward the viewer.
//
//===----------------------------------------------------------------------===//
#include "OslRender/Bsdf.h"
#include "OslRuntime/StringCall.h"

#include <algorithm>
#include <deque>

namespace osl::render {
namespace {

/// 0 for GGX, 1 for Beckmann ("beckmann", "default", anything else).
int distributionCode(int32_t handle) { return stringText(handle) == "ggx" ? 0 : 1; }

float alpha(float a) { return std::max(std::fabs(a), 1e-4f); }

/// What fraction of light a top lobe reflects toward wo (layer's estimate).
float topReflectance(const Lobe &l, Vec3 wo) {
  float cosO = std::clamp(dot(l.n, wo), 0.0f, 1.0f);
  switch (l.model) {
  case Lobe::Microfacet:
    if (l.fresnel == 0)
      return luminance(l.weight * l.tintR) * fresnelDielectric(cosO, l.eta);
    return luminance(l.weight * l.tintR);
  case Lobe::Reflection: return luminance(l.weight) * fresnelDielectric(cosO, l.eta);
  case Lobe::Transparent:
  case Lobe::Refraction: return 0;
  case Lobe::OrenNayarEnergy: return luminance(l.weight * l.tintR);
  default: return luminance(l.weight);
  }
}

void addMicrofacet(ShadingResult &out, Vec3 w, Vec3 n, Vec3 u, int dist, float ax, float ay) {
  Lobe l;
  l.model = Lobe::Microfacet;
  l.weight = w;
  l.n = n;
  l.t = u;
  l.dist = dist;
  l.a = alpha(ax);
  l.b = alpha(ay);
  out.lobes.push_back(l);
}

} // namespace

void addClosure(const ClosureArena &arena, int32_t handle, const ShadingPoint &at,
                ShadingResult &out, Vec3 scale) {
  bool backfacing = at.backfacing;
  // Reused per thread (layer() nests, so each depth has its own list).
  static thread_local std::deque<std::vector<ClosurePrimitive>> lists; // stable references
  static thread_local size_t depth = 0;
  if (lists.size() <= depth)
    lists.resize(depth + 1);
  std::vector<ClosurePrimitive> &prims = lists[depth];
  prims.clear();
  arena.flatten(handle, prims);
  struct Nest {
    size_t &d;
    explicit Nest(size_t &d) : d(++d) {}
    ~Nest() { --d; }
  } nest(depth);
  for (const ClosurePrimitive &p : prims) {
    Vec3 w = Vec3(p.weight) * scale;
    if (!(std::isfinite(w.x) && std::isfinite(w.y) && std::isfinite(w.z)))
      continue; // a NaN weight would poison the pixel; OSL's renderers skip it too
    auto n = [&](int i) { return normalize(Vec3(p.tripleParam(i))); };
    auto c = [&](int i) { return Vec3(p.tripleParam(i)); };
    auto f = [&](int i) { return p.floatParam(i); };
    Lobe l;
    l.weight = w;
    l.n = at.n;
    switch (p.id) {
    case kEmission: out.emission += w; continue;
    case kMxUniformEdf: out.emission += w * c(0); continue;
    case kBackground: out.background += w; continue;
    case kDiffuse: l.model = Lobe::Diffuse; l.n = n(0); break;
    case kOrenNayar: l.model = Lobe::OrenNayar; l.n = n(0); l.a = f(1); break;
    case kTranslucent: l.model = Lobe::Translucent; l.n = n(0); break;
    case kPhong: l.model = Lobe::Phong; l.n = n(0); l.a = std::max(0.0f, f(1)); break;
    case kWard:
      l.model = Lobe::Ward; l.n = n(0); l.t = Vec3(p.tripleParam(1));
      l.a = alpha(f(2)); l.b = alpha(f(3));
      break;
    case kMicrofacet:
      addMicrofacet(out, w, n(1), Vec3(p.tripleParam(2)), distributionCode(p.stringParam(0)),
                    f(3), f(4));
      out.lobes.back().eta = f(5);
      out.lobes.back().refract = std::clamp(p.intParam(6), 0, 2);
      continue;
    case kReflection: l.model = Lobe::Reflection; l.n = n(0); l.eta = f(1); break;
    case kRefraction: l.model = Lobe::Refraction; l.n = n(0); l.eta = f(1); break;
    case kTransparent:
    case kMxTransparent: l.model = Lobe::Transparent; break;
    case kSubsurface: l.model = Lobe::Diffuse; l.weight = w * c(3); break;
    case kMxSubsurface: l.model = Lobe::Diffuse; l.n = n(0); l.weight = w * c(1); break;
    case kMxOrenNayarDiffuse:
      // Keywords follow the positional N, albedo, roughness: label, then
      // energy_compensation. Compensated, the albedo is inside the model
      // (its multiple scattering saturates colors); otherwise a weight.
      l.n = n(0);
      l.a = f(2);
      if (p.intParam(4)) {
        l.model = Lobe::OrenNayarEnergy;
        l.tintR = c(1);
      } else {
        l.model = Lobe::OrenNayar;
        l.weight = w * c(1);
      }
      break;
    case kMxBurleyDiffuse:
      l.model = Lobe::Burley; l.n = n(0); l.weight = w * c(1); l.a = f(2);
      break;
    case kMxTranslucent: l.model = Lobe::Translucent; l.n = n(0); l.weight = w * c(1); break;
    case kMxSheen: l.model = Lobe::Sheen; l.n = n(0); l.weight = w * c(1); l.a = f(2); break;
    case kMxDielectric: {
      Vec3 tintR = c(2), tintT = c(3);
      addMicrofacet(out, w, n(0), Vec3(p.tripleParam(1)), distributionCode(p.stringParam(7)),
                    f(4), f(5));
      Lobe &m = out.lobes.back();
      m.eta = backfacing ? 1 / std::max(f(6), 1e-4f) : f(6);
      m.tintR = tintR;
      m.tintT = tintT;
      m.refract = tintT.isZero() ? 0 : tintR.isZero() ? 1 : 2;
      continue;
    }
    case kMxConductor: {
      addMicrofacet(out, w, n(0), Vec3(p.tripleParam(1)), distributionCode(p.stringParam(6)),
                    f(2), f(3));
      Lobe &m = out.lobes.back();
      m.fresnel = 1;
      m.ior = c(4);
      m.kappa = c(5);
      continue;
    }
    case kMxGeneralizedSchlick: {
      Vec3 tintR = c(2), tintT = c(3), f0 = c(6);
      addMicrofacet(out, w, n(0), Vec3(p.tripleParam(1)), distributionCode(p.stringParam(9)),
                    f(4), f(5));
      Lobe &m = out.lobes.back();
      m.fresnel = 2;
      m.f0 = f0;
      m.f90 = c(7);
      m.exponent = f(8);
      m.tintR = tintR;
      m.tintT = tintT;
      // The index the reflectance at normal incidence implies, for refraction.
      float r0 = std::sqrt(std::clamp(luminance(f0), 0.0f, 0.99f));
      m.eta = (1 + r0) / (1 - r0);
      if (backfacing)
        m.eta = 1 / m.eta;
      m.refract = tintT.isZero() ? 0 : 2;
      continue;
    }
    case kMxLayer: {
      size_t first = out.lobes.size();
      addClosure(arena, p.closureParam(0), at, out, w);
      float reflectance = 0;
      for (size_t i = first; i < out.lobes.size(); ++i)
        reflectance += topReflectance(out.lobes[i], at.wo) / std::max(1e-6f, luminance(w));
      float through = std::clamp(1 - reflectance, 0.0f, 1.0f);
      addClosure(arena, p.closureParam(1), at, out, w * through);
      continue;
    }
    default: // volumes, holdout, debug
      ++out.ignored;
      continue;
    }
    out.lobes.push_back(l);
  }
}

} // namespace osl::render
