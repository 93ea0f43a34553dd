//===- ColorBuilder.cpp - OSL's color functions on lane values ------------===//
//
// The constants and algorithms are OSL's ColorSystem's (facts from its
// documentation and behaviour): chromaticities per space, the XYZ matrices
// derived from them, the Foley & van Dam hsv/hsl conversions, the YIQ
// matrices, Planck's law integrated against the CIE 1931 2-degree observer
// at 5 nm steps, and blackbody's table of nonlinearly spaced temperatures.
//
//===----------------------------------------------------------------------===//
#include "OslLanes/ColorBuilder.h"
#include "OslLanes/ConstantTable.h"
#include "OslLanes/LaneEmitter.h"
#include "OslLanes/LaneMath.h"

#include "mlir/Dialect/Arith/IR/Arith.h"
#include "mlir/Dialect/SCF/IR/SCF.h"
#include "mlir/Dialect/Vector/IR/VectorOps.h"

#include <cmath>
#include <map>
#include <mutex>

using namespace mlir;
using namespace mlir::osl;

namespace {

/// CIE 1931 2-degree colour matching functions x, y, z from 380 nm to
/// 780 nm in 5 nm steps, to four decimals (the table OSL integrates with).
constexpr float kCie[81][3] = {
    {0.0014f, 0.0000f, 0.0065f}, {0.0022f, 0.0001f, 0.0105f}, {0.0042f, 0.0001f, 0.0201f},
    {0.0076f, 0.0002f, 0.0362f}, {0.0143f, 0.0004f, 0.0679f}, {0.0232f, 0.0006f, 0.1102f},
    {0.0435f, 0.0012f, 0.2074f}, {0.0776f, 0.0022f, 0.3713f}, {0.1344f, 0.0040f, 0.6456f},
    {0.2148f, 0.0073f, 1.0391f}, {0.2839f, 0.0116f, 1.3856f}, {0.3285f, 0.0168f, 1.6230f},
    {0.3483f, 0.0230f, 1.7471f}, {0.3481f, 0.0298f, 1.7826f}, {0.3362f, 0.0380f, 1.7721f},
    {0.3187f, 0.0480f, 1.7441f}, {0.2908f, 0.0600f, 1.6692f}, {0.2511f, 0.0739f, 1.5281f},
    {0.1954f, 0.0910f, 1.2876f}, {0.1421f, 0.1126f, 1.0419f}, {0.0956f, 0.1390f, 0.8130f},
    {0.0580f, 0.1693f, 0.6162f}, {0.0320f, 0.2080f, 0.4652f}, {0.0147f, 0.2586f, 0.3533f},
    {0.0049f, 0.3230f, 0.2720f}, {0.0024f, 0.4073f, 0.2123f}, {0.0093f, 0.5030f, 0.1582f},
    {0.0291f, 0.6082f, 0.1117f}, {0.0633f, 0.7100f, 0.0782f}, {0.1096f, 0.7932f, 0.0573f},
    {0.1655f, 0.8620f, 0.0422f}, {0.2257f, 0.9149f, 0.0298f}, {0.2904f, 0.9540f, 0.0203f},
    {0.3597f, 0.9803f, 0.0134f}, {0.4334f, 0.9950f, 0.0087f}, {0.5121f, 1.0000f, 0.0057f},
    {0.5945f, 0.9950f, 0.0039f}, {0.6784f, 0.9786f, 0.0027f}, {0.7621f, 0.9520f, 0.0021f},
    {0.8425f, 0.9154f, 0.0018f}, {0.9163f, 0.8700f, 0.0017f}, {0.9786f, 0.8163f, 0.0014f},
    {1.0263f, 0.7570f, 0.0011f}, {1.0567f, 0.6949f, 0.0010f}, {1.0622f, 0.6310f, 0.0008f},
    {1.0456f, 0.5668f, 0.0006f}, {1.0026f, 0.5030f, 0.0003f}, {0.9384f, 0.4412f, 0.0002f},
    {0.8544f, 0.3810f, 0.0002f}, {0.7514f, 0.3210f, 0.0001f}, {0.6424f, 0.2650f, 0.0000f},
    {0.5419f, 0.2170f, 0.0000f}, {0.4479f, 0.1750f, 0.0000f}, {0.3608f, 0.1382f, 0.0000f},
    {0.2835f, 0.1070f, 0.0000f}, {0.2187f, 0.0816f, 0.0000f}, {0.1649f, 0.0610f, 0.0000f},
    {0.1212f, 0.0446f, 0.0000f}, {0.0874f, 0.0320f, 0.0000f}, {0.0636f, 0.0232f, 0.0000f},
    {0.0468f, 0.0170f, 0.0000f}, {0.0329f, 0.0119f, 0.0000f}, {0.0227f, 0.0082f, 0.0000f},
    {0.0158f, 0.0057f, 0.0000f}, {0.0114f, 0.0041f, 0.0000f}, {0.0081f, 0.0029f, 0.0000f},
    {0.0058f, 0.0021f, 0.0000f}, {0.0041f, 0.0015f, 0.0000f}, {0.0029f, 0.0010f, 0.0000f},
    {0.0020f, 0.0007f, 0.0000f}, {0.0014f, 0.0005f, 0.0000f}, {0.0010f, 0.0004f, 0.0000f},
    {0.0007f, 0.0002f, 0.0000f}, {0.0005f, 0.0002f, 0.0000f}, {0.0003f, 0.0001f, 0.0000f},
    {0.0002f, 0.0001f, 0.0000f}, {0.0002f, 0.0001f, 0.0000f}, {0.0001f, 0.0000f, 0.0000f},
    {0.0001f, 0.0000f, 0.0000f}, {0.0001f, 0.0000f, 0.0000f}, {0.0000f, 0.0000f, 0.0000f}};
constexpr int kCieSamples = 81;

/// Red, green, blue and white chromaticities (x, y) of each space.
struct Chromaticities {
  const char *name;
  float xy[8];
};
constexpr Chromaticities kSpaces[] = {
    {"Rec709", {0.64f, 0.33f, 0.30f, 0.60f, 0.15f, 0.06f, 0.3127f, 0.3291f}},
    {"sRGB", {0.64f, 0.33f, 0.30f, 0.60f, 0.15f, 0.06f, 0.3127f, 0.3291f}},
    {"NTSC", {0.67f, 0.33f, 0.21f, 0.71f, 0.14f, 0.08f, 0.3101f, 0.3162f}},
    {"EBU", {0.64f, 0.33f, 0.29f, 0.60f, 0.15f, 0.06f, 0.3127f, 0.3291f}},
    {"PAL", {0.64f, 0.33f, 0.29f, 0.60f, 0.15f, 0.06f, 0.3127f, 0.3291f}},
    {"SECAM", {0.64f, 0.33f, 0.29f, 0.60f, 0.15f, 0.06f, 0.3127f, 0.3291f}},
    {"SMPTE", {0.630f, 0.340f, 0.310f, 0.595f, 0.155f, 0.070f, 0.3127f, 0.3291f}},
    {"HDTV", {0.670f, 0.330f, 0.210f, 0.710f, 0.150f, 0.060f, 0.3127f, 0.3291f}},
    {"CIE", {0.7355f, 0.2645f, 0.2658f, 0.7243f, 0.1669f, 0.0085f, 1 / 3.f, 1 / 3.f}},
    {"AdobeRGB", {0.64f, 0.33f, 0.21f, 0.71f, 0.15f, 0.06f, 0.3127f, 0.3291f}},
    {"XYZ", {1.0f, 0.0f, 0.0f, 1.0f, 0.0f, 0.0f, 1 / 3.f, 1 / 3.f}},
    {"ACES2065-1", {0.7347f, 0.2653f, 0.0f, 1.0f, 0.0001f, -0.077f, 0.32168f, 0.33767f}},
    {"ACEScg", {0.713f, 0.293f, 0.165f, 0.830f, 0.128f, 0.044f, 0.32168f, 0.33767f}},
};

// blackbody's table: T_i = 2 i^1.5 + 800 up to the first entry past 12000 K.
constexpr float kDraperKelvin = 800.0f;
constexpr float kTableMaxKelvin = 12000.0f;
constexpr double kPlanckC1 = 3.74183e-16; // 2 pi h c^2, W m^2
constexpr double kPlanckC2 = 1.4388e-2;   // h c / k, m K
const float kCieStep = float(5.0f * 1e-9); // metres

std::array<float, 3> rowTimes(const std::array<float, 3> &c, const std::array<float, 9> &m) {
  std::array<float, 3> r;
  for (int j = 0; j < 3; ++j)
    r[j] = c[0] * m[0 * 3 + j] + c[1] * m[1 * 3 + j] + c[2] * m[2 * 3 + j];
  return r;
}

/// Planck's law at wavelength `nm` (W/m^2 per metre of wavelength).
float planck(float nm, double kelvin) {
  double metres = nm * 1e-9;
  return float((kPlanckC1 * std::pow(metres, -5.0)) / std::expm1(kPlanckC2 / (metres * kelvin)));
}

std::array<float, 3> blackbodyXYZ(float kelvin) {
  std::array<float, 3> xyz = {0, 0, 0};
  for (int i = 0; i < kCieSamples; ++i) {
    float me = planck(380.0f + 5.0f * float(i), kelvin) * kCieStep;
    for (int c = 0; c < 3; ++c)
      xyz[c] += me * kCie[i][c];
  }
  return xyz;
}

void initColorSystem(ColorSystem &cs, const Chromaticities &ch) {
  auto point = [&](int k) {
    float x = ch.xy[2 * k], y = ch.xy[2 * k + 1];
    return std::array<float, 3>{x, y, 1.0f - (x + y)};
  };
  auto R = point(0), G = point(1), B = point(2), W = point(3);
  std::array<float, 3> r = {G[1] * B[2] - B[1] * G[2], B[0] * G[2] - G[0] * B[2],
                            G[0] * B[1] - B[0] * G[1]};
  std::array<float, 3> g = {B[1] * R[2] - R[1] * B[2], R[0] * B[2] - B[0] * R[2],
                            B[0] * R[1] - R[0] * B[1]};
  std::array<float, 3> b = {R[1] * G[2] - G[1] * R[2], G[0] * R[2] - R[0] * G[2],
                            R[0] * G[1] - G[0] * R[1]};
  auto dot = [](auto &p, auto &q) { return p[0] * q[0] + p[1] * q[1] + p[2] * q[2]; };
  std::array<float, 3> w = {dot(r, W), dot(g, W), dot(b, W)};
  if (W[1] != 0.0f)
    for (float &x : w)
      x *= 1.0f / W[1]; // luminance of white = 1
  for (int i = 0; i < 3; ++i) {
    r[i] /= w[0];
    g[i] /= w[1];
    b[i] /= w[2];
  }
  cs.name = ch.name;
  for (int i = 0; i < 3; ++i) {
    cs.xyzToRgb[i * 3 + 0] = r[i];
    cs.xyzToRgb[i * 3 + 1] = g[i];
    cs.xyzToRgb[i * 3 + 2] = b[i];
  }
  // The inverse, by cofactors in double.
  const auto &m = cs.xyzToRgb;
  auto at = [&](int i, int j) { return double(m[i * 3 + j]); };
  double det = at(0, 0) * (at(1, 1) * at(2, 2) - at(1, 2) * at(2, 1)) -
               at(0, 1) * (at(1, 0) * at(2, 2) - at(1, 2) * at(2, 0)) +
               at(0, 2) * (at(1, 0) * at(2, 1) - at(1, 1) * at(2, 0));
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      int i1 = (j + 1) % 3, i2 = (j + 2) % 3, j1 = (i + 1) % 3, j2 = (i + 2) % 3;
      cs.rgbToXyz[i * 3 + j] = float((at(i1, j1) * at(i2, j2) - at(i1, j2) * at(i2, j1)) / det);
    }
  cs.luminance = {cs.rgbToXyz[1], cs.rgbToXyz[4], cs.rgbToXyz[7]};
  // Rounding can keep the weights from summing to 1; if nearly, make it so.
  float rest = 1.0f - cs.luminance[0] - cs.luminance[1];
  if (std::fabs(rest - cs.luminance[2]) < 0.001f)
    cs.luminance[2] = rest;
}

