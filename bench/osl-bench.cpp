//===- osl-bench.cpp - ns per shading point and JIT time ------------------===//
//
// For each shader: source-to-callable compile time (median of several
// compiles) and single-thread shading time per point at widths 1, 4, 8,
// 16, with the speedup of each width over width 1 measured in the same
// run. Not a test: timings depend on the machine.
//
//   osl-bench [-g X Y] [--iters N] [--compiles N] SHADER.osl...
//
//===----------------------------------------------------------------------===//
#include "OslRuntime/Jit.h"
#include "OslCompiler/ShaderCompiler.h"
#include "OslRuntime/ThreadPool.h"

#include "llvm/Support/Format.h"
#include "llvm/Support/MemoryBuffer.h"
#include "llvm/Support/raw_ostream.h"

#include <algorithm>
#include <chrono>
#include <filesystem>

using namespace osl;

namespace {

double seconds(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since)
      .count();
}

struct Measurement {
  double compileMs = 0;
  double nsPerPoint = 0;
};

bool measure(const std::string &path, llvm::StringRef source, int width,
             int xres, int yres, int iters, int compiles, Measurement &m) {
  std::vector<double> times;
  std::unique_ptr<CompiledShader> shader;
  for (int i = 0; i < compiles; ++i) {
    CompileOptions options;
    options.width = width;
    auto start = std::chrono::steady_clock::now();
    ShaderCompiler compiler(options, llvm::errs());
    shader = compiler.compile(source, path);
    times.push_back(seconds(start) * 1e3);
    if (!shader)
      return false;
  }
  std::sort(times.begin(), times.end());
  m.compileMs = times[times.size() / 2];
  GridOptions grid;
  grid.xres = xres;
  grid.yres = yres;
  ThreadPool pool(1);
  // One untimed pass warms caches and pages in the outputs.
  shadeGrid(shader->kernel, width, shader->outputs, grid, pool);
  double total = 0;
  for (int i = 0; i < iters; ++i)
    total += shadeGrid(shader->kernel, width, shader->outputs, grid, pool).seconds;
  m.nsPerPoint = total * 1e9 / (double(xres) * yres * iters);
  return true;
}

} // namespace

int main(int argc, char **argv) {
  // Kernels compile faster without it (Jit.h).
  osl::Jit::disableMachineScheduler();
  int xres = 512, yres = 512, iters = 5, compiles = 5;
  std::vector<std::string> shaders;
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    if (a == "-g" && i + 2 < argc) {
      xres = std::atoi(argv[++i]);
      yres = std::atoi(argv[++i]);
    } else if (a == "--iters" && i + 1 < argc) {
      iters = std::atoi(argv[++i]);
    } else if (a == "--compiles" && i + 1 < argc) {
      compiles = std::atoi(argv[++i]);
    } else if (!a.empty() && a[0] != '-') {
      shaders.push_back(a);
    } else {
      llvm::errs() << "usage: osl-bench [-g X Y] [--iters N] [--compiles N] SHADER.osl...\n";
      return 2;
    }
  }
  if (shaders.empty() || xres < 1 || yres < 1 || iters < 1 || compiles < 1) {
    llvm::errs() << "usage: osl-bench [-g X Y] [--iters N] [--compiles N] SHADER.osl...\n";
    return 2;
  }
  llvm::outs() << "grid " << xres << "x" << yres << ", 1 thread, " << iters
               << " iterations; JIT = source to callable, median of " << compiles
               << "\n\n";
  llvm::outs() << llvm::format("%-28s %5s %12s %10s %9s\n", (const char *)"shader",
                               (const char *)"width", (const char *)"ns/point",
                               (const char *)"speedup", (const char *)"JIT ms");
  int failures = 0;
  for (const std::string &path : shaders) {
    auto buffer = llvm::MemoryBuffer::getFile(path);
    if (!buffer) {
      llvm::errs() << "cannot read " << path << "\n";
      ++failures;
      continue;
    }
    std::filesystem::path p(path);
    std::string name = p.parent_path().filename().string() + "/" + p.stem().string();
    double scalarNs = 0;
    for (int width : {1, 4, 8, 16}) {
      Measurement m;
      if (!measure(path, (*buffer)->getBuffer(), width, xres, yres, iters, compiles, m)) {
        ++failures;
        break;
      }
      if (width == 1)
        scalarNs = m.nsPerPoint;
      llvm::outs() << llvm::format("%-28s %5d %12.2f %9.2fx %9.1f\n", name.c_str(),
                                   width, m.nsPerPoint, scalarNs / m.nsPerPoint,
                                   m.compileMs);
    }
  }
  return failures ? 1 : 0;
}
