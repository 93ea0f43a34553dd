//===- Grid.cpp - testshade-style grid shading with a batch kernel ---------===//
//
// The globals follow OSL testshade's setup_shaderglobals, including its
// float evaluation order, so u, v and P match OSL's bit for bit.
//
//===----------------------------------------------------------------------===//

#include "OslRuntime/Grid.h"
#include "OslRuntime/Closure.h"
#include "OslRuntime/PointCloud.h"
#include "OslRuntime/PrintCall.h"
#include "OslRuntime/Progress.h"
#include "OslRuntime/ThreadPool.h"

#include <algorithm>
#include <limits>
#include <atomic>
#include <cassert>
#include <chrono>
#include <cstdio>
#include <immintrin.h>
#include <map>
#include <memory>
#include <mutex>
#include <new>
#include <string_view>
#include <unistd.h>

// testshade computes uscale * t + uoffset without contraction; an FMA here
// (e.g. when built with -march=native) could move u by one ulp.
#pragma STDC FP_CONTRACT OFF

namespace osl {

namespace {

constexpr int rowOf(std::string_view name) {
  for (const GlobalSlot &s : kGlobalSlots)
    if (s.name == name)
      return s.row;
  return -1;
}

constexpr int kP = rowOf("P"), kN = rowOf("N"), kNg = rowOf("Ng"),
              kdPdu = rowOf("dPdu"), kdPdv = rowOf("dPdv"),
              kdPdx = rowOf("dPdx"), kdPdy = rowOf("dPdy"), kU = rowOf("u"),
              kV = rowOf("v"), kdudx = rowOf("dudx"), kdudy = rowOf("dudy"),
              kdvdx = rowOf("dvdx"), kdvdy = rowOf("dvdy"),
              kSurfaceArea = rowOf("surfacearea");
static_assert(kP >= 0 && kN >= 0 && kNg >= 0 && kdPdu >= 0 && kdPdv >= 0 &&
                  kdPdx >= 0 && kdPdy >= 0 && kU >= 0 && kV >= 0 &&
                  kdudx >= 0 && kdudy >= 0 && kdvdx >= 0 && kdvdy >= 0 &&
                  kSurfaceArea >= 0,
              "GlobalsLayout.h lost a global the grid fills");

/// Writes batches of globals. Everything that does not depend on the pixel
/// is written once per buffer; per batch only u, v, P.xy (and the
/// derivatives that --vary_* make per-pixel) are rewritten, from per-column
/// and per-row tables, so setting up a batch costs a few stores per lane.
class GlobalsWriter {
public:
  /// Batches cover the window of `cols` columns from `colBegin` and the rows
  /// from `rowBegin`, its pixels counted row-major from 0.
  GlobalsWriter(const GridOptions &o, int width, int colBegin, int cols, int rowBegin)
      : opt(o), width(width), colBegin(colBegin), cols(cols), rowBegin(rowBegin) {
    us.resize(std::max(o.xres, 0));
    vs.resize(std::max(o.yres, 0));
    for (int x = 0; x < o.xres; ++x)
      us[x] = coord(x, o.xres, o.uscale, o.uoffset);
    for (int y = 0; y < o.yres; ++y)
      vs[y] = coord(y, o.yres, o.vscale, o.voffset);
    dudx = o.center ? o.uscale / o.xres : o.uscale / std::max(1, o.xres - 1);
    dvdy = o.center ? o.vscale / o.yres : o.vscale / std::max(1, o.yres - 1);
    // testshade uses the Reyes-grid spacing for dPdx/dPdy even with
    // --center (unlike dudx/dvdy); the references encode that.
    dPdxX = o.uscale / std::max(1, o.xres - 1);
    dPdyY = o.vscale / std::max(1, o.yres - 1);
  }

  void writeConstantRows(float *g) const {
    std::fill(g, g + kGlobalRows * width, 0.0f); // I, dPdz, time, ... = 0
    setRow(g, kP + 2, 1.0f);
    setRow(g, kN + 2, 1.0f);
    setRow(g, kNg + 2, 1.0f);
    setRow(g, kdPdu + 0, 1.0f);
    setRow(g, kdPdv + 1, 1.0f);
    setRow(g, kSurfaceArea, 1.0f);
    if (!opt.varyPdxdy) {
      setRow(g, kdPdx + 0, dPdxX);
      setRow(g, kdPdy + 1, dPdyY);
    }
    if (!opt.varyUdxdy)
      setRow(g, kdudx, dudx);
    if (!opt.varyVdxdy)
      setRow(g, kdvdy, dvdy);
  }