//===----------------------------------------------------------------------===//
// Lane code
//===----------------------------------------------------------------------===//

/// The lane emitter with the color conversions' pieces. Constants take
/// the shape of a value (cst), as colors come uniform or varying.
struct ColorLanes : public LaneEmitter {
  ColorLanes(OpBuilder &b, Location loc) : LaneEmitter(b, loc) {}

  /// v0 (1 - t) + v1 t, as OpenImageIO's lerp.
  Value lerp(Value v0, Value v1, Value t) {
    return add(mul(v0, sub(cst(t, 1), t)), mul(v1, t));
  }
  /// c < 0 becomes 0 (NaN stays).
  Value clampZero(Value c) { return select(lt(c, cst(c, 0)), cst(c, 0), c); }
  /// c * m for a row vector c.
  LaneColor times(LaneColor c, const std::array<float, 9> &m) {
    LaneColor r;
    for (int j = 0; j < 3; ++j)
      r[j] = add(add(mul(c[0], cst(c[0], m[j])), mul(c[1], cst(c[0], m[3 + j]))),
                 mul(c[2], cst(c[0], m[6 + j])));
    return r;
  }
  /// Lanes of `x`, as an i32 lane value that truncates toward zero.
  Value toInt(Value x) { return lane::convert(b, loc, x, b.getI32Type()); }
  Value toFloat(Value i) { return lane::convert(b, loc, i, b.getF32Type()); }
  Value addInt(Value i, int64_t k) {
    return b.create<arith::AddIOp>(loc, i, lane::constantLike(b, loc, i, double(k)));
  }
};

