//===- ClosureLobes.cpp - From a closure to lobes, as testrender reads it --===//
//
// Each closure of OSL's standard library becomes the lobe testrender makes
// of it, with the same parameters (normals as the shader gave them), so
// that osl-run --scene scatters as testrender does. First the medium pass
// (the index of refraction a transmissive MaterialX closure declares, which
// the transmissive lobes made after it use), then the lobes; layer() weighs
// its base by one minus its top's opacity toward the viewer. Closures
// testrender lacks scatter as documented in README.md ("Closures and the
// render mode"): subsurface as Lambert times its albedo; volumes, holdout
// and debug are ignored.
//
//===----------------------------------------------------------------------===//
#include "OslRender/Bsdf.h"
#include "OslRender/Sampling.h"
#include "OslRuntime/StringCall.h"

#include <algorithm>
#include <memory>

namespace osl::render {
namespace {

bool isBlack(Vec3 c) { return c.x == 0 && c.y == 0 && c.z == 0; }

/// A closure tree flattened into its primitives (weights multiplied down),
/// in a per-thread list per nesting depth (layer() recurses while its
/// parent's list is still being read).
class Flattened {
public:
  Flattened(const ClosureArena &arena, int32_t handle, Vec3 scale) : lists(perThread()) {
    // Lists are owned one by one: a deeper level's growth moves none.
    if (lists.open.size() <= lists.depth)
      lists.open.push_back(std::make_unique<std::vector<ClosurePrimitive>>());
    prims = lists.open[lists.depth++].get();
    prims->clear();
    arena.flatten(handle, *prims);
    if (!(scale.x == 1 && scale.y == 1 && scale.z == 1)) // 1 * w is w
      for (ClosurePrimitive &p : *prims)
        for (int c = 0; c < 3; ++c)
          p.weight[c] = scale[c] * p.weight[c];
  }
  ~Flattened() { --lists.depth; }
  const std::vector<ClosurePrimitive> &operator*() const { return *prims; }

private:
  struct Lists {
    std::vector<std::unique_ptr<std::vector<ClosurePrimitive>>> open;
    size_t depth = 0;
  };
  static Lists &perThread() {
    static thread_local Lists lists;
    return lists;
  }
  Lists &lists;
  std::vector<ClosurePrimitive> *prims;
};

Vec3 tripleOf(const ClosurePrimitive &p, int i) { return Vec3(p.tripleParam(i)); }

/// The MaterialX microfacets' common parameters: N, U, roughness x and y
/// at `roughnessAt` (testrender uses GGX whatever the distribution).
Lobe mxMicrofacet(const ClosurePrimitive &p, Lobe::Model model, int roughnessAt) {
  Lobe l;
  l.model = model;
  l.n = tripleOf(p, 0);
  l.t = tripleOf(p, 1);
  l.a = p.floatParam(roughnessAt);
  l.b = p.floatParam(roughnessAt + 1);
  return l;
}

/// The index of refraction generalized_schlick's f0 implies.
float schlickIor(Vec3 f0) {
  float avg = fast::clamp((f0.x + f0.y + f0.z) / 3.0f, 0.0f, 0.99f);
  float root = std::sqrt(avg);
  return (1 + root) / (1 - root);
}

bool lobeOf(const ClosurePrimitive &p, Vec3 w, float refractionIor, Lobe &l);

/// How much of what is below a layer's top the top hides toward wo
/// (testrender's evaluate_layer_opacity): a reflectance for the closures
/// that let light through, 1 for the others.
Vec3 layerOpacity(const ClosureArena &arena, int32_t handle, const ShadingPoint &at, Vec3 scale) {
  Vec3 sum;
  Flattened prims(arena, handle, scale);
  for (const ClosurePrimitive &p : *prims) {
    Vec3 w(p.weight);
    switch (p.id) {
    case kMxLayer:
      sum += layerOpacity(arena, p.closureParam(0), at, w) +
             layerOpacity(arena, p.closureParam(1), at, w);
      break;
    case kMxDielectric:
    case kMxGeneralizedSchlick:
      if (!isBlack(tripleOf(p, 3))) {
        sum += Vec3(1, 1, 1); // transmissive: opaque
        break;
      }
      [[fallthrough]];
    case kReflection:
    case kMxSheen: {
      Lobe l;
      lobeOf(p, w, 1.0f, l);
      sum += w * lobeAlbedo(l, at.wo);
      break;
    }
    default: sum += Vec3(1, 1, 1); break;
    }
  }
  return sum;
}

/// The base's weight under a layer whose top is `top`.
Vec3 underLayer(const ClosureArena &arena, int32_t top, const ShadingPoint &at, Vec3 w) {
  return w * (Vec3(1, 1, 1) - fast::clamp(layerOpacity(arena, top, at, Vec3(1, 1, 1)), 0.f, 1.f));
}

/// testrender's medium pass over one primitive: the index of refraction it
/// declares.
void readMedium(const ClosureArena &arena, const ClosurePrimitive &p, const ShadingPoint &at,
                ShadingResult &out);
void readMedium(const ClosureArena &arena, int32_t handle, const ShadingPoint &at, Vec3 scale,
                ShadingResult &out) {
  Flattened prims(arena, handle, scale);
  for (const ClosurePrimitive &p : *prims)
    readMedium(arena, p, at, out);
}
void readMedium(const ClosureArena &arena, const ClosurePrimitive &p, const ShadingPoint &at,
                ShadingResult &out) {
  // Seen from inside, the index is inverted.
  auto setIor = [&](float ior) { out.refractionIor = at.backfacing ? 1.0f / ior : ior; };
  Vec3 w(p.weight);
  switch (p.id) {
  case kMxLayer:
    readMedium(arena, p.closureParam(0), at, w, out);
    readMedium(arena, p.closureParam(1), at, underLayer(arena, p.closureParam(0), at, w), out);
    break;
  case kMxMediumVdf: setIor(p.floatParam(4)); break;
  case kMxDielectric:
    if (!isBlack(w * tripleOf(p, 3)))
      setIor(p.floatParam(6));
    break;
  case kMxGeneralizedSchlick:
    if (!isBlack(w * tripleOf(p, 3)))
      setIor(schlickIor(tripleOf(p, 6)));
    break;
  default: break;
  }
}

/// The lobe and emission of one primitive (its weight scaled).
void addLobes(const ClosureArena &arena, const ClosurePrimitive &p, const ShadingPoint &at,
              bool lightOnly, ShadingResult &out);
void addLobes(const ClosureArena &arena, int32_t handle, const ShadingPoint &at, Vec3 scale,
              bool lightOnly, ShadingResult &out) {
  Flattened prims(arena, handle, scale);
  for (const ClosurePrimitive &p : *prims)
    addLobes(arena, p, at, lightOnly, out);
}
void addLobes(const ClosureArena &arena, const ClosurePrimitive &p, const ShadingPoint &at,
              bool lightOnly, ShadingResult &out) {
  Vec3 w(p.weight);
  switch (p.id) {
  case kEmission: out.emission += w; return;
  case kMxUniformEdf: out.emission += w * tripleOf(p, 0); return;
  case kBackground: out.background += w; return;
  default: break;
  }
  if (lightOnly)
    return;
  if (p.id == kMxLayer) {
    Vec3 base = underLayer(arena, p.closureParam(0), at, w);
    addLobes(arena, p.closureParam(0), at, w, lightOnly, out);
    if (!isBlack(base))
      addLobes(arena, p.closureParam(1), at, base, lightOnly, out);
    return;
  }
  if (lobeOf(p, w, out.refractionIor, out.next()))
    out.keepNext();
  else
    out.dropNext();
}

/// The MaterialX dielectric's and generalized Schlick's common part: the
/// tints, and the transmission lobe (with the medium's index) where the
/// transmission tint is not black.
Lobe mxTinted(const ClosurePrimitive &p, Lobe::Model model, float refractionIor) {
  Lobe l = mxMicrofacet(p, model, 4);
  l.tintR = tripleOf(p, 2);
  l.tintT = tripleOf(p, 3);
  l.refract = isBlack(l.tintT) ? 0 : 1;
  l.refractionIor = l.refract ? refractionIor : 1.0f;
  return l;
}

/// Into `l` (a default Lobe), the lobe testrender makes of primitive `p`
/// with weight `w` (`refractionIor`: the medium pass's index); false for
/// what does not scatter (volumes, holdout, debug, a microfacet of unknown
/// distribution).
bool lobeOf(const ClosurePrimitive &p, Vec3 w, float refractionIor, Lobe &l) {
  auto c = [&](int i) { return tripleOf(p, i); };
  auto f = [&](int i) { return p.floatParam(i); };
  switch (p.id) {
  case kDiffuse: l.model = Lobe::Diffuse; l.n = c(0); break;
  case kTranslucent: l.model = Lobe::Translucent; l.n = c(0); break;
  case kOrenNayar: l.model = Lobe::OrenNayar; l.n = c(0); l.a = f(1); break;
  case kPhong: l.model = Lobe::Phong; l.n = c(0); l.a = f(1); break;
  case kWard:
    l.model = Lobe::Ward; l.n = c(0); l.t = c(1); l.a = f(2); l.b = f(3);
    break;
  case kMicrofacet: {
    std::string dist = stringText(p.stringParam(0));
    if (dist == "ggx")
      l.dist = 0;
    else if (dist == "beckmann" || dist == "default")
      l.dist = 1;
    else
      return false; // testrender makes no lobe of another distribution
    l.model = Lobe::Microfacet;
    l.n = c(1);
    l.t = c(2);
    l.a = f(3);
    l.b = f(4);
    l.eta = f(5);
    l.refract = p.intParam(6);
    if (l.refract < 0 || l.refract > 2)
      return false;
    break;
  }
  case kReflection: l.model = Lobe::Reflection; l.n = c(0); l.eta = f(1); break;
  case kRefraction: l.model = Lobe::Refraction; l.n = c(0); l.eta = f(1); break;
  case kTransparent:
  case kMxTransparent: l.model = Lobe::Transparent; break;
  case kMxOrenNayarDiffuse:
    l.n = c(0);
    l.a = f(2);
    if (p.intParam(4)) {
      l.model = Lobe::OrenNayarEnergy;
      l.albedo = c(1);
    } else {
      l.model = Lobe::OrenNayar;
      w = w * c(1);
    }
    break;
  case kMxBurleyDiffuse: l.model = Lobe::Burley; l.n = c(0); l.albedo = c(1); l.a = f(2); break;
  case kMxSheen: l.model = Lobe::Sheen; l.n = c(0); l.albedo = c(1); l.a = f(2); break;
  case kMxTranslucent: l.model = Lobe::Translucent; l.n = c(0); w = w * c(1); break;
  case kMxSubsurface: l.model = Lobe::Diffuse; l.n = c(0); w = w * c(1); break;
  case kSubsurface: l.model = Lobe::Diffuse; l.n = c(0); w = w * c(3); break;
  case kMxDielectric:
    l = mxTinted(p, Lobe::MxDielectric, refractionIor);
    l.eta = f(6);
    break;
  case kMxConductor:
    l = mxMicrofacet(p, Lobe::MxConductor, 2);
    l.ior = c(4);
    l.kappa = c(5);
    break;
  case kMxGeneralizedSchlick:
    l = mxTinted(p, Lobe::MxSchlick, refractionIor);
    l.f0 = c(6);
    l.f90 = c(7);
    l.exponent = f(8);
    break;
  default: return false; // volumes (read by the medium pass), holdout, debug
  }
  l.weight = w;
  return true;
}

} // namespace

void addClosure(const ClosureArena &arena, int32_t handle, const ShadingPoint &at,
                ShadingResult &out, bool lightOnly) {
  // Both passes walk the tree itself: at the top, weights are scaled by
  // nothing, and a list would cost more than a second walk (layers flatten
  // their own parts). The medium pass reads only the closures below; a
  // batch that made none skips it.
  constexpr uint64_t kMediumPass =
      ClosureArena::idBit(kMxMediumVdf) | ClosureArena::idBit(kMxDielectric) |
      ClosureArena::idBit(kMxGeneralizedSchlick) | ClosureArena::idBit(kMxLayer);
  if (!lightOnly && arena.madeAny(kMediumPass))
    arena.forEachPrimitive(handle,
                           [&](const ClosurePrimitive &p) { readMedium(arena, p, at, out); });
  arena.forEachPrimitive(
      handle, [&](const ClosurePrimitive &p) { addLobes(arena, p, at, lightOnly, out); });
}

Vec3 backgroundOf(const ClosureArena &arena, int32_t handle) {
  Vec3 sum;
  arena.forEachPrimitive(handle, [&](const ClosurePrimitive &p) {
    if (p.id == kBackground)
      sum += Vec3(p.weight);
  });
  return sum;
}

} // namespace osl::render
