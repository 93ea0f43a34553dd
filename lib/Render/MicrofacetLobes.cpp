//===- MicrofacetLobes.cpp - testrender's microfacet, sheen and Burley lobes -===//
//
// The lobes of OSL 1.13's testrender built on a microsurface, evaluated and
// sampled as testrender does, so that osl-run --scene traces testrender's
// paths bit for bit (OSL's testsuite compares renders pixel by pixel):
//
//  - `microfacet`: GGX or Beckmann normals (Heitz's anisotropic forms with
//    height-correlated masking-shadowing, visible normals sampled as d'Eon
//    and Heitz do), reflecting, refracting or both with dielectric Fresnel;
//  - MaterialX `dielectric_bsdf`, `conductor_bsdf` and
//    `generalized_schlick_bsdf`: always GGX, roughness used as alpha as it
//    is, each with its Fresnel term, and a transmission lobe picked by the
//    share of transmittance where the closure transmits;
//  - MaterialX `burley_diffuse_bsdf` and `sheen_bsdf` (cosine and uniform
//    hemisphere sampling).
//
// Also the conductor and generalized Schlick Fresnel terms of Bsdf.h (the
// dielectric ones, shared with the delta lobes, are in Bsdf.cpp).
//
// Every expression keeps testrender's operation order, OpenImageIO's fast_*
// approximations and Imath's normalize, so each rounding is the same (this
// file is built with -ffp-contract=off, as testrender's x86-64 baseline build
// fuses nothing). Where testrender departs from the papers (marked "as
// testrender"), the departure is kept: the renders must agree.
//
// What each model reads from its Lobe (nothing is precomputed; the frame
// and the Fresnel terms are rebuilt per call from these):
//   Microfacet    n, t (= U), a, b (alpha x, y), eta, dist (0 GGX,
//                 1 Beckmann), refract (0 reflect, 1 refract, 2 both)
//   MxDielectric  n, t, a, b (roughness x, y), tintR, tintT, eta (= ior),
//                 refract (1: transmits), refractionIor
//   MxConductor   n, t, a, b, ior, kappa (= extinction)
//   MxSchlick     n, t, a, b, tintR, tintT, f0, f90, exponent, refract,
//                 refractionIor
//   Burley        n, albedo, a (= roughness)
//   Sheen         n, albedo, a (= roughness)
//
//===----------------------------------------------------------------------===//
#include "OslRender/Bsdf.h"
#include "OslRender/Sampling.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace osl::render {
namespace {

float square(float x) { return x * x; }
Vec3 gray(float x) { return {x, x, x}; }
Vec3 divide(Vec3 a, Vec3 b) { return {a.x / b.x, a.y / b.y, a.z / b.z}; }

//===----------------------------------------------------------------------===//
// Imath's normalize and OpenImageIO's erf approximations
//===----------------------------------------------------------------------===//

/// |v| for a v whose squared length underflows: measured after dividing by
/// the largest magnitude (Imath's lengthTiny).
float tinyLength(Vec3 v) {
  float ax = v.x >= 0 ? v.x : -v.x;
  float ay = v.y >= 0 ? v.y : -v.y;
  float az = v.z >= 0 ? v.z : -v.z;
  float m = ax;
  if (m < ay)
    m = ay;
  if (m < az)
    m = az;
  if (m == 0)
    return 0;
  ax /= m;
  ay /= m;
  az /= m;
  return m * std::sqrt(ax * ax + ay * ay + az * az);
}

/// v / |v| as testrender's Imath vectors normalize: tiny vectors measured
/// with care, a zero vector left as it is, NaN spreading to every component.
Vec3 unit(Vec3 v) {
  float len2 = dot(v, v);
  float len = len2 < 2 * std::numeric_limits<float>::min() ? tinyLength(v) : std::sqrt(len2);
  if (len != 0)
    v = {v.x / len, v.y / len, v.z / len};
  return v;
}

/// OpenImageIO's fast_erf: Abramowitz and Stegun 7.1.28, a sixth-degree
/// polynomial raised to the 16th power.
float fastErf(float x) {
  float a = std::fabs(x);
  float b = 1.0f - (1.0f - a); // flushes denormals, as OpenImageIO
  float r = 0.0000430638f;
  r = r * b + 0.0002765672f;
  r = r * b + 0.0001520143f;
  r = r * b + 0.0092705272f;
  r = r * b + 0.0422820123f;
  r = r * b + 0.0705230784f;
  r = r * b + 1.0f;
  float r2 = r * r, r4 = r2 * r2, r8 = r4 * r4, r16 = r8 * r8;
  return std::copysign(1.0f - 1.0f / r16, x);
}

/// OpenImageIO's fast_ierf: Giles' single-precision erfinv, with |x|
/// held below 1.
float fastInverseErf(float x) {
  float a = std::fabs(x);
  if (a > 0.99999994f)
    a = 0.99999994f;
  float w = -fast::log((1.0f - a) * (1.0f + a));
  float p;
  if (w < 5.0f) {
    w = w - 2.5f;
    p = 2.81022636e-08f;
    p = p * w + 3.43273939e-07f;
    p = p * w + -3.5233877e-06f;
    p = p * w + -4.39150654e-06f;
    p = p * w + 0.00021858087f;
    p = p * w + -0.00125372503f;
    p = p * w + -0.00417768164f;
    p = p * w + 0.246640727f;
    p = p * w + 1.50140941f;
  } else {
    w = std::sqrt(w) - 3.0f;
    p = -0.000200214257f;
    p = p * w + 0.000100950558f;
    p = p * w + 0.00134934322f;
    p = p * w + -0.00367342844f;
    p = p * w + 0.00573950773f;
    p = p * w + -0.0076224613f;
    p = p * w + 0.00943887047f;
    p = p * w + 1.00167406f;
    p = p * w + 2.83297682f;
  }
  return p * x;
}

//===----------------------------------------------------------------------===//
// The two normal distributions
//===----------------------------------------------------------------------===//

/// The slope density of the unit-alpha distribution at tan^2(theta_m)
/// (the D of a normal, before the alpha and cos^4 factors).
float ggxSlopeDensity(float tan2) { return 1 / (kPiF * (1 + tan2) * (1 + tan2)); }
float beckmannSlopeDensity(float tan2) { return float(1 / M_PI) * fast::exp(-tan2); }

/// Smith's Lambda in terms of a2 = 1 / (alpha tan(theta))^2.
float ggxLambda(float a2) { return 0.5f * (-1.0f + std::sqrt(1.0f + 1.0f / a2)); }
/// Walter's rational fit, 0 past a = 1.6.
float beckmannLambda(float a2) {
  float a = std::sqrt(a2);
  return a < 1.6f ? (1.0f - 1.259f * a + 0.396f * a2) / (3.535f * a + 2.181f * a2) : 0.0f;
}

/// A slope of the unit-alpha GGX distribution visible from an incident
/// direction at cos(theta) in the xz plane: x by inverting its CDF in
/// closed form, y from a rational fit of the conditional.
void ggxVisibleSlope(float cosTheta, float u, float v, float &sx, float &sy) {
  float c = cosTheta < 1e-6f ? 1e-6f : cosTheta;
  float q = (1 + c) * u - c;
  float num = c * std::sqrt((1 - c) * (1 + c)) - q * std::sqrt((1 - q) * (1 + q));
  float den = (q - c) * (q + c);
  constexpr float kMinDen = 1.0f / 4294967296.0f; // 2^-32, keeps the division finite
  den = std::fabs(den) < kMinDen ? std::copysign(kMinDen, den) : den;
  sx = num / den;

  float r = 1 - 2 * v;
  float w = std::fabs(r);
  float z = (w * (w * (w * 0.27385f - 0.73369f) + 0.46341f)) /
            (w * (w * (w * 0.093073f + 0.309420f) - 1.0f) + 0.597999f);
  sy = std::copysign(1.0f, r) * z * std::sqrt(1.0f + sx * sx);
}

/// The same for Beckmann (Jakob's routine as testrender refines it): a
/// first guess for x from exp(-erfinv(y)^2) ~ 1 - y^2, then at most two
/// Newton steps on the exact CDF; y is Gaussian.
void beckmannVisibleSlope(float cosTheta, float u, float v, float &sx, float &sy) {
  const float invSqrtPi = 1 / std::sqrt(kPiF);
  float c = cosTheta < 1e-6f ? 1e-6f : cosTheta;
  float tanTheta = std::sqrt(1 - c * c) / c;
  float cotTheta = 1 / tanTheta;

  float erfCot = fastErf(cotTheta);
  float k = tanTheta * invSqrtPi;
  float yApprox = u * (1.0f + erfCot + k * (1 - erfCot * erfCot));
  float yExact = u * (1.0f + erfCot + k * fast::exp(-cotTheta * cotTheta));
  float b = k > 0 ? (0.5f - std::sqrt(k * (k - yApprox + 1.0f) + 0.25f)) / k : yApprox - 1.0f;

  // How far the CDF at erfinv(b) misses yExact.
  auto residual = [&](float x) { return 1.0f + b + k * fast::exp(-x * x) - yExact; };
  float x = fastInverseErf(b);
  float miss = residual(x);
  if (std::fabs(miss) > 1e-6f) { // close enough otherwise (and no 0/0 at the root)
    b -= miss / (1 - x * tanTheta);
    x = fastInverseErf(b);
    miss = residual(x);
    b -= miss / (1 - x * tanTheta);
    x = fastInverseErf(b);
  }
  sx = x;
  sy = fastInverseErf(2.0f * v - 1.0f);
}

//===----------------------------------------------------------------------===//
// The microsurface: frame, alphas, D, masking, visible-normal sampling
//===----------------------------------------------------------------------===//

/// G1 of the outgoing direction and the height-correlated G2 of the pair.
struct Masking {
  float g1, g2;
};

struct Microsurface {
  TangentFrame frame;
  float ax, ay;
  bool beckmann;