LaneColor hsvToRgb(ColorLanes &l, LaneColor hsv) {
  auto [h, s, v] = hsv;
  Value one = l.cst(h, 1);
  Value h6 = l.mul(l.cst(h, 6), l.sub(h, lane::floor(l.b, l.loc, {h}))); // [0, 6)
  Value hi = lane::floor(l.b, l.loc, {h6});
  Value f = l.sub(h6, hi);
  Value p = l.mul(v, l.sub(one, s));
  Value q = l.mul(v, l.sub(one, l.mul(s, f)));
  Value t = l.mul(v, l.sub(one, l.mul(s, l.sub(one, f))));
  // The sextant's (r, g, b), from sextant 0 to 5 (and beyond: 5).
  const Value table[6][3] = {{v, t, p}, {q, v, p}, {p, v, t}, {p, q, v}, {t, p, v}, {v, p, q}};
  LaneColor rgb = {table[5][0], table[5][1], table[5][2]};
  for (int k = 4; k >= 0; --k) {
    Value isK = l.feq(hi, l.cst(hi, k));
    rgb = l.select(isK, LaneColor{table[k][0], table[k][1], table[k][2]}, rgb);
  }
  Value grey = l.lt(s, l.cst(s, 0.0001));
  return l.select(grey, LaneColor{v, v, v}, rgb);
}

