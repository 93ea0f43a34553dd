//===- Grid.h - testshade-style grid shading with a batch kernel -*- C++ -*-===//
//
// Runs a compiled batch kernel (see GlobalsLayout.h) over an xres x yres grid
// the way OSL's testshade sets up its shading points, so output images can
// be compared with OSL's reference images pixel for pixel.
//
//===----------------------------------------------------------------------===//
#ifndef OSLRUNTIME_GRID_H
#define OSLRUNTIME_GRID_H

#include "OslAbi/GlobalsLayout.h"
#include "OslRuntime/PrintCall.h"

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace osl {

class ThreadPool;

/// testshade's grid options (-g, --center, -t, --vary_*dxdy, --scaleuv,
/// --offsetuv).
struct GridOptions {
  int xres = 1, yres = 1;
  /// --center: shading points at pixel centres, u = (x+0.5)/xres.
  bool center = false;
  /// Participating threads; 0 = all hardware threads. Ignored when a
  /// ThreadPool is passed to shadeGrid.
  int threads = 0;
  /// Batches per tile, the unit of work handed to a thread; 0 picks a size
  /// that gives every thread several tiles. Never changes results.
  int tileBatches = 0;
  /// testshade's --vary_udxdy: Dx(u) = 1-u, Dy(u) = u.
  bool varyUdxdy = false;
  /// --vary_vdxdy: Dx(v) = 1-v, Dy(v) = v.
  bool varyVdxdy = false;
  /// --vary_pdxdy: Dx(P) = (1-u, 1-v, u/2), Dy(P) = (1-v, 1-u, v/2).
  bool varyPdxdy = false;
  /// testshade's --scaleuv / --offsetuv (u = uscale * u0 + uoffset).
  float uscale = 1.0f, vscale = 1.0f, uoffset = 0.0f, voffset = 0.0f;
  /// Progress bar on stderr, shown only if stderr is a terminal and the run
  /// lasts more than about a second.
  bool progress = false;
  /// Which outputs become images (by index; empty: all). The others are
  /// computed and dropped, taking no memory per point.
  std::vector<bool> keepImages;
  /// The band of rows shaded: [rowBegin, rowEnd), rowEnd < 0 meaning yres.
  /// Images then hold the band's rows only, and each point is shaded as in
  /// the whole grid, so bands written one after another (osl-run streams
  /// images larger than its memory budget this way) equal the whole image.
  int rowBegin = 0, rowEnd = -1;
  /// The columns shaded: [colBegin, colEnd), colEnd < 0 meaning xres. With
  /// rows, a crop window (osl-run --crop): images hold the window's pixels,
  /// each shaded as in the whole grid, so windows assemble into the whole
  /// image bit for bit.
  int colBegin = 0, colEnd = -1;
};

/// One shader output as laid out in the kernel's output rows.
struct OutputSpec {
  std::string name;
  int channels;
  /// A closure (Ci): its one row holds closure handles (OslRuntime/Closure.h)
  /// as float bits, not an image.
  bool closure = false;
  /// An int output: its rows (and images) hold the ints' bits as floats,
  /// read with intOutputValue (a float holds ints exactly only to 2^24).
  bool integer = false;
};

/// An int output's value from a float of its rows or images.
inline int32_t intOutputValue(float bits) {
  int32_t value;
  std::memcpy(&value, &bits, sizeof value);
  return value;
}

/// A whole number held as a float, as the int it holds (x86's conversion:
/// NaN and values out of int range give INT_MIN).
inline int32_t wholeNumber(float value) {
  if (!(value >= -2147483648.0f && value < 2147483648.0f))
    return INT32_MIN;
  return int32_t(value);
}

/// An int as an int output's rows hold it (its bits).
inline float intOutputBits(int32_t value) {
  float bits;
  std::memcpy(&bits, &value, sizeof bits);
  return bits;
}

struct ShadeResult {
  /// Per output: xres*rows*channels floats for the band of rows shaded
  /// (all yres by default), pixel-major (row-major pixels, channels
  /// interleaved), ready for writeImage.
  std::vector<std::vector<float>> images;
  /// Wall time of the shading loop (buffers and tables set up excluded).
  double seconds = 0;
  /// What the shader printed (printf, warning, error...), in point order;
  /// the caller emits it (emitPrints) where its output wants it.
  PrintLog printed;
};

/// Shades every grid point with `kernel` compiled for `width` lanes.
/// Pixels are taken in row-major order in batches of `width` consecutive
/// pixels (a batch may span rows; the last one may be partial). Each pixel's
/// values depend only on its own globals, so results are identical for any
/// thread count or tile size.
ShadeResult shadeGrid(BatchKernel kernel, int width,
                      const std::vector<OutputSpec> &outputs,
                      const GridOptions &options);

/// As above on an existing pool (options.threads is ignored), so repeated
/// runs do not start threads each time.
ShadeResult shadeGrid(BatchKernel kernel, int width,
                      const std::vector<OutputSpec> &outputs,
                      const GridOptions &options, ThreadPool &pool);

/// As above into `result`, whose images are reused when they already have
/// the right sizes: repeated passes (--iters) allocate and page in their
/// images once.
void shadeGridInto(ShadeResult &result, BatchKernel kernel, int width,
                   const std::vector<OutputSpec> &outputs, const GridOptions &options,
                   ThreadPool &pool);

/// Fills one batch of globals (kGlobalRows x width floats) for the pixels
/// [firstPixel, firstPixel + nactive) in row-major order. Lanes past
/// nactive repeat the last active pixel, so code that computes on every
/// lane sees ordinary values. Exposed for tests and for tools that drive a
/// kernel themselves; shadeGrid uses a faster equivalent.
void fillGlobals(float *globals, int width, long firstPixel, int nactive,
                 const GridOptions &options);

} // namespace osl

#endif // OSLRUNTIME_GRID_H
