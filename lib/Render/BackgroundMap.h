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
  /// A direction drawn with (rx, ry), its radiance over its pdf, and the pdf.
  Vec3 sample(float rx, float ry, Vec3 &dir, float &pdf) const;

private:
  /// The direction at grid coordinates (x, y), with its derivatives along
  /// them.
  Dual3 direction(float x, float y) const;
  int res = 0;
  float invres = 0, invjacobian = 0;
  std::vector<Vec3> values;
  /// Cumulative: rows[y] over rows; cols[y * res + x] within row y.
  std::vector<float> rows, cols;
};

} // namespace osl::render

#endif // OSLRENDER_BACKGROUNDMAP_H