LaneColor rgbToHsv(ColorLanes &l, LaneColor rgb) {
  auto [r, g, b] = rgb;
  Value zero = l.cst(r, 0);
  Value lo = l.min(r, l.min(g, b));
  Value hi = l.max(r, l.max(g, b));
  Value delta = l.sub(hi, lo);
  Value s = l.select(l.lt(zero, hi), l.div(delta, hi), zero);
  Value hr = l.div(l.sub(g, b), delta);
  Value hg = l.add(l.cst(r, 2), l.div(l.sub(b, r), delta));
  Value hb = l.add(l.cst(r, 4), l.div(l.sub(r, g), delta));
  Value h = l.select(l.ge(r, hi), hr, l.select(l.ge(g, hi), hg, hb));
  h = l.mul(h, l.cst(r, 1.0f / 6.0f));
  h = l.select(l.lt(h, zero), l.add(h, l.cst(r, 1)), h);
  h = l.select(l.le(s, zero), zero, h);
  return {h, s, hi};
}

LaneColor hslToRgb(ColorLanes &l, LaneColor hsl) {
  auto [h, s, lum] = hsl;
  Value one = l.cst(h, 1), zero = l.cst(h, 0);
  Value v = l.select(l.le(lum, l.cst(h, 0.5)), l.mul(lum, l.add(one, s)),
                  l.add(l.mul(lum, l.sub(one, s)), s));
  Value lo = l.sub(l.mul(l.cst(h, 2), lum), v);
  Value sv = l.div(l.sub(v, lo), v);
  LaneColor rgb = hsvToRgb(l, {h, sv, v});
  return l.select(l.le(v, zero), LaneColor{zero, zero, zero}, rgb);
}

