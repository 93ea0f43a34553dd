//===- BackgroundMap.cpp - Importance sampling of the background ----------===//
#include "BackgroundMap.h"
#include "OslRender/Sampling.h"

#include <algorithm>

namespace osl::render {
void BackgroundMap::prepare(
    int resolution,
    const std::function<void(const std::vector<Dual3> &, std::vector<Vec3> &)> &shade) {
  res = std::max(resolution, 32);
  invres = 1.0f / float(res);
  invjacobian = float(res * res) / float(4 * M_PI);
  std::vector<Dual3> dirs;
  dirs.reserve(size_t(res) * res);
  for (int y = 0; y < res; ++y)
    for (int x = 0; x < res; ++x)
      dirs.push_back(tableDirection(table(), float(x) + 0.5f, float(y) + 0.5f));
  shade(dirs, values);
  rows.assign(res, 0.0f);
  cols.assign(size_t(res) * res, 0.0f);
  for (int y = 0, i = 0; y < res; ++y) {
    for (int x = 0; x < res; ++x, ++i)
      cols[i] = std::max(std::max(values[i].x, values[i].y), values[i].z) +
                (x > 0 ? cols[i - 1] : 0.0f);
    rows[y] = cols[i - 1] + (y > 0 ? rows[y - 1] : 0.0f);
    if (cols[i - 1] > 0)
      for (int x = 0; x < res; ++x)
        cols[i - res + x] /= cols[i - 1];
  }
  for (int y = 0; y < res; ++y)
    rows[y] /= rows[res - 1];
  for (int y = 0, i = 0; y < res; ++y) {
    float rowPdf = rows[y] - (y > 0 ? rows[y - 1] : 0.0f);
    for (int x = 0; x < res; ++x, ++i) {
      float colPdf = cols[i] - (x > 0 ? cols[i - 1] : 0.0f);
      values[i] = values[i] / (rowPdf * colPdf * invjacobian);
    }
  }
}

Vec3 BackgroundMap::eval(Vec3 dir, float &pdf) const {
  return values[tableCell(table(), dir, pdf)];
}

} // namespace osl::render