  /// D(m) for a local unit normal m (0 below the surface).
  float density(Vec3 m) const {
    if (!(m.z > 0))
      return 0;
    float cos2 = square(m.z);
    float tan2 = (square(m.x / ax) + square(m.y / ay)) / cos2;
    float d = beckmann ? beckmannSlopeDensity(tan2) : ggxSlopeDensity(tan2);
    return d / (ax * ay * square(cos2));
  }

  float lambda(Vec3 w) const {
    float a2 = square(w.z) / (square(w.x * ax) + square(w.y * ay));
    return beckmann ? beckmannLambda(a2) : ggxLambda(a2);
  }

  Masking masking(Vec3 woL, Vec3 wiL) const {
    float lo = lambda(woL), li = lambda(wiL);
    return {1 / (lo + 1), 1 / (lo + li + 1)};
  }

  /// A local normal visible from local woL: woL stretched to unit alphas,
  /// a slope sampled there, rotated to woL's azimuth and unstretched.
  Vec3 sampleNormal(Vec3 woL, float u, float v) const {
    Vec3 s = unit(Vec3(woL.x * ax, woL.y * ay, woL.z));
    float cosTheta = std::max(s.z, 0.0f);
    float cosPhi = 1, sinPhi = 0; // azimuth 0 near normal incidence
    if (cosTheta < 0.99999f) {
      float invLen = 1 / std::sqrt(square(s.x) + square(s.y));
      cosPhi = s.x * invLen;
      sinPhi = s.y * invLen;
    }
    float sx, sy;
    if (beckmann)
      beckmannVisibleSlope(cosTheta, u, v, sx, sy);
    else
      ggxVisibleSlope(cosTheta, u, v, sx, sy);
    float tx = (cosPhi * sx - sinPhi * sy) * ax;
    float ty = (sinPhi * sx + cosPhi * sy) * ay;
    float len = std::sqrt(tx * tx + ty * ty + 1);
    return {std::fabs(tx) < len ? -tx / len : 1.0f, std::fabs(ty) < len ? -ty / len : 1.0f,
            1.0f / len};
  }
};

/// As testrender: the frame follows the tangent only where it is nonzero
/// and the alphas differ, and is then built from the tangent as given (not
/// made orthogonal to n or unit first).
Microsurface microsurfaceOf(const Lobe &l, bool beckmann) {
  bool noTangent = l.t.x == 0 && l.t.y == 0 && l.t.z == 0;
  return {noTangent || l.a == l.b ? TangentFrame(l.n) : TangentFrame(l.n, l.t), l.a, l.b, beckmann};
}

/// The pdfs of a reflected and a refracted direction through normal m,
/// before the lobe choice.
float reflectionPdf(Masking g, float d, float cosNO) { return (g.g1 * d * 0.25f) / cosNO; }
float refractionPdf(Masking g, float d, float cosHI, float cosHO, float eta, float invHt2,
                    float cosNO) {
  return (std::fabs(cosHI * cosHO) * (eta * eta) * (g.g1 * d) * invHt2) / cosNO;
}

/// The unit half vector of a refraction from wo into wi (local), toward
/// wo's side. Also returns 1/|h|^2 of that unit vector, as testrender,
/// whose in-place normalize leaves its ht unit before it is measured.
Vec3 refractionHalfVector(Vec3 woL, Vec3 wiL, float eta, float &invHt2) {
  Vec3 ht = -(eta * wiL + woL);
  if (eta < 1.0f)
    ht = -ht;
  Vec3 h = unit(ht);
  invHt2 = 1 / dot(h, h);
  return h;
}

//===----------------------------------------------------------------------===//
// testrender's `microfacet`: dielectric Fresnel, refract 0, 1 or 2
//===----------------------------------------------------------------------===//

bool reflects(const Lobe &l) { return l.refract == 0 || l.refract == 2; }
bool refracts(const Lobe &l) { return l.refract == 1 || l.refract == 2; }

/// A sample's value as the mode weighs it: with both lobes, Fresnel chose
/// the lobe and scales the pdf; with one, it scales the weight.
BsdfSample dielectricSample(const Lobe &l, Vec3 wi, float out, float pdf, float fresnel) {
  float rough = std::max(l.a, l.b);
  if (l.refract == 2)
    return {wi, gray(out), pdf * fresnel, rough};
  return {wi, gray(out * fresnel), pdf, rough};
}

BsdfSample dielectricEval(const Lobe &l, Vec3 wo, Vec3 wi) {
  Microsurface ms = microsurfaceOf(l, l.dist == 1);
  Vec3 woL = ms.frame.toLocal(wo), wiL = ms.frame.toLocal(wi);
  if (reflects(l) && woL.z > 0 && wiL.z > 0) {
    Vec3 m = unit(wiL + woL);
    float d = ms.density(m);
    Masking g = ms.masking(woL, wiL);
    float fr = fresnelDielectric(dot(m, woL), l.eta);
    return dielectricSample(l, wi, g.g2 / g.g1, reflectionPdf(g, d, woL.z), fr);
  }
  if (refracts(l) && wiL.z < 0 && woL.z > 0.0f) {
    float invHt2;
    Vec3 h = refractionHalfVector(woL, wiL, l.eta, invHt2);
    float cosHO = dot(h, woL);
    float ft = 1.0f - fresnelDielectric(cosHO, l.eta);
    if (ft > 0) { // 0 at total internal reflection
      float cosHI = dot(h, wiL);
      if (h.z <= 0.0f)
        return {};
      float d = ms.density(h);
      Masking g = ms.masking(woL, wiL);
      float pdf = refractionPdf(g, d, cosHI, cosHO, l.eta, invHt2, woL.z);
      return dielectricSample(l, wi, g.g2 / g.g1, pdf, ft);
    }
  }
  return {};
}

BsdfSample dielectricSampleLobe(const Lobe &l, Vec3 wo, float rx, float ry, float rz) {
  Microsurface ms = microsurfaceOf(l, l.dist == 1);
  Vec3 woL = ms.frame.toLocal(wo);
  float cosNO = woL.z;
  if (!(cosNO > 0))
    return {};
  Vec3 m = ms.sampleNormal(woL, rx, ry);
  float cosMO = dot(m, woL);
  float f = fresnelDielectric(cosMO, l.eta);
  float d = ms.density(m);
  if (l.refract == 0 || (l.refract == 2 && rz < f)) {
    Vec3 wiL = (2.0f * cosMO) * m - woL;
    Masking g = ms.masking(woL, wiL);
    Vec3 wi = ms.frame.toWorld(wiL);
    return dielectricSample(l, wi, g.g2 / g.g1, reflectionPdf(g, d, cosNO), f);
  }
  Vec3 wi;
  float ft = fresnelRefraction(-wo, ms.frame.toWorld(m), l.eta, wi);
  Vec3 wiL = ms.frame.toLocal(wi);
  float cosHI = dot(m, wiL);
  Masking g = ms.masking(woL, wiL);
  Vec3 ht = -(l.eta * wiL + woL);
  float invHt2 = 1.0f / dot(ht, ht);
  float pdf = refractionPdf(g, d, cosHI, cosMO, l.eta, invHt2, std::fabs(woL.z));
  return dielectricSample(l, wi, g.g2 / g.g1, pdf, ft);
}

Vec3 dielectricAlbedo(const Lobe &l, Vec3 wo) {
  if (l.refract == 2)
    return gray(1.0f);
  float fr = fresnelDielectric(dot(l.n, wo), l.eta);
  return gray(l.refract ? 1 - fr : fr);
}

//===----------------------------------------------------------------------===//
// The MaterialX microfacets (GGX)
//===----------------------------------------------------------------------===//

/// Conductors never transmit; the others do where the closure made them so.
bool mxTransmits(const Lobe &l) { return l.model != Lobe::MxConductor && l.refract != 0; }

/// The cosine the Fresnel terms see: leaving a denser medium with
/// transmission on, the refracted ray's (0 past the critical angle).
float mxFresnelCosine(const Lobe &l, float cosTheta) {
  float eta = l.refractionIor;
  if (mxTransmits(l) && eta < 1) {
    float cos2 = 1.0f - (1.0f - cosTheta * cosTheta) * eta * eta;
    return cos2 > 0 ? std::sqrt(cos2) : 0.0f;
  }
  return cosTheta;
}

/// The model's tinted reflectance and transmittance at a cosine.
struct MxFresnel {
  Vec3 r, t;
};
MxFresnel mxFresnel(const Lobe &l, float cosTheta) {
  switch (l.model) {
  case Lobe::MxDielectric: {
    float f = fresnelDielectric(cosTheta, l.eta);
    return {l.tintR * f, l.tintT * (1.0f - f)};
  }
  case Lobe::MxConductor: return {fresnelConductor(cosTheta, l.ior, l.kappa), Vec3()};
  default: {
    Vec3 f = fresnelGeneralizedSchlick(cosTheta, l.f0, l.f90, l.exponent);
    return {l.tintR * f, l.tintT * (Vec3(1, 1, 1) - f)};
  }
  }
}

/// The chance of following transmission: its share of the summed terms.
float transmitChance(Vec3 r, Vec3 t) {
  float wt = t.sum(), wr = r.sum();
  return wt / (wt + wr + 1e-6f);
}

BsdfSample mxEval(const Lobe &l, Vec3 wo, Vec3 wi) {
  Microsurface ms = microsurfaceOf(l, false);
  Vec3 woL = ms.frame.toLocal(wo), wiL = ms.frame.toLocal(wi);
  float rough = std::max(l.a, l.b);
  if (woL.z > 0 && wiL.z > 0) {
    Vec3 m = unit(wiL + woL);
    float d = ms.density(m);
    Masking g = ms.masking(woL, wiL);
    MxFresnel f = mxFresnel(l, mxFresnelCosine(l, dot(m, woL)));
    float pdf = reflectionPdf(g, d, woL.z);
    float out = g.g2 / g.g1;
    if (mxTransmits(l)) {
      float pickReflect = 1.0f - transmitChance(f.r, f.t);
      out /= pickReflect;
      pdf *= pickReflect;
    }
    return {wi, f.r * out, pdf, rough};
  }
  float eta = l.refractionIor;
  if (mxTransmits(l) && wiL.z < 0 && woL.z > 0.0f) {
    float invHt2;
    Vec3 h = refractionHalfVector(woL, wiL, eta, invHt2);
    float cosHO = dot(h, woL);
    // As testrender: the transmitted lobe is weighed by the reflectance, and
    // the chance of picking it is the reflectance's against itself.
    Vec3 ft = mxFresnel(l, mxFresnelCosine(l, cosHO)).r;
    if (ft.sum() > 0) {
      float cosHI = dot(h, wiL);
      if (h.z <= 0.0f)
        return {};
      float d = ms.density(h);
      Masking g = ms.masking(woL, wiL);
      float pdf = refractionPdf(g, d, cosHI, cosHO, eta, invHt2, woL.z);
      float out = g.g2 / g.g1;
      float pickTransmit = transmitChance(ft, ft);
      return {wi, ft * out / pickTransmit, pdf * pickTransmit, rough};
    }
  }
  return {};
}

BsdfSample mxSample(const Lobe &l, Vec3 wo, float rx, float ry, float rz) {
  Microsurface ms = microsurfaceOf(l, false);
  Vec3 woL = ms.frame.toLocal(wo);
  float cosNO = woL.z;
  if (!(cosNO > 0))
    return {};
  float rough = std::max(l.a, l.b);
  Vec3 m = ms.sampleNormal(woL, rx, ry);
  float cosMO = dot(m, woL);
  MxFresnel f = mxFresnel(l, mxFresnelCosine(l, cosMO));
  float d = ms.density(m);
  Vec3 wiL = (2.0f * cosMO) * m - woL;
  Masking g = ms.masking(woL, wiL);
  Vec3 wi = ms.frame.toWorld(wiL);
  float pdf = reflectionPdf(g, d, cosNO);
  float out = g.g2 / g.g1;
  if (!mxTransmits(l))
    return {wi, f.r * out, pdf, rough};

  float pickTransmit = transmitChance(f.r, f.t);
  if (!(rz < pickTransmit)) // as testrender: the pdf scaled by transmission's chance
    return {wi, f.r * out / (1.0f - pickTransmit), pdf * pickTransmit, rough};
  // Through m; at total internal reflection wi is 0 (as testrender).
  float eta = l.refractionIor;
  fresnelRefraction(-wo, ms.frame.toWorld(m), eta, wi);
  Vec3 wtL = ms.frame.toLocal(wi);
  float cosHI = dot(m, wtL);
  Masking gt = ms.masking(woL, wtL);
  Vec3 ht = -(eta * wtL + woL);
  float invHt2 = 1.0f / dot(ht, ht);
  float pdfT = refractionPdf(gt, d, cosHI, cosMO, eta, invHt2, std::fabs(woL.z));
  return {wi, f.t * (gt.g2 / gt.g1) / pickTransmit, pdfT * pickTransmit, rough};
}

/// As testrender: 1 with transmission (no estimate), the reflectance
/// toward wo otherwise.
Vec3 mxAlbedo(const Lobe &l, Vec3 wo) {
  if (mxTransmits(l))
    return gray(1.0f);
  return mxFresnel(l, mxFresnelCosine(l, dot(l.n, wo))).r;
}

//===----------------------------------------------------------------------===//
// MaterialX Burley diffuse and sheen
//===----------------------------------------------------------------------===//

/// Schlick's Fresnel between scalars f0 and f90.
float schlick(float cosTheta, float f0, float f90) {
  float x = fast::clamp(1.0f - cosTheta, 0.0f, 1.0f);
  float x2 = x * x, x4 = x2 * x2, x5 = x4 * x;
  return fast::lerp(f0, f90, x5);
}

BsdfSample burleyEval(const Lobe &l, Vec3 wo, Vec3 wi) {
  Vec3 h = unit(wi + wo);
  float cosLH = fast::clamp(dot(wi, h), 0.0f, 1.0f);
  float cosNV = fast::clamp(dot(l.n, wo), 0.0f, 1.0f);
  float cosNL = fast::clamp(dot(l.n, wi), 0.0f, 1.0f);
  float f90 = 0.5f + (2.0f * l.a * cosLH * cosLH);
  float toLight = schlick(cosNL, 1.0f, f90), toViewer = schlick(cosNV, 1.0f, f90);
  return {wi, l.albedo * toLight * toViewer, cosNL * float(M_1_PI), 1.0f};
}

BsdfSample sheenEval(const Lobe &l, Vec3 wo, Vec3 wi) {
  Vec3 h = unit(wi + wo);
  float cosNV = fast::clamp(dot(l.n, wo), 0.0f, 1.0f);
  float cosNL = fast::clamp(dot(l.n, wi), 0.0f, 1.0f);
  float cosNH = fast::clamp(dot(l.n, h), 0.0f, 1.0f);
  float invRough = 1.0f / std::max(l.a, 0.005f);
  // Estevez and Kulla's "Charlie" distribution (libm's powf, as testrender).
  float d = (2.0f + invRough) * std::pow(1.0f - cosNH * cosNH, invRough * 0.5f) / float(2 * M_PI);
  // No Fresnel or masking; Neubelt and Pettineo's visibility term.
  Vec3 value = float(2 * M_PI) * cosNL * l.albedo * d / (4.0f * (cosNL + cosNV - cosNL * cosNV));
  return {wi, value, float(0.5 * M_1_PI), 1.0f};
}

/// MaterialX's rational fit of the sheen's directional albedo.
Vec3 sheenAlbedo(const Lobe &l, Vec3 wo) {
  float c = fast::clamp(dot(l.n, wo), 0.0f, 1.0f), r = l.a;
  float num = 13.67300f + -68.78018f * c + 799.08825f * r + -905.00061f * c * r +
              60.28956f * c * c + 1086.96473f * r * r;
  float den = 1.0f + 61.57746f * c + 442.78211f * r + 2597.49308f * c * r + 121.81241f * c * c +
              3045.55075f * r * r;
  return fast::clamp(l.albedo * (num / den), 0.0f, 1.0f);
}

} // namespace