LaneColor rgbToHsl(ColorLanes &l, LaneColor rgb) {
  auto [r, g, b] = rgb;
  Value lo = l.min(r, l.min(g, b));
  LaneColor hsv = rgbToHsv(l, rgb);
  Value hi = hsv[2];
  Value lum = l.div(l.add(lo, hi), l.cst(r, 2));
  Value delta = l.sub(hi, lo);
  Value s = l.select(l.le(lum, l.cst(r, 0.5)), l.div(delta, l.add(hi, lo)),
                  l.div(delta, l.sub(l.sub(l.cst(r, 2), hi), lo)));
  s = l.select(l.feq(lo, hi), l.cst(r, 0), s);
  return {hsv[0], s, lum};
}

constexpr std::array<float, 9> kYiqToRgb = {1.0000f, 1.0000f,  1.0000f,  0.9557f, -0.2716f,
                                            -1.1082f, 0.6199f, -0.6469f, 1.7051f};
constexpr std::array<float, 9> kRgbToYiq = {0.299f, 0.596f,  0.212f,  0.587f, -0.275f,
                                            -0.523f, 0.114f, -0.321f, 0.311f};

LaneColor xyYToXYZ(ColorLanes &l, LaneColor xyY) {
  auto [x, y, Y] = xyY;
  Value zero = l.cst(x, 0);
  Value yRatio = l.select(l.lt(l.cst(x, 1.0e-6), y), l.div(Y, y), zero);
  return {l.mul(yRatio, x), Y, l.mul(yRatio, l.sub(l.sub(l.cst(x, 1), x), y))};
}

LaneColor xyzToXyY(ColorLanes &l, LaneColor xyz) {
  auto [X, Y, Z] = xyz;
  Value n = l.add(l.add(X, Y), Z);
  Value inv = l.select(l.ge(n, l.cst(X, 1.0e-6)), l.div(l.cst(X, 1), n), l.cst(X, 0));
  return {l.mul(X, inv), l.mul(Y, inv), Y};
}

LaneColor srgbToLinear(ColorLanes &l, LaneColor c) {
  LaneColor r;
  for (int i = 0; i < 3; ++i) {
    Value x = c[i];
    Value lin = l.mul(x, l.cst(x, 1.0f / 12.92f));
    Value curve = lane::pow(l.b, l.loc,
                            {l.mul(l.add(x, l.cst(x, 0.055f)), l.cst(x, 1.0f / 1.055f)),
                             l.cst(x, 2.4f)});
    r[i] = l.select(l.le(x, l.cst(x, 0.04045f)), lin, curve);
  }
  return r;
}

LaneColor linearToSrgb(ColorLanes &l, LaneColor c) {
  LaneColor r;
  for (int i = 0; i < 3; ++i) {
    Value x = c[i];
    Value lin = l.mul(l.cst(x, 12.92f), x);
    Value curve = l.sub(
        l.mul(l.cst(x, 1.055f), lane::pow(l.b, l.loc, {x, l.cst(x, 1.0f / 2.4f)})),
        l.cst(x, 0.055f));
    r[i] = l.select(l.le(x, l.cst(x, 0.0031308f)), lin, curve);
  }
  return r;
}

