//===- Spaces.cpp - Named coordinate spaces -------------------------------===//
//
// testshade's fixed spaces (../shared/conformance/README.md): "common" =
// "world" = "camera"; shader->common rotates 45 degrees about z then
// translates (1,0,0); object->common rotates 90 degrees about z (by the
// float pi/2, as testshade's Imath does) then translates (0,1,0); myspace->common scales by (1,2,1). Matrices are
// composed in double and rounded to float once, when emitted.
//
// The camera spaces follow testshade's SimpleRenderer: common->screen is
// a perspective projection (x/z, y/z scaled by 1/tan(fov/2), depth mapped
// so that near -> 0 and far -> 1 after the w divide), screen->NDC maps the
// window [-1,1]^2 to [0,1]^2, NDC->raster scales by the image size. The
// renderer builds these entries in float; so does cameraFromCommon.
//
//===----------------------------------------------------------------------===//
#include "OslLanes/LibraryBuilders.h"
#include "OslLanes/NamedSpaces.h"

#include "mlir/Dialect/Arith/IR/Arith.h"
#include "OslLanes/LaneMath.h"

#include <cmath>

using namespace mlir;
using namespace mlir::osl;

namespace {

Matrix44 identity() {
  return {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
}

std::optional<Matrix44> toCommon(StringRef space) {
  if (space == "common" || space == "world" || space == "camera")
    return identity();
  double c = std::sqrt(0.5);
  if (space == "shader")
    return Matrix44{c, c, 0, 0, -c, c, 0, 0, 0, 0, 1, 0, 1, 0, 0, 1};
  if (space == "object") {
    // testshade rotates by the float pi/2 with float cos and sin (Imath's
    // rotate): its cosine is -4.37113883e-08, not 0, and shaders that print
    // the matrix or transform by it show that.
    double co = std::cos(float(M_PI_2)), si = std::sin(float(M_PI_2));
    return Matrix44{co, si, 0, 0, -si, co, 0, 0, 0, 0, 1, 0, 0, 1, 0, 1};
  }
  if (space == "myspace")
    return Matrix44{1, 0, 0, 0, 0, 2, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  return std::nullopt;
}

Matrix44 multiply(const Matrix44 &a, const Matrix44 &b) {
  Matrix44 r{};
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      for (int k = 0; k < 4; ++k)
        r[i * 4 + j] += a[i * 4 + k] * b[k * 4 + j];
  return r;
}

/// Gauss-Jordan with partial pivoting; the spaces above are all invertible.
Matrix44 inverse(Matrix44 m) {
  Matrix44 inv = identity();
  for (int col = 0; col < 4; ++col) {
    int pivot = col;
    for (int r = col + 1; r < 4; ++r)
      if (std::fabs(m[r * 4 + col]) > std::fabs(m[pivot * 4 + col]))
        pivot = r;
    for (int k = 0; k < 4; ++k) {
      std::swap(m[col * 4 + k], m[pivot * 4 + k]);
      std::swap(inv[col * 4 + k], inv[pivot * 4 + k]);
    }
    double d = m[col * 4 + col];
    for (int k = 0; k < 4; ++k) {
      m[col * 4 + k] /= d;
      inv[col * 4 + k] /= d;
    }
    for (int r = 0; r < 4; ++r) {
      if (r == col)
        continue;
      double f = m[r * 4 + col];
      for (int k = 0; k < 4; ++k) {
        m[r * 4 + k] -= f * m[col * 4 + k];
        inv[r * 4 + k] -= f * inv[col * 4 + k];
      }
    }
  }
  return inv;
}

/// common (= camera) to "screen", "NDC" or "raster".
Matrix44 cameraFromCommon(StringRef space, const CameraImage &camera) {
  const float fovDegrees = 90.0f, hither = 0.1f, yon = 1000.0f;
  float tanHalfFov = std::tan(float(0.5 * fovDegrees * M_PI / 180.0));
  float depthRange = float(double(yon) - double(hither));
  float focal = 1.0f / tanHalfFov;
  float depthScale = yon / depthRange;
  float depthOffset = -(yon * hither) / depthRange;
  Matrix44 m{focal, 0, 0, 0, 0, focal, 0, 0, 0, 0, depthScale, 1, 0, 0, depthOffset, 0};
  if (space == "screen")
    return m;
  Matrix44 toNdc{0.5, 0, 0, 0, 0, 0.5, 0, 0, 0, 0, 1, 0, 0.5, 0.5, 0, 1};
  m = multiply(m, toNdc);
  if (space == "NDC")
    return m;
  Matrix44 toRaster{double(camera.xres), 0, 0, 0, 0, double(camera.yres), 0, 0,
                    0, 0, 1, 0, 0, 0, 0, 1};
  return multiply(m, toRaster);
}

} // namespace

bool mlir::osl::isProjectionSpace(StringRef space) {
  return space == "screen" || space == "NDC" || space == "raster";
}

std::optional<Matrix44> mlir::osl::namedSpaceTransform(StringRef from, StringRef to,
                                                        const CameraImage &camera) {
  if (!isProjectionSpace(to))
    return namedSpaceTransform(from, to);
  if (from == to) // as below
    return identity();
  if (from == "camera") // as below
    return std::nullopt;
  auto fromCommon = toCommon(from);
  if (!fromCommon)
    return std::nullopt;
  return multiply(*fromCommon, cameraFromCommon(to, camera));
}

std::optional<Matrix44> mlir::osl::namedSpaceTransform(StringRef from,
                                                        StringRef to) {
  auto fromCommon = toCommon(from);
  auto toSpace = toCommon(to);
  if (!fromCommon || !toSpace)
    return std::nullopt;
  // A space to itself is exactly the identity (as OSL answers), not a
  // product with a float inverse.
  if (from == to)
    return identity();
  // testshade's renderer has a matrix to "camera" but none from it.
  if (from == "camera")
    return std::nullopt;
  return multiply(*fromCommon, inverse(*toSpace));
}

std::array<Value, 3> mlir::osl::buildTransform(OpBuilder &b, Location loc,
                                               const Matrix44 &matrix,
                                               TransformKind kind,
                                               std::array<Value, 3> p) {
  Matrix44 m = matrix;
  if (kind == TransformKind::normal) {
    Matrix44 inv = inverse(matrix);
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j)
        m[i * 4 + j] = inv[j * 4 + i];
  }
  bool translate = kind == TransformKind::point;
  std::array<Value, 3> out;
  for (int j = 0; j < 3; ++j) {
    Value sum;
    for (int i = 0; i < 3; ++i) {
      Value term = b.create<arith::MulFOp>(
          loc, p[i], lane::constantLike(b, loc, p[i], float(m[i * 4 + j])));
      sum = sum ? b.create<arith::AddFOp>(loc, sum, term).getResult() : term;
    }
    if (translate)
      sum = b.create<arith::AddFOp>(
          loc, sum, lane::constantLike(b, loc, p[0], float(m[12 + j])));
    out[j] = sum;
  }
  return out;
}
