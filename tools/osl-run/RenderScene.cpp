//===- RenderScene.cpp - osl-run --scene ----------------------------------===//
//
// testrender's command line on top of lib/Render: reads the scene, compiles
// each shader group for the chosen width, path traces and writes the image.
//
//===----------------------------------------------------------------------===//
#include "RunOptions.h"

#include "OslRender/Renderer.h"
#include "OslRuntime/ImageOutput.h"

#include "llvm/Support/Format.h"
#include "llvm/Support/Path.h"
#include "llvm/Support/raw_ostream.h"

using namespace osl;

int osl::renderScene(const RunOptions &options) {
  render::Scene scene;
  std::string error;
  if (!render::loadScene(options.scenePath, scene, error)) {
    llvm::errs() << "osl-run: error: " << error << "\n";
    return 1;
  }
  std::vector<std::string> dirs = options.shaderDirs;
  llvm::StringRef sceneDir = llvm::sys::path::parent_path(options.scenePath);
  std::string base = sceneDir.empty() ? "." : sceneDir.str();
  dirs.push_back(base);
  dirs.push_back(base + "/shaders");
  dirs.push_back(base + "/../shaders");
  dirs.push_back(".");

  render::RenderOptions ropt;
  ropt.xres = options.renderX;
  ropt.yres = options.renderY;
  ropt.aa = options.aa;
  ropt.threads = options.grid.threads;
  ropt.seed = uint32_t(options.seed);
  if (scene.maxBounces >= 0)
    ropt.maxBounces = scene.maxBounces;
  ropt.timeShading = options.timeKernels;
  if (options.cropGiven) {
    ropt.cropX0 = options.crop[0];
    ropt.cropY0 = options.crop[1];
    ropt.cropX1 = options.crop[2];
    ropt.cropY1 = options.crop[3];
  }

  Stats stats;
  bool printStats = options.stats || options.timeKernels;
  Stats *statsPtr = printStats ? &stats : nullptr;
  CompileOptions compile = options.compile;
  compile.camera = {ropt.xres, ropt.yres};
  render::Renderer renderer(scene, ropt);
  if (!renderer.compileShaders(dirs, compile, llvm::errs(), statsPtr))
    return 1;

  std::vector<float> rgb;
  render::RenderStats rstats;
  renderer.render(rgb, rstats);
  stats.add("rendering", rstats.seconds);
  {
    ScopedTimer timer(statsPtr, "write image");
    // Half floats unless -d says otherwise, as testrender writes them.
    std::string type = options.dataType.empty() ? "half" : options.dataType;
    if (!writeImage(options.sceneOutput, ropt.windowWidth(), ropt.windowHeight(), 3,
                    rgb.data(), error, type)) {
      llvm::errs() << "osl-run: error: cannot write '" << options.sceneOutput << "': " << error
                   << "\n";
      return 1;
    }
  }
  if (printStats) {
    llvm::errs() << "scene " << options.scenePath << ", " << ropt.xres << "x" << ropt.yres
                 << ", " << ropt.aa * ropt.aa << " paths per pixel, width "
                 << renderer.width() << "\n";
    stats.print(llvm::errs());
    llvm::errs() << llvm::format("paths: %ld, %.0f samples per second\n", rstats.paths,
                                 rstats.paths / std::max(1e-9, rstats.seconds))
                 << llvm::format("shaded points: %ld in %ld batches, %.1f%% of lanes active\n",
                                 rstats.shadedPoints, rstats.batches,
                                 100 * rstats.activeLaneFraction)
                 ;
    if (ropt.timeShading)
      llvm::errs() << llvm::format("in shading kernels: %.1f ms (%.1f ns per shaded point)\n",
                                   rstats.shadingSeconds * 1e3,
                                   rstats.shadingSeconds * 1e9 /
                                       std::max(1L, rstats.shadedPoints));
  }
  return statusAfterShading(options);
}