bool isWorkingRgb(StringRef space, StringRef working) {
  return space == "rgb" || space == "RGB" || space == "linear" || space == working;
}

std::optional<LaneColor> toRgb(ColorLanes &l, const ColorSystem &cs, StringRef from, LaneColor c) {
  if (isWorkingRgb(from, cs.name))
    return c;
  if (from == "hsv")
    return hsvToRgb(l, c);
  if (from == "hsl")
    return hslToRgb(l, c);
  if (from == "YIQ")
    return l.times(c, kYiqToRgb);
  if (from == "XYZ")
    return l.times(c, cs.xyzToRgb);
  if (from == "xyY")
    return l.times(xyYToXYZ(l, c), cs.xyzToRgb);
  if (from == "sRGB")
    return srgbToLinear(l, c);
  return std::nullopt;
}

std::optional<LaneColor> fromRgb(ColorLanes &l, const ColorSystem &cs, StringRef to, LaneColor c) {
  if (isWorkingRgb(to, cs.name))
    return c;
  if (to == "hsv")
    return rgbToHsv(l, c);
  if (to == "hsl")
    return rgbToHsl(l, c);
  if (to == "YIQ")
    return l.times(c, kRgbToYiq);
  if (to == "XYZ")
    return l.times(c, cs.rgbToXyz);
  if (to == "xyY")
    return xyzToXyY(l, l.times(c, cs.rgbToXyz));
  if (to == "sRGB")
    return linearToSrgb(l, c);
  return std::nullopt;
}

/// The symbol of a table that depends on the working space, and of one
/// that does not.
std::string tableSymbol(const ColorSystem &cs, StringRef what) {
  return ("osl_" + what + "_" + cs.name).str();
}
std::string tableSymbol(StringRef what) { return ("osl_" + what).str(); }

/// The observer's x, y or z weights (`channel` 0, 1, 2) as a constant
/// table, shared by blackbody and wavelength_color.
LLVM::GlobalOp cieTable(OpBuilder &b, Location loc, int channel) {
  static const char *names[3] = {"cie_x", "cie_y", "cie_z"};
  std::vector<float> column;
  for (int i = 0; i < kCieSamples; ++i)
    column.push_back(kCie[i][channel]);
  return getConstantTable(b, loc, tableSymbol(names[channel]), column);
}

/// Per wavelength of the observer: Planck's law as scale / expm1(exponent
/// / T), and the CIE x, y, z weights.
struct SpectrumTables {
  LLVM::GlobalOp scale, exponent, cie[3];

  SpectrumTables(OpBuilder &b, Location loc) {
    std::vector<float> s, e;
    for (int i = 0; i < kCieSamples; ++i) {
      double metres = (380.0f + 5.0f * float(i)) * 1e-9;
      s.push_back(float(kPlanckC1 * std::pow(metres, -5.0)));
      e.push_back(float(kPlanckC2 / metres));
    }
    scale = getConstantTable(b, loc, tableSymbol("planck_scale"), s);
    exponent = getConstantTable(b, loc, tableSymbol("planck_exponent"), e);
    for (int k = 0; k < 3; ++k)
      cie[k] = cieTable(b, loc, k);
  }
};

