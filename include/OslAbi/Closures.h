//===- Closures.h - The closure table kernels and runtime share --*- C++ -*-===//
//
// A closure value is an i32 handle into the shading thread's closure arena
// (OslRuntime/Closure.h): 0 is the empty closure, any other handle names a
// node that is a primitive (one closure of OSL's standard library with its
// parameters and a weight of 1), a product with a color weight, or a sum.
// Kernels build nodes through three entry points (EntryPoints.h), one call
// per op and batch, each taking rows of W 32-bit values (floats' bits, ints,
// string or closure handles; a triple takes three rows) followed by the
// result row.
//
// The front end (signatures), the dialect's verifier (operand kinds), the
// compiler (row counts) and the runtime (parameter layout) all read the
// table below.
//
//===----------------------------------------------------------------------===//
#ifndef OSLABI_CLOSURES_H
#define OSLABI_CLOSURES_H

#include <cstdint>
#include <iterator>
#include <string_view>

namespace osl {

/// One closure of OSL 1.13's standard library (or of testshade's renderer).
/// Parameter kinds, one letter each: `n` a normal or vector, `c` a color, `f`
/// a float, `i` an int, `s` a string, `k` a closure; a letter followed by a
/// count is an array of that many (`i5`: int[5]), which the kernel passes
/// as that many parameters. `keywords` lists the optional keyword
/// parameters (`name:kind`, comma separated) that may follow the positional
/// ones as ("name", value) pairs; absent ones are 0 or "".
struct ClosureSignature {
  const char *name;
  const char *params;
  const char *keywords;
};

enum ClosureId : int32_t {
  kEmission, kBackground, kDiffuse, kOrenNayar, kTranslucent, kPhong, kWard,
  kMicrofacet, kReflection, kRefraction, kTransparent, kDebug, kHoldout,
  kSubsurface, kMxOrenNayarDiffuse, kMxBurleyDiffuse, kMxDielectric,
  kMxConductor, kMxGeneralizedSchlick, kMxTranslucent, kMxTransparent,
  kMxSubsurface, kMxSheen, kMxUniformEdf, kMxAnisotropicVdf, kMxMediumVdf,
  kMxLayer, kParameterTest, kClosureCount,
};

/// Most of testshade's and testrender's closures take a "label" keyword
/// (not oren_nayar, translucent, ward, microfacet, reflection and
/// refraction, which OSL prints without one and warns of one given).
#define OSL_LABEL_KEYWORD "label:s"
#define OSL_MX_KEYWORDS "label:s"
#define OSL_MX_OREN_NAYAR_KEYWORDS "label:s,energy_compensation:i"
#define OSL_MX_FILM_KEYWORDS "label:s,thinfilm_thickness:f,thinfilm_ior:f"
/// In ClosureId order.
inline constexpr ClosureSignature kClosures[] = {
    {"emission", "", ""},
    {"background", "", ""},
    {"diffuse", "n", OSL_LABEL_KEYWORD},
    {"oren_nayar", "nf", ""},
    {"translucent", "n", ""},
    {"phong", "nf", OSL_LABEL_KEYWORD},
    {"ward", "nnff", ""},
    // distribution, N, U, xalpha, yalpha, eta, refract (0 reflect, 1 refract, 2 both)
    {"microfacet", "snnfffi", ""},
    // N, eta; eta 0 means no Fresnel term (reflection(N))
    {"reflection", "nf", ""},
    {"refraction", "nf", ""},
    {"transparent", "", ""},
    {"debug", "s", ""},
    {"holdout", "", ""},
    // eta, g, mean free path, albedo
    {"subsurface", "ffcc", ""},
    {"oren_nayar_diffuse_bsdf", "ncf", OSL_MX_OREN_NAYAR_KEYWORDS},
    {"burley_diffuse_bsdf", "ncf", OSL_MX_KEYWORDS},
    // N, U, reflection_tint, transmission_tint, roughness_x, roughness_y, ior, distribution
    {"dielectric_bsdf", "nnccfffs", OSL_MX_FILM_KEYWORDS},
    // N, U, roughness_x, roughness_y, ior, extinction, distribution
    {"conductor_bsdf", "nnffccs", OSL_MX_FILM_KEYWORDS},
    // N, U, reflection_tint, transmission_tint, roughness_x, roughness_y, f0, f90,
    // exponent, distribution
    {"generalized_schlick_bsdf", "nnccffccfs", OSL_MX_FILM_KEYWORDS},
    {"translucent_bsdf", "nc", OSL_MX_KEYWORDS},
    {"transparent_bsdf", "", OSL_MX_KEYWORDS},
    // N, albedo, transmission_depth, transmission_color, anisotropy (OSL
    // 1.13's stdosl.h)
    {"subsurface_bssrdf", "ncfcf", OSL_MX_KEYWORDS},
    {"sheen_bsdf", "ncf", OSL_MX_KEYWORDS},
    {"uniform_edf", "c", OSL_MX_KEYWORDS},
    // albedo, extinction, anisotropy
    {"anisotropic_vdf", "ccf", OSL_MX_KEYWORDS},
    // albedo, transmission_depth, transmission_color, anisotropy, ior, priority
    {"medium_vdf", "cfcffi", OSL_MX_KEYWORDS},
    // top, base
    {"layer", "kk", ""},
    // testshade's closure with a parameter of every type, arrays included
    // (its testsuite prints it back)
    {"parameter_test", "ifcnsi5n5c5f5s5",
     "int_key:i,float_key:f,color_key:c,vector_key:n,string_key:s"},
};
#undef OSL_LABEL_KEYWORD
#undef OSL_MX_KEYWORDS
#undef OSL_MX_OREN_NAYAR_KEYWORDS
#undef OSL_MX_FILM_KEYWORDS
static_assert(std::size(kClosures) == kClosureCount, "one signature per ClosureId");

/// The id of closure `name`, or -1.
constexpr int32_t closureId(std::string_view name) {
  for (int32_t i = 0; i < kClosureCount; ++i)
    if (name == kClosures[i].name)
      return i;
  return -1;
}

/// The rows one parameter of kind `kind` takes.
constexpr int32_t closureParamRows(char kind) { return kind == 'n' || kind == 'c' ? 3 : 1; }

/// Calls `fn(kind, length)` for each positional parameter of closure `id`,
/// in order (`length` 0: not an array).
template <typename Fn> constexpr void forEachClosureParam(int32_t id, Fn fn) {
  for (const char *p = kClosures[id].params; *p;) {
    char kind = *p++;
    int32_t length = 0;
    while (*p >= '0' && *p <= '9')
      length = 10 * length + (*p++ - '0');
    fn(kind, length);
  }
}

/// How many positional parameters closure `id` has (an array counts once).
constexpr int32_t closurePositionalCount(int32_t id) {
  int32_t n = 0;
  forEachClosureParam(id, [&](char, int32_t) { ++n; });
  return n;
}

/// Calls `fn(name, kind)` for each keyword of closure `id`, in order.
template <typename Fn> constexpr void forEachClosureKeyword(int32_t id, Fn fn) {
  std::string_view list = kClosures[id].keywords;
  while (!list.empty()) {
    size_t comma = list.find(',');
    std::string_view entry = list.substr(0, comma);
    size_t colon = entry.find(':');
    fn(entry.substr(0, colon), entry[colon + 1]);
    list = comma == std::string_view::npos ? std::string_view() : list.substr(comma + 1);
  }
}

/// Every parameter kind of closure `id`, positional then keywords, as the
/// kernel passes them (the front end fills absent keywords with 0 or "").
/// Writes at most `capacity` kinds to `out`; returns how many there are.
constexpr int32_t closureParamKinds(int32_t id, char *out, int32_t capacity) {
  int32_t n = 0;
  forEachClosureParam(id, [&](char kind, int32_t length) {
    for (int32_t e = 0; e < (length ? length : 1); ++e, ++n)
      if (n < capacity)
        out[n] = kind;
  });
  forEachClosureKeyword(id, [&](std::string_view, char kind) {
    if (n < capacity)
      out[n] = kind;
    ++n;
  });
  return n;
}

/// Upper bound of the parameters (positional, array elements and keywords)
/// of any closure.
inline constexpr int32_t kMaxClosureParams = 40;

} // namespace osl

#endif // OSLABI_CLOSURES_H
