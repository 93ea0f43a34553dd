//===- Renderer.h - A batched path tracer for OSL closures ------*- C++ -*-===//
//
// osl-run --scene: path traces a testrender scene, along testrender's own
// paths (its sampler, camera, geometry, lobes, mixture, background table and
// ray differentials), so that its images match testrender's pixel for
// pixel. Paths advance in waves: every path of a tile's wave is traced to
// its next hit (rays intersected W at a time, one SIMD lane each:
// Geometry.h's intersectBatch), the hits are grouped by shader and shaded in
// full batches of W lanes (so SIMD lanes stay busy however the paths
// scatter), then each path draws one sampler point and with it samples the
// background table, every light (multiple importance sampling with the
// BSDF; the bounce's shadow rays are intersected together) and its BSDF.
// Light and background shaders are batched the same way. Random numbers
// depend only on (pixel, sample, bounce), and a pixel's samples are mixed
// in in order, so an image is the same at every width and thread count.
//
//===----------------------------------------------------------------------===//
#ifndef OSLRENDER_RENDERER_H
#define OSLRENDER_RENDERER_H

#include "OslCompiler/ShaderCompiler.h"
#include "OslRender/Scene.h"

#include <memory>
#include <string>
#include <vector>

namespace osl::render {

struct RenderOptions {
  int xres = 256, yres = 256;
  /// aa x aa paths per pixel.
  int aa = 1;
  int threads = 0; // 0: all cores
  uint32_t seed = 0;
  /// Longest path (bounces; the last one adds emission only, as
  /// testrender's max_bounces, whose default this is); Russian roulette
  /// ends most paths far earlier.
  int maxBounces = 1000000;
  bool progress = true;
  /// Time the kernel calls (RenderStats::shadingSeconds); two clock reads
  /// per batch.
  bool timeShading = false;
  /// The window rendered (osl-run --crop): [cropX0, cropX1) x [cropY0,
  /// cropY1), -1 ending at the image's edge. The image holds the window's
  /// pixels, each as in the whole image (its paths are seeded by pixel and
  /// summed in sample order), so windows assemble into it bit for bit.
  int cropX0 = 0, cropY0 = 0, cropX1 = -1, cropY1 = -1;
  int windowWidth() const { return (cropX1 < 0 ? xres : cropX1) - cropX0; }
  int windowHeight() const { return (cropY1 < 0 ? yres : cropY1) - cropY0; }
  /// Where the image's pixel `pixel` (y * xres + x) is in the window.
  size_t windowIndex(int pixel) const {
    return size_t(pixel / xres - cropY0) * size_t(windowWidth()) +
           size_t(pixel % xres - cropX0);
  }
};

struct RenderStats {
  long paths = 0;
  long shadedPoints = 0;  // surface, light and background shader runs
  long batches = 0;
  double activeLaneFraction = 0; // shaded points / (batches x width)
  double seconds = 0;            // the render loop, shaders compiled already
  double shadingSeconds = 0;     // in compiled kernels (summed over threads), if timed
};

class Renderer {
public:
  Renderer(const Scene &scene, const RenderOptions &options) : scene(scene), options(options) {}

  /// Compiles every shader instance of the scene (NAME.osl, searched in
  /// `searchPaths` in order) with `compile` (its width and options) plus
  /// the instance's parameter values. Diagnostics go to `errs`.
  bool compileShaders(const std::vector<std::string> &searchPaths, const CompileOptions &compile,
                      llvm::raw_ostream &errs, Stats *stats = nullptr);

  /// Renders into `rgb` (xres*yres*3 floats, row-major from the top).
  void render(std::vector<float> &rgb, RenderStats &stats);

  int width() const { return laneWidth; }

private:
  const Scene &scene;
  RenderOptions options;
  int laneWidth = 0;
  /// Per shader instance: its kernel and the row of its Ci output.
  struct Kernel {
    std::unique_ptr<CompiledShader> shader;
    int ciRow = -1;
    int outputRows = 0;
  };
  std::vector<Kernel> kernels;
  friend class PathWave;
};

} // namespace osl::render

#endif // OSLRENDER_RENDERER_H