/// blackbody above the table: Planck's law summed over the observer's 81
/// wavelengths, one loop iteration per wavelength.
LaneColor blackbodyBySpectrum(ColorLanes &l, const ColorSystem &cs, const SpectrumTables &tables,
                              Value kelvin) {
  OpBuilder &b = l.b;
  Value zero = l.cst(kelvin, 0);
  Value lb = b.create<arith::ConstantIndexOp>(l.loc, 0);
  Value ub = b.create<arith::ConstantIndexOp>(l.loc, kCieSamples);
  Value step = b.create<arith::ConstantIndexOp>(l.loc, 1);
  auto loop = b.create<scf::ForOp>(
      l.loc, lb, ub, step, ValueRange{zero, zero, zero},
      [&](OpBuilder &nb, Location loc, Value iv, ValueRange xyz) {
        ColorLanes in(nb, loc);
        Value i = nb.create<arith::IndexCastOp>(loc, nb.getI32Type(), iv);
        int64_t width = 0;
        if (auto vec = dyn_cast<VectorType>(kelvin.getType()))
          width = vec.getNumElements();
        auto load = [&](LLVM::GlobalOp table) {
          return lane::broadcast(nb, loc, lookupConstantTable(nb, loc, table, i), width);
        };
        Value spectral = in.div(
            load(tables.scale),
            lane::expm1(nb, loc, {in.div(load(tables.exponent), kelvin)}));
        Value me = in.mul(spectral, in.cst(kelvin, kCieStep));
        SmallVector<Value> sums;
        for (int c = 0; c < 3; ++c)
          sums.push_back(in.add(xyz[c], in.mul(me, load(tables.cie[c]))));
        nb.create<scf::YieldOp>(loc, sums);
      });
  LaneColor rgb =
      l.times({loop.getResult(0), loop.getResult(1), loop.getResult(2)}, cs.xyzToRgb);
  for (Value &c : rgb)
    c = l.clampZero(c);
  return rgb;
}

} // namespace

const std::array<std::vector<float>, 3> &ColorSystem::blackbodyTable() const {
  std::call_once(blackbodyOnce, [&] {
    float lastKelvin = 0;
    for (int i = 0; lastKelvin <= kTableMaxKelvin; ++i) {
      float s = std::sqrt(float(i));
      float kelvin = s * s * s * 2.0f + kDraperKelvin;
      lastKelvin = kelvin;
      std::array<float, 3> rgb = rowTimes(blackbodyXYZ(kelvin), xyzToRgb);
      for (int c = 0; c < 3; ++c)
        blackbody[c].push_back(std::pow(std::max(rgb[c], 0.0f), 1.0f / 5.0f));
    }
  });
  return blackbody;
}

const ColorSystem *ColorSystem::get(StringRef name) {
  static std::mutex mutex;
  static std::map<std::string, ColorSystem, std::less<>> made;
  std::lock_guard<std::mutex> lock(mutex);
  if (auto it = made.find(name); it != made.end())
    return &it->second;
  for (const Chromaticities &ch : kSpaces)
    if (name == ch.name) {
      ColorSystem &cs = made.try_emplace(ch.name).first->second;
      initColorSystem(cs, ch);
      return &cs;
    }
  return nullptr;
}

bool mlir::osl::isColorSpaceName(StringRef space, StringRef working) {
  return isWorkingRgb(space, working) ||
         llvm::is_contained(ArrayRef<StringRef>{"hsv", "hsl", "YIQ", "XYZ", "xyY", "sRGB"},
                            space);
}

FailureOr<LaneColor> mlir::osl::buildTransformc(OpBuilder &b, Location loc,
                                                const ColorSystem &cs, StringRef from,
                                                StringRef to, LaneColor c) {
  ColorLanes l(b, loc);
  std::optional<LaneColor> rgb = toRgb(l, cs, from, c);
  if (!rgb)
    return failure();
  std::optional<LaneColor> r = fromRgb(l, cs, to, *rgb);
  if (!r)
    return failure();
  return *r;
}