  /// A pixel of the window by its column and row in the grid.
  struct Pixel {
    int x, y;
  };
  /// The window's pixel `index` (counted row-major in the window).
  Pixel pixel(long index) const {
    return {colBegin + static_cast<int>(index % cols), rowBegin + static_cast<int>(index / cols)};
  }
  /// The pixel n further on: a batch's first pixel from the last batch's
  /// without a 64-bit division per batch.
  Pixel advance(Pixel p, int n) const {
    for (p.x += n; p.x >= colBegin + cols; p.x -= cols)
      ++p.y;
    return p;
  }

  /// Pixel rows for the window's pixels [first, first+nactive); lanes past
  /// nactive repeat the last active pixel.
  void writeBatch(float *g, long first, int nactive) const {
    writeBatch(g, pixel(first), nactive);
  }
  void writeBatch(float *g, Pixel first, int nactive) const {
    auto [x, y] = first;
    int xEnd = colBegin + cols;
    if (x + nactive <= xEnd && !opt.varyUdxdy && !opt.varyVdxdy && !opt.varyPdxdy) {
      // The common case, a batch within one row: four plain row copies the
      // host compiler vectorizes (this runs once per batch, beside the
      // kernel).
      float *u = &at(g, kU, 0);
      copyRowLanes(u, &us[x], nactive);
      std::fill(u + nactive, u + width, us[x + nactive - 1]);
      copyRowLanes(&at(g, kP + 0, 0), u, width);
      setRow(g, kV, vs[y]);
      setRow(g, kP + 1, vs[y]);
      return;
    }
    for (int lane = 0; lane < width; ++lane) {
      float u = us[x], v = vs[y];
      at(g, kU, lane) = u;
      at(g, kV, lane) = v;
      at(g, kP + 0, lane) = u;
      at(g, kP + 1, lane) = v;
      if (opt.varyUdxdy) {
        at(g, kdudx, lane) = 1.0f - u;
        at(g, kdudy, lane) = u;
      }
      if (opt.varyVdxdy) {
        at(g, kdvdx, lane) = 1.0f - v;
        at(g, kdvdy, lane) = v;
      }
      if (opt.varyPdxdy) {
        // testshade multiplies by the double 0.5; same value as 0.5f.
        at(g, kdPdx + 0, lane) = 1.0f - u;
        at(g, kdPdx + 1, lane) = 1.0f - v;
        at(g, kdPdx + 2, lane) = static_cast<float>(u * 0.5);
        at(g, kdPdy + 0, lane) = 1.0f - v;
        at(g, kdPdy + 1, lane) = 1.0f - u;
        at(g, kdPdy + 2, lane) = static_cast<float>(v * 0.5);
      }
      if (lane + 1 < nactive && ++x == xEnd) {
        x = colBegin;
        ++y;
      }
    }
  }

private:
  // testshade: uscale * (x + 0.5f) / xres + uoffset with --center, else
  // uscale * (x / (xres - 1), or 0.5 for a single column) + uoffset.
  float coord(int i, int res, float scale, float offset) const {
    if (opt.center)
      return scale * (float)(i + 0.5f) / res + offset;
    return scale * ((res == 1) ? 0.5f : (float)i / (res - 1)) + offset;
  }
  float &at(float *g, int row, int lane) const { return g[row * width + lane]; }
  void setRow(float *g, int row, float value) const {
    std::fill(g + row * width, g + (row + 1) * width, value);
  }

