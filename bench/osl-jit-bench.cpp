//===- osl-jit-bench.cpp - OSL source to callable kernel, stage by stage --===//
//
// Compiles one shader N times in this process and prints the median time
// of each compile stage (front end, MLIR passes, LLVM, codegen) and of the
// whole source-to-callable path. Stage times are the compiling thread's CPU
// time, so other jobs on the machine do not inflate them; the wall-clock
// median of the whole path is printed beside it. Not a test.
//
//   osl-jit-bench [--compiles N] [--width W] SHADER.osl
//
//===----------------------------------------------------------------------===//
#include "OslRuntime/Jit.h"
#include "OslCompiler/ShaderCompiler.h"

#include "llvm/Support/Format.h"
#include "llvm/Support/MemoryBuffer.h"
#include "llvm/Support/raw_ostream.h"

#include <algorithm>
#include <map>

using namespace osl;

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0 : v[v.size() / 2];
}

constexpr const char *kUsage =
    "usage: osl-jit-bench [--compiles N] [--width W] SHADER.osl\n";

} // namespace

int main(int argc, char **argv) {
  // Kernels compile faster without it (Jit.h).
  osl::Jit::disableMachineScheduler();
  int compiles = 20, width = 0;
  std::string path;
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    if (a == "--compiles" && i + 1 < argc)
      compiles = std::atoi(argv[++i]);
    else if (a == "--width" && i + 1 < argc)
      width = std::atoi(argv[++i]);
    else if (!a.empty() && a[0] != '-' && path.empty())
      path = a;
    else {
      llvm::errs() << kUsage;
      return 2;
    }
  }
  if (path.empty() || compiles < 1) {
    llvm::errs() << kUsage;
    return 2;
  }
  auto buffer = llvm::MemoryBuffer::getFile(path);
  if (!buffer) {
    llvm::errs() << "osl-jit-bench: cannot read " << path << "\n";
    return 1;
  }

  std::vector<std::string> order;
  std::map<std::string, std::vector<double>> stageMs;
  std::vector<double> cpuMs, wallMs;
  int usedWidth = 0;
  // One untimed compile first: it pays for one-time setup (target
  // registration, the string table) that a renderer pays once per process.
  for (int i = -1; i < compiles; ++i) {
    CompileOptions options;
    options.width = width;
    Stats stats;
    stats.clock = Stats::Clock::ThreadCpu;
    double wallStart = Stats::now(Stats::Clock::Wall);
    ShaderCompiler compiler(options, llvm::errs(), &stats);
    std::unique_ptr<CompiledShader> shader =
        compiler.compile((*buffer)->getBuffer(), path);
    double wall = Stats::now(Stats::Clock::Wall) - wallStart;
    if (!shader)
      return 1;
    usedWidth = shader->width;
    if (i < 0)
      continue;
    double total = 0;
    for (const auto &[name, seconds] : stats.stages) {
      if (!stageMs.count(name))
        order.push_back(name);
      stageMs[name].push_back(seconds * 1e3);
      total += seconds;
    }
    cpuMs.push_back(total * 1e3);
    wallMs.push_back(wall * 1e3);
  }
  llvm::outs() << "JIT " << path << ", width " << usedWidth << ", median of "
               << compiles << " compiles (CPU time of the compiling thread)\n";
  for (const std::string &name : order)
    llvm::outs() << llvm::format("  %-16s %8.2f ms\n", name.c_str(), median(stageMs[name]));
  llvm::outs() << llvm::format("  %-16s %8.2f ms (wall %.2f ms)\n", (const char *)"source to kernel",
                               median(cpuMs), median(wallMs));
  return 0;
}