LaneColor mlir::osl::buildBlackbody(OpBuilder &b, Location loc, const ColorSystem &cs,
                                    Value kelvin) {
  ColorLanes l(b, loc);
  Value below = l.lt(kelvin, l.cst(kelvin, kDraperKelvin));
  Value inTable = l.lt(kelvin, l.cst(kelvin, kTableMaxKelvin));
  // The table position i = ((T - 800) / 2)^(2/3); lanes outside the table
  // read entry 0 (their result is chosen elsewhere).
  Value tableLane = b.create<arith::AndIOp>(
      loc, inTable, b.create<arith::XOrIOp>(loc, below, lane::constantLike(b, loc, below, 1)));
  Value t = l.div(l.sub(kelvin, l.cst(kelvin, kDraperKelvin)), l.cst(kelvin, 2));
  Value cube = lane::cbrt(b, loc, {t});
  Value pos = l.select(tableLane, l.mul(cube, cube), l.cst(kelvin, 0));
  Value index = l.toInt(pos);
  Value frac = l.sub(pos, l.toFloat(index));
  LaneColor table;
  static const char *names[3] = {"blackbody_r", "blackbody_g", "blackbody_b"};
  for (int c = 0; c < 3; ++c) {
    LLVM::GlobalOp entries =
        getConstantTable(b, loc, tableSymbol(cs, names[c]), cs.blackbodyTable()[c]);
    Value lo = lookupConstantTable(b, loc, entries, index);
    Value hi = lookupConstantTable(b, loc, entries, l.addInt(index, 1));
    Value x = l.lerp(lo, hi, frac);
    Value x2 = l.mul(x, x);
    table[c] = l.mul(l.mul(x2, x2), x); // the table holds the 5th root
  }
  // Hotter lanes integrate the spectrum, when the batch has any.
  Value hot = l.ge(kelvin, l.cst(kelvin, kTableMaxKelvin));
  SpectrumTables spectrum(b, loc);
  auto ifHot = b.create<scf::IfOp>(
      loc, lane::any(b, loc, hot),
      [&](OpBuilder &tb, Location tl) {
        ColorLanes in(tb, tl);
        LaneColor r = blackbodyBySpectrum(in, cs, spectrum, kelvin);
        tb.create<scf::YieldOp>(tl, ValueRange{r[0], r[1], r[2]});
      },
      [&](OpBuilder &eb, Location el) {
        Value z = lane::constantLike(eb, el, kelvin, 0);
        eb.create<scf::YieldOp>(el, ValueRange{z, z, z});
      });
  LaneColor result;
  for (int c = 0; c < 3; ++c) {
    Value dim = l.cst(kelvin, c == 0 ? 1.0e-6 : 0.0); // very dim red below 800 K
    Value v = l.select(below, dim, l.select(inTable, table[c], ifHot.getResult(c)));
    v.getDefiningOp()->setAttr(kDualRuleAttr, b.getStringAttr(kDualRuleNone));
    result[c] = v;
  }
  return result;
}

LaneColor mlir::osl::buildWavelengthColor(OpBuilder &b, Location loc, const ColorSystem &cs,
                                          Value nanometers) {
  ColorLanes l(b, loc);
  Value pos = l.div(l.sub(nanometers, l.cst(nanometers, 380)), l.cst(nanometers, 5));
  // int(pos) must lie in [0, 80): pos in (-1, 80).
  Value inside = b.create<arith::AndIOp>(loc, l.lt(l.cst(pos, -1), pos),
                                         l.lt(pos, l.cst(pos, 80)));
  Value index = l.toInt(l.select(inside, pos, l.cst(pos, 0)));
  Value frac = l.sub(pos, l.toFloat(index));
  LaneColor xyz;
  for (int c = 0; c < 3; ++c) {
    LLVM::GlobalOp entries = cieTable(b, loc, c);
    Value lo = lookupConstantTable(b, loc, entries, index);
    Value hi = lookupConstantTable(b, loc, entries, l.addInt(index, 1));
    xyz[c] = l.lerp(lo, hi, frac);
  }
  LaneColor rgb = l.times(xyz, cs.xyzToRgb);
  LaneColor result;
  for (int c = 0; c < 3; ++c) {
    // An empirical scale that keeps every component at most 1.
    Value v = l.clampZero(l.mul(rgb[c], l.cst(rgb[c], float(1.0 / 2.52))));
    v = l.select(inside, v, l.cst(v, 0));
    v.getDefiningOp()->setAttr(kDualRuleAttr, b.getStringAttr(kDualRuleNone));
    result[c] = v;
  }
  return result;
}

Value mlir::osl::buildLuminance(OpBuilder &b, Location loc, const ColorSystem &cs,
                                LaneColor c) {
  ColorLanes l(b, loc);
  return l.add(l.add(l.mul(c[0], l.cst(c[0], cs.luminance[0])),
                     l.mul(c[1], l.cst(c[1], cs.luminance[1]))),
               l.mul(c[2], l.cst(c[2], cs.luminance[2])));
}
