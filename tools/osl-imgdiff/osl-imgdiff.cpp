//===- osl-imgdiff.cpp - Are two images within a threshold? ---------------===//
//
//   osl-imgdiff [--fail T] A B
//
// Exit status 0: both images read, with the same size and channels, and
// every value of B within T of A's, all finite: what idiff and `oiiotool --diff` pass with any failpercent, and
// hardfail and warn thresholds of at least T. Status 1: they differ (the
// largest difference is printed); 2: it cannot tell (a file it cannot
// read natively, a non-finite value). The judges run idiff when
// the status is not 0, so its verdict and message stay the reference's.
//
//===----------------------------------------------------------------------===//
#include "OslRuntime/ImageOutput.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

namespace {

int usage() {
  std::fprintf(stderr, "usage: osl-imgdiff [--fail THRESHOLD] A B\n");
  return 2;
}

} // namespace

int main(int argc, char **argv) {
  double threshold = 0;
  const char *paths[2] = {nullptr, nullptr};
  int npaths = 0;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--fail") == 0 && i + 1 < argc) {
      char *end = nullptr;
      threshold = std::strtod(argv[++i], &end);
      if (*end || !(threshold >= 0)) {
        std::fprintf(stderr, "osl-imgdiff: error: bad threshold '%s'\n", argv[i]);
        return 2;
      }
    } else if (argv[i][0] == '-' || npaths == 2) {
      return usage();
    } else {
      paths[npaths++] = argv[i];
    }
  }
  if (npaths != 2)
    return usage();
  osl::ImageData a, b;
  std::string error;
  // Only what it reads without OpenImageIO (and so quickly); idiff judges
  // the rest (other formats, several subimages, ...).
  for (int i = 0; i < 2; ++i)
    if (!osl::readImageNatively(paths[i], i == 0 ? a : b, error)) {
      std::fprintf(stderr, "osl-imgdiff: %s\n",
                   error.empty() ? (std::string(paths[i]) + ": left to idiff").c_str()
                                 : error.c_str());
      return 2;
    }
  if (a.xres != b.xres || a.yres != b.yres || a.channels != b.channels ||
      a.channelNames != b.channelNames) {
    std::printf("different shapes: %dx%d (%d channels) and %dx%d (%d channels)\n", a.xres,
                a.yres, a.channels, b.xres, b.yres, b.channels);
    return 1;
  }
  double worst = 0;
  size_t worstAt = 0, over = 0;
  for (size_t i = 0; i < a.pixels.size(); ++i) {
    float x = a.pixels[i], y = b.pixels[i];
    // How idiff counts infinities and NaNs is its own business.
    if (!std::isfinite(x) || !std::isfinite(y))
      return 2;
    double d = std::fabs(double(x) - double(y));
    if (d > threshold)
      ++over;
    if (d > worst)
      worst = d, worstAt = i;
  }
  if (over == 0) {
    std::printf("match: largest difference %g (threshold %g)\n", worst, threshold);
    return 0;
  }
  size_t pixel = worstAt / size_t(a.channels);
  std::printf("%zu values over %g; largest difference %g at (%zu, %zu) channel %s\n", over,
              threshold, worst, pixel % size_t(a.xres), pixel / size_t(a.xres),
              a.channelNames[worstAt % size_t(a.channels)].c_str());
  return 1;
}
