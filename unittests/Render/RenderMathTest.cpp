//===- RenderMathTest.cpp - The renderer's polynomials against double ----===//
//
// RenderMath.h's sin, cos, atan2 and acos replace libm's in the renderer's
// lane loops: measured here against glibc's double precision results over
// the ranges the renderer uses, in absolute error (the renderer's angles
// and parameters are O(1)).
//
//===----------------------------------------------------------------------===//
#include "OslRender/RenderMath.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace osl::render;

namespace {
/// A float's spacing near `x` (one ulp), for the bounds.
double ulp(double x) { return std::ldexp(1.0, std::ilogb(std::fmax(std::fabs(x), 1e-30)) - 23); }
} // namespace

TEST(RenderMath, SinCosWithinAFewUlpsOfDouble) {
  double worst = 0;
  for (int i = -400000; i <= 400000; ++i) {
    float x = float(i) * (4 * kRenderPi / 400000); // [-4 pi, 4 pi]
    float s, c;
    polySinCos(x, s, c);
    // Absolute error in ulps of 1: sin and cos are at most 1.
    worst = std::fmax(worst, std::fabs(s - std::sin(double(x))) / ulp(1.0));
    worst = std::fmax(worst, std::fabs(c - std::cos(double(x))) / ulp(1.0));
  }
  EXPECT_LE(worst, 4.0) << "max error " << worst << " ulps of 1";
  float s, c;
  polySinCos(0.0f, s, c);
  EXPECT_EQ(s, 0.0f);
  EXPECT_EQ(c, 1.0f);
}

TEST(RenderMath, Atan2WithinAFewUlpsOfDouble) {
  double worst = 0;
  for (int i = 0; i < 1000; ++i)
    for (int j = 0; j < 1000; ++j) {
      float y = float(i - 500) / 173.0f, x = float(j - 500) / 211.0f;
      double exact = std::atan2(double(y), double(x));
      double err = std::fabs(polyAtan2(y, x) - exact) / ulp(exact);
      worst = std::fmax(worst, std::fabs(exact) < 1e-3 ? 0 : err);
    }
  EXPECT_LE(worst, 4.0) << "max error " << worst << " ulps";
  EXPECT_EQ(polyAtan2(0, 0), 0.0f);
  EXPECT_NEAR(polyAtan2(0, -1), float(M_PI), 1e-6f);
  EXPECT_NEAR(polyAtan2(-1, 0), float(-M_PI / 2), 1e-6f);
}

TEST(RenderMath, AcosWithinAFewUlpsOfDouble) {
  double worst = 0;
  for (int i = -100000; i <= 100000; ++i) {
    float x = float(i) / 100000;
    double exact = std::acos(double(x));
    worst = std::fmax(worst, std::fabs(polyAcos(x) - exact) / ulp(M_PI));
  }
  EXPECT_LE(worst, 4.0) << "max error " << worst << " ulps of pi";
  EXPECT_EQ(polyAcos(1.0f), 0.0f);
  EXPECT_EQ(polyAcos(2.0f), 0.0f); // clamped, as the renderer's normals may overshoot
  EXPECT_NEAR(polyAcos(-1.0f), float(M_PI), 1e-6f);
}