//===----------------------------------------------------------------------===//
// Fresnel terms and the entry points
//===----------------------------------------------------------------------===//

Vec3 fresnelConductor(float cosTheta, Vec3 n, Vec3 k) {
  float c = fast::clamp(cosTheta, 0.0f, 1.0f);
  float cos2 = c * c, sin2 = 1.0f - cos2;
  Vec3 n2 = n * n, k2 = k * k;
  Vec3 t0 = n2 - k2 - gray(sin2);
  auto abLength = [](float t, float nn, float kk) { return std::sqrt(t * t + 4.0f * nn * kk); };
  Vec3 a2b2(abLength(t0.x, n2.x, k2.x), abLength(t0.y, n2.y, k2.y), abLength(t0.z, n2.z, k2.z));
  Vec3 t1 = a2b2 + gray(cos2);
  auto halfRoot = [](float s, float t) { return std::sqrt(std::max(0.5f * (s + t), 0.0f)); };
  Vec3 a(halfRoot(a2b2.x, t0.x), halfRoot(a2b2.y, t0.y), halfRoot(a2b2.z, t0.z));
  Vec3 t2 = (2.0f * c) * a;
  Vec3 rs = divide(t1 - t2, t1 + t2);
  Vec3 t3 = cos2 * a2b2 + gray(sin2 * sin2);
  Vec3 t4 = t2 * sin2;
  Vec3 rp = divide(rs * (t3 - t4), t3 + t4);
  return 0.5f * (rp + rs);
}