  GridOptions opt;
  int width, colBegin, cols, rowBegin;
  std::vector<float> us, vs;
  float dudx, dvdy, dPdxX, dPdyY;
};

/// Floats on their own 64-byte lines: vector loads of a row stay aligned
/// and two threads' buffers never share a cache line.
struct AlignedFloats {
  struct Free {
    void operator()(float *p) const { ::operator delete[](p, std::align_val_t(64)); }
  };
  std::unique_ptr<float[], Free> data;
  explicit AlignedFloats(size_t n) {
    size_t bytes = (n * sizeof(float) + 63) / 64 * 64;
    data.reset(static_cast<float *>(
        ::operator new[](bytes ? bytes : 64, std::align_val_t(64))));
  }
  float *get() const { return data.get(); }
};

/// Four lanes of three rows as four pixels of three channels: six unpacks
/// and three shuffles (x86-64's baseline SSE) instead of twelve scalar
/// moves, which the host compiler does not find on its own.
inline void interleave3x4(float *out, const float *r, const float *g, const float *b) {
  __m128 x = _mm_loadu_ps(r), y = _mm_loadu_ps(g), z = _mm_loadu_ps(b);
  __m128 xyLo = _mm_unpacklo_ps(x, y), xyHi = _mm_unpackhi_ps(x, y); // x0 y0 x1 y1, x2 y2 x3 y3
  __m128 zxLo = _mm_unpacklo_ps(z, x), zxHi = _mm_unpackhi_ps(z, x); // z0 x0 z1 x1, z2 x2 z3 x3
  __m128 yzLo = _mm_unpacklo_ps(y, z), yzHi = _mm_unpackhi_ps(y, z); // y0 z0 y1 z1, y2 z2 y3 z3
  _mm_storeu_ps(out + 0, _mm_shuffle_ps(xyLo, zxLo, _MM_SHUFFLE(3, 0, 1, 0))); // x0 y0 z0 x1
  _mm_storeu_ps(out + 4, _mm_shuffle_ps(yzLo, xyHi, _MM_SHUFFLE(1, 0, 3, 2))); // y1 z1 x2 y2
  _mm_storeu_ps(out + 8, _mm_shuffle_ps(zxHi, yzHi, _MM_SHUFFLE(3, 2, 3, 0))); // z2 x3 y3 z3
}

/// Pixel-major image values from the kernel's channel rows: pixel `lane`
/// gets rows[c * width + lane] as channel c. Runs once per output per
/// batch: colours go four lanes at a time.
void interleaveRows(float *image, const float *rows, int channels, int width, int nactive) {
  if (channels == 1) {
    copyRowLanes(image, rows, nactive);
    return;
  }
  if (channels == 3) {
    const float *r0 = rows, *r1 = rows + width, *r2 = rows + 2 * width;
    int lane = 0;
    for (; lane + 4 <= nactive; lane += 4)
      interleave3x4(image + 3 * lane, r0 + lane, r1 + lane, r2 + lane);
    for (; lane < nactive; ++lane) {
      image[3 * lane + 0] = r0[lane];
      image[3 * lane + 1] = r1[lane];
      image[3 * lane + 2] = r2[lane];
    }
    return;
  }
  for (int c = 0; c < channels; ++c)
    for (int lane = 0; lane < nactive; ++lane)
      image[lane * channels + c] = rows[c * width + lane];
}

int chooseTileBatches(const GridOptions &opt, long nbatches, int width,
                      int threads) {
  // Tiles are counted in an int: a huge grid takes bigger tiles.
  long atLeast = nbatches / std::numeric_limits<int>::max() + 1;
  if (opt.tileBatches > 0)
    return static_cast<int>(std::max<long>(opt.tileBatches, atLeast));
  // ~4096 pixels per tile keeps hand-out overhead negligible; small grids
  // get smaller tiles so every thread has a few to balance the load.
  long byPixels = std::max(1, 4096 / width);
  long bySplit = (nbatches + 4L * threads - 1) / (4L * threads);
  return static_cast<int>(std::max(atLeast, std::min(byPixels, bySplit)));
}

} // namespace

void fillGlobals(float *globals, int width, long firstPixel, int nactive,
                 const GridOptions &options) {
  GlobalsWriter writer(options, width, 0, std::max(options.xres, 1), 0);
  writer.writeConstantRows(globals);
  writer.writeBatch(globals, firstPixel, nactive);
}

ShadeResult shadeGrid(BatchKernel kernel, int width,
                      const std::vector<OutputSpec> &outputs,
                      const GridOptions &options) {
  ThreadPool pool(options.threads);
  return shadeGrid(kernel, width, outputs, options, pool);
}

ShadeResult shadeGrid(BatchKernel kernel, int width,
                      const std::vector<OutputSpec> &outputs,
                      const GridOptions &opt, ThreadPool &pool) {
  ShadeResult result;
  shadeGridInto(result, kernel, width, outputs, opt, pool);
  return result;
}

void shadeGridInto(ShadeResult &result, BatchKernel kernel, int width,
                   const std::vector<OutputSpec> &outputs, const GridOptions &opt,
                   ThreadPool &pool) {
  assert(kernel && width > 0 && "shadeGrid needs a kernel and a width");
  result.seconds = 0;
  int rowEnd = opt.rowEnd < 0 ? opt.yres : std::min(opt.rowEnd, opt.yres);
  int rowBegin = std::clamp(opt.rowBegin, 0, std::max(rowEnd, 0));
  int colEnd = opt.colEnd < 0 ? opt.xres : std::min(opt.colEnd, opt.xres);
  int colBegin = std::clamp(opt.colBegin, 0, std::max(colEnd, 0));
  int cols = std::max(colEnd - colBegin, 0);
  // Pixel indices below count row-major in the window.
  long npixels = static_cast<long>(cols) * static_cast<long>(std::max(rowEnd - rowBegin, 0));
  int totalChannels = 0;
  std::vector<int> firstRow;
  result.images.resize(outputs.size());
  for (size_t o = 0; o < outputs.size(); ++o) {
    firstRow.push_back(totalChannels);
    totalChannels += outputs[o].channels;
    // Every pixel is written below, so a buffer of the right size is
    // reused as it is. An output nobody reads takes no memory.
    bool kept = opt.keepImages.empty() || opt.keepImages[o];
    size_t size = kept ? static_cast<size_t>(npixels) * outputs[o].channels : 0;
    if (result.images[o].size() != size)
      result.images[o].assign(size, 0.0f);
  }
  if (npixels == 0 || !kernel || width <= 0)
    return;

  GlobalsWriter writer(opt, width, colBegin, cols, rowBegin);
  long nbatches = (npixels + width - 1) / width;
  int tileBatches = chooseTileBatches(opt, nbatches, width, pool.size());
  long ntiles = (nbatches + tileBatches - 1) / tileBatches;

  // Two globals and two outputs buffers per thread, reused for every
  // batch. A batch's globals are written before the batch ahead of it runs,
  // and its outputs are copied into the images after the batch behind it
  // ran: a load right after the stores it reads waits for them to reach
  // the cache, and doing so at every kernel entry and exit cost the marble
  // about 10% at width 16 (measured). One batch apart, they are long there.
  std::vector<AlignedFloats> globals, outRows;
  for (int w = 0; w < 2 * pool.size(); ++w) {
    globals.emplace_back(static_cast<size_t>(kGlobalRows) * width);
    writer.writeConstantRows(globals.back().get());
    outRows.emplace_back(static_cast<size_t>(totalChannels) * width);
  }

  // What batches print, put in batch order once all have run, so the
  // text is in point order whatever the threads did.
  std::mutex printedMutex;
  std::map<long, PrintLog> printed;
  // Most batches print nothing: a log is made only for one that did.
  auto takePrints = [&](long b) {
    if (!batchPrinted())
      return;
    PrintLog log;
    takeBatchPrints(log);
    std::lock_guard<std::mutex> lock(printedMutex);
    printed.emplace(b, std::move(log));
  };

  Progress progress(opt.progress, npixels, "shading");
  auto start = std::chrono::steady_clock::now();
  pool.parallelForWithWorker(static_cast<int>(ntiles), [&](int tile,
                                                           int worker) {
    auto globalsOf = [&](long b) { return globals[2 * worker + (b & 1)].get(); };
    auto outputsOf = [&](long b) { return outRows[2 * worker + (b & 1)].get(); };
    auto activeIn = [&](long b) {
      return static_cast<int>(std::min<long>(width, npixels - b * width));
    };
    auto copyOutputs = [&](long b) {
      for (size_t o = 0; o < outputs.size(); ++o) {
        if (result.images[o].empty())
          continue; // discarded
        int channels = outputs[o].channels;
        interleaveRows(result.images[o].data() + b * width * channels,
                       outputsOf(b) + static_cast<size_t>(firstRow[o]) * width, channels,
                       width, activeIn(b));
      }
    };
    // Per batch, the harness costs as much as a small shader: the thread's
    // arena is looked up once per tile.
    ClosureArena &arena = threadClosureArena();
    long firstBatch = static_cast<long>(tile) * tileBatches;
    long endBatch = std::min(nbatches, firstBatch + tileBatches);
    auto next = writer.pixel(firstBatch * width); // the last written batch's first pixel
    writer.writeBatch(globalsOf(firstBatch), next, activeIn(firstBatch));
    for (long b = firstBatch; b < endBatch; ++b) {
      if (b + 1 < endBatch) {
        next = writer.advance(next, width);
        writer.writeBatch(globalsOf(b + 1), next, activeIn(b + 1));
      }
      // A lane the kernel leaves unwritten must read 0, not whatever this
      // thread's previous batch left: that would depend on the schedule.
      float *out = outputsOf(b);
      std::fill(out, out + static_cast<size_t>(totalChannels) * width, 0.0f);
      // Closures a batch builds (Ci) are not images: drop them per batch.
      arena.reset();
      // (A band's points follow the rows above it.)
      setPointCloudBatch(long(rowBegin) * long(cols) + b * width);
      kernel(globalsOf(b), out, activeIn(b));
      takePrints(b);
      if (b > firstBatch)
        copyOutputs(b - 1);
    }
    copyOutputs(endBatch - 1);
    progress.add((std::min(npixels, endBatch * width)) - firstBatch * width);
  });
  result.seconds = std::chrono::duration<double>(
                       std::chrono::steady_clock::now() - start)
                       .count();
  progress.finish();
  result.printed.texts.clear();
  for (auto &[batch, log] : printed)
    for (PrintedText &t : log.texts)
      result.printed.texts.push_back(std::move(t));
}

} // namespace osl
