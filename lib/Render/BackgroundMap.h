//===- BackgroundMap.h - Importance sampling of the background -----*- C++ -*-===//
//
// testrender's table for <Background resolution="N"/>: the background
// shaded at the centres of an N x N latitude-longitude grid (N at least
// 32), a cumulative distribution over rows and, per row, over columns, in
// proportion to each cell's largest channel. Escaping rays after the first
// bounce read the table instead of running the shader, and each hit point
// sends one shadow ray toward a direction the table samples.
//
//===----------------------------------------------------------------------===//
#ifndef OSLRENDER_BACKGROUNDMAP_H
#define OSLRENDER_BACKGROUNDMAP_H

#include "Dual.h"
#include "OslRender/Vec3.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <vector>

namespace osl::render {

class BackgroundMap {
public:
  /// Shades the grid's directions with `shade` (directions with their
  /// derivatives along the grid in, radiance out, as many as given) and
  /// builds the distributions.
  void prepare(int resolution,
               const std::function<void(const std::vector<Dual3> &, std::vector<Vec3> &)> &shade);
  bool empty() const { return res == 0; }
  /// The radiance over the pdf of direction `dir`, and that pdf.
  Vec3 eval(Vec3 dir, float &pdf) const;
  /// The tables, for sampling in lanes (LaneKernels::sampleBackground).
  struct Table {
    int res = 0;
    float invres = 0, invjacobian = 0;
    const float *rows = nullptr, *cols = nullptr;
    const Vec3 *values = nullptr;
  };
  Table table() const { return {res, invres, invjacobian, rows.data(), cols.data(), values.data()}; }

private:
  int res = 0;
  float invres = 0, invjacobian = 0;
  std::vector<Vec3> values;
  /// Cumulative: rows[y] over rows; cols[y * res + x] within row y.
  std::vector<float> rows, cols;
};

/// The cell of the table direction `dir` falls in (testrender's), and the
/// pdf of sampling it.
inline size_t tableCell(const BackgroundMap::Table &t, Vec3 dir, float &pdf) {
  float u = fast::atan2(dir.y, dir.x) * float(M_1_PI * 0.5f);
  u = u < 0 ? u + 1 : u;
  float v = (1 - dir.z) * 0.5f;
  int x = std::clamp(int(u * float(t.res)), 0, t.res - 1);
  int y = std::clamp(int(v * float(t.res)), 0, t.res - 1);
  int i = y * t.res + x;
  float rowPdf = t.rows[y] - (y > 0 ? t.rows[y - 1] : 0.0f);
  float colPdf = t.cols[i] - (x > 0 ? t.cols[i - 1] : 0.0f);
  pdf = rowPdf * colPdf * t.invjacobian;
  return size_t(i);
}

/// Sampling the table, in pieces a lane loop runs (LaneKernels'
/// sampleBackground searches the distributions between them, each lane a
/// branchless std::upper_bound): entry `index` of the cumulative `cdf`
/// chosen for `x` (below 1), its probability, and x rescaled within it.
inline float rescaleInCdf(const float *cdf, int index, float x, float &p) {
  float below = index > 0 ? cdf[index - 1] : 0.0f, at = cdf[index];
  p = index > 0 ? at - below : at;
  float scaled = index > 0 ? (x - below) / (at - below) : x / at;
  return std::min(scaled, 0.99999994f);
}

/// The direction at grid coordinates (x, y), with its derivatives along
/// them (the table's shading wants them; a sample, only the value).
inline Dual3 tableDirection(const BackgroundMap::Table &t, float x, float y) {
  Dual u = Dual(x, 1, 0) * t.invres, v = Dual(y, 0, 1) * t.invres;
  Dual st, ct;
  fastSinCos(u * float(2 * M_PI), st, ct);
  Dual cosPhi = 1.0f - 2.0f * v;
  Dual sinPhi = sqrt(1.0f - cosPhi * cosPhi);
  return Dual3::of(sinPhi * ct, sinPhi * st, cosPhi);
}

} // namespace osl::render

#endif // OSLRENDER_BACKGROUNDMAP_H
