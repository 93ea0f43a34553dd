//===- osl-texture-bench.cpp - Texture lookups: SIMD kernels vs per point --===//
//
// bench/shaders/texture_wrap.osl (a wrap mode chosen per point, so lookups
// are split into lane groups) at widths 1 and 16, one thread, and the same
// lookups made point by point straight into the texture system
// (osl_rt_texture with one lane), which is what the shader's lookups cost
// without any shading around them. Ratios are within one run. Run from the
// repository root. Not a test: timings depend on the machine.
//
//   osl-texture-bench [-g X Y] [--iters N]
//
//===----------------------------------------------------------------------===//
#include "OslCompiler/ShaderCompiler.h"
#include "OslAbi/EntryPoints.h"
#include "OslRuntime/TextureCall.h"
#include "OslRuntime/ThreadPool.h"

#include "llvm/Support/Format.h"
#include "llvm/Support/MemoryBuffer.h"
#include "llvm/Support/raw_ostream.h"

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <string>

using namespace osl;

namespace {

constexpr const char *kShader = "bench/shaders/texture_wrap.osl";
constexpr const char *kTexture = "conformance/texture/tex/ramp.tx";

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// ns per point of the compiled shader at `width`.
double shaderNsPerPoint(llvm::StringRef source, int width, int xres, int yres, int iters) {
  CompileOptions options;
  options.width = width;
  ShaderCompiler compiler(options, llvm::errs());
  std::unique_ptr<CompiledShader> shader = compiler.compile(source, kShader);
  if (!shader)
    std::exit(1);
  GridOptions grid;
  grid.xres = xres;
  grid.yres = yres;
  ThreadPool pool(1);
  shadeGrid(shader->kernel, width, shader->outputs, grid, pool); // warm the cache
  double total = 0;
  for (int i = 0; i < iters; ++i)
    total += shadeGrid(shader->kernel, width, shader->outputs, grid, pool).seconds;
  return total * 1e9 / (double(xres) * yres * iters);
}

/// One lookup of one point through the runtime entry the kernels use.
void lookUp(float s, float t, float dsdx, float dtdy, float blur, int wrap, float *rgb) {
  float rows[kTextureRows] = {};
  rows[kTextureCoordRow] = s;
  rows[kTextureCoordRow + 1] = t;
  rows[kTextureDerivRow] = dsdx;     // ds/dx
  rows[kTextureDerivRow + 3] = dtdy; // dt/dy
  rows[kTextureOptionRow + 0] = rows[kTextureOptionRow + 1] = blur;
  rows[kTextureOptionRow + 3] = rows[kTextureOptionRow + 4] = rows[kTextureOptionRow + 5] = 1;
  osl_rt_texture("bench", kTexture, "", 0, kTexture2D, 3, wrap, wrap, wrap,
                 textureInterpCode("smartcubic"), 0, rows, 1, 1u);
  for (int c = 0; c < 3; ++c)
    rgb[c] = rows[kTextureResultRow + c];
}

/// ns per point of the shader's two lookups made point by point.
double pointByPointNs(int xres, int yres, int iters) {
  const int wraps[4] = {textureWrapCode("black"), textureWrapCode("clamp"),
                        textureWrapCode("periodic"), textureWrapCode("mirror")};
  float du = 1.0f / float(xres - 1), dv = 1.0f / float(yres - 1);
  double checksum = 0;
  auto pass = [&] {
    for (int y = 0; y < yres; ++y)
      for (int x = 0; x < xres; ++x) {
        float u = float(x) * du, v = float(y) * dv;
        float s = u * 3.0f - 1.0f, t = v * 3.0f - 1.0f;
        int wrap = wraps[int(std::floor(u * 3.999f))];
        float a[3], b[3];
        lookUp(s, t, 3.0f * du, 3.0f * dv, 0.01f, wrap, a);
        lookUp(2.0f * t, 2.0f * s, 0, 0, 0, wrap, b);
        checksum += a[0] + 0.5f * b[0];
      }
  };
  pass();
  auto start = std::chrono::steady_clock::now();
  for (int i = 0; i < iters; ++i)
    pass();
  double ns = secondsSince(start) * 1e9 / (double(xres) * yres * iters);
  if (checksum == -1) // keep the work observable
    llvm::errs() << "";
  return ns;
}

} // namespace

int main(int argc, char **argv) {
  int xres = 512, yres = 512, iters = 5;
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    if (a == "-g" && i + 2 < argc) {
      xres = std::atoi(argv[++i]);
      yres = std::atoi(argv[++i]);
    } else if (a == "--iters" && i + 1 < argc) {
      iters = std::atoi(argv[++i]);
    } else {
      llvm::errs() << "usage: osl-texture-bench [-g X Y] [--iters N]\n";
      return 2;
    }
  }
  if (xres < 2 || yres < 2 || iters < 1) {
    llvm::errs() << "usage: osl-texture-bench [-g X Y] [--iters N]\n";
    return 2;
  }
  auto buffer = llvm::MemoryBuffer::getFile(kShader);
  if (!buffer) {
    llvm::errs() << "cannot read " << kShader << " (run from the repository root)\n";
    return 1;
  }
  double w1 = shaderNsPerPoint((*buffer)->getBuffer(), 1, xres, yres, iters);
  double w16 = shaderNsPerPoint((*buffer)->getBuffer(), 16, xres, yres, iters);
  double lanes = pointByPointNs(xres, yres, iters);
  llvm::outs() << "texture_wrap, grid " << xres << "x" << yres << ", 1 thread, " << iters
               << " iterations\n";
  llvm::outs() << llvm::format("  width 1:              %8.1f ns/point\n", w1);
  llvm::outs() << llvm::format("  width 16:             %8.1f ns/point (%.2fx width 1)\n", w16,
                               w1 / w16);
  llvm::outs() << llvm::format("  point-by-point calls: %8.1f ns/point (width 16 is %.2fx)\n",
                               lanes, lanes / w16);
  return 0;
}