Vec3 fresnelGeneralizedSchlick(float cosTheta, Vec3 f0, Vec3 f90, float exponent) {
  float x = fast::clamp(1.0f - cosTheta, 0.0f, 1.0f);
  return fast::lerp(f0, f90, fast::powPositive(x, exponent));
}

bool isMicrofacetLobe(Lobe::Model m) {
  switch (m) {
  case Lobe::Microfacet:
  case Lobe::MxDielectric:
  case Lobe::MxConductor:
  case Lobe::MxSchlick:
  case Lobe::Burley:
  case Lobe::Sheen: return true;
  default: return false;
  }
}

BsdfSample evalMicrofacetLobe(const Lobe &l, Vec3 wo, Vec3 wi) {
  switch (l.model) {
  case Lobe::Microfacet: return dielectricEval(l, wo, wi);
  case Lobe::MxDielectric:
  case Lobe::MxConductor:
  case Lobe::MxSchlick: return mxEval(l, wo, wi);
  case Lobe::Burley: return burleyEval(l, wo, wi);
  case Lobe::Sheen: return sheenEval(l, wo, wi);
  default: return {};
  }
}

BsdfSample sampleMicrofacetLobe(const Lobe &l, Vec3 wo, float rx, float ry, float rz) {
  float pdf;
  switch (l.model) {
  case Lobe::Microfacet: return dielectricSampleLobe(l, wo, rx, ry, rz);
  case Lobe::MxDielectric:
  case Lobe::MxConductor:
  case Lobe::MxSchlick: return mxSample(l, wo, rx, ry, rz);
  case Lobe::Burley: return burleyEval(l, wo, sampleCosineHemisphere(l.n, rx, ry, pdf));
  case Lobe::Sheen: return sheenEval(l, wo, sampleUniformHemisphere(l.n, rx, ry, pdf));
  default: return {};
  }
}

Vec3 microfacetLobeAlbedo(const Lobe &l, Vec3 wo) {
  switch (l.model) {
  case Lobe::Microfacet: return dielectricAlbedo(l, wo);
  case Lobe::MxDielectric:
  case Lobe::MxConductor:
  case Lobe::MxSchlick: return mxAlbedo(l, wo);
  case Lobe::Burley: return l.albedo;
  case Lobe::Sheen: return sheenAlbedo(l, wo);
  default: return gray(1.0f);
  }
}

} // namespace osl::render
