//===- osl-difftest.cpp - SIMD kernels against the one-point reference ---===//
//
// For each shader given, compiles it in reference mode (one point at a
// time, ordinary branches, no masks; osl-run --interpret) and as batch
// kernels of width 1, 4, 8 and 16, shades the same small grid (its size
// makes the last batch partial), and requires every output to be
// bit-identical to the reference, except that any NaN matches any NaN
// there (scalar and vector instructions propagate different NaN payloads),
// and the widths to be bit-identical to each other, NaNs included. Shaders
// the compiler rejects are reported and make the exit status 1 (every
// input is meant to be valid OSL), after the rest have been compared.
//
//   osl-difftest [-g X Y] [--quiet] [--reference-only] FILE...
//
// --quiet leaves out the closing count (mismatches and rejections are
// still reported). --reference-only compiles and shades the reference alone: a quick way to
// find which of many generated shaders the compiler rejects, and why.
//
// Exits 1 at the first mismatch, naming the file, output, width and pixel,
// or after all files when any was rejected.
//
//===----------------------------------------------------------------------===//
#include "OslRuntime/Jit.h"
#include "OslCompiler/ShaderCompiler.h"
#include "OslRuntime/Grid.h"
#include "OslRuntime/ThreadPool.h"

#include "llvm/Support/MemoryBuffer.h"
#include "llvm/Support/raw_ostream.h"

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

using namespace osl;

namespace {

struct Run {
  std::vector<OutputSpec> outputs;
  std::vector<std::vector<float>> images;
};

/// Compiles and shades one shader; false (with the diagnostics in `errors`)
/// if it does not compile.
bool shade(llvm::StringRef source, llvm::StringRef path, int width, bool reference,
           const GridOptions &grid, ThreadPool &pool, Run &run, std::string &errors) {
  CompileOptions options;
  options.width = width;
  options.reference = reference;
  options.camera = {grid.xres, grid.yres};
  // Random programs are where a pass leaves invalid IR: catch it there.
  options.verifyEachPass = true;
  llvm::raw_string_ostream errs(errors);
  ShaderCompiler compiler(options, errs);
  std::unique_ptr<CompiledShader> shader = compiler.compile(source, path);
  if (!shader)
    return false;
  run.outputs = shader->outputs;
  run.images = shadeGrid(shader->kernel, shader->width, shader->outputs, grid, pool).images;
  return true;
}

/// The first value whose bits differ (with `anyNaN`, NaNs all match), or -1.
long firstDifference(const std::vector<float> &a, const std::vector<float> &b, bool anyNaN) {
  for (size_t i = 0; i < a.size(); ++i) {
    if (anyNaN && std::isnan(a[i]) && std::isnan(b[i]))
      continue;
    if (std::memcmp(&a[i], &b[i], sizeof(float)) != 0)
      return long(i);
  }
  return -1;
}

/// A value of an output's image as text: an int output's as the int.
std::string shown(float value, bool integer) {
  return integer ? std::to_string(intOutputValue(value)) : std::to_string(value);
}

} // namespace

int main(int argc, char **argv) {
  // Kernels compile faster without it (Jit.h).
  osl::Jit::disableMachineScheduler();
  GridOptions grid;
  grid.xres = 13;
  grid.yres = 7;
  grid.threads = 1;
  bool quiet = false, referenceOnly = false;
  std::vector<std::string> files;
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    if (a == "-g" && i + 2 < argc) {
      grid.xres = std::atoi(argv[++i]);
      grid.yres = std::atoi(argv[++i]);
    } else if (a == "--quiet") {
      quiet = true;
    } else if (a == "--reference-only") {
      referenceOnly = true;
    } else if (!a.empty() && a[0] == '-') {
      llvm::errs() << "osl-difftest: unknown option '" << a
                   << "'\nusage: osl-difftest [-g X Y] [--quiet] [--reference-only] FILE...\n";
      return 2;
    } else {
      files.push_back(a);
    }
  }
  if (files.empty() || grid.xres < 1 || grid.yres < 1) {
    llvm::errs() << "usage: osl-difftest [-g X Y] [--quiet] [--reference-only] FILE...\n";
    return 2;
  }
  ThreadPool pool(1);
  size_t compared = 0, rejected = 0;
  for (const std::string &path : files) {
    auto buffer = llvm::MemoryBuffer::getFile(path);
    if (!buffer) {
      llvm::errs() << path << ": error: cannot read: " << buffer.getError().message() << "\n";
      return 2;
    }
    llvm::StringRef source = (*buffer)->getBuffer();
    std::string errors;
    Run reference;
    if (!shade(source, path, 1, /*reference=*/true, grid, pool, reference, errors)) {
      // Every input is meant to be valid OSL: a rejection is a compiler bug
      // as much as a mismatch is, so it is always shown and fails the run.
      ++rejected;
      llvm::errs() << "REJECTED " << path << ":\n" << errors;
      continue;
    }
    if (referenceOnly) {
      ++compared;
      continue;
    }
    Run first; // width 1, which the other widths must equal bit for bit
    for (int width : {1, 4, 8, 16}) {
      Run simd;
      if (!shade(source, path, width, false, grid, pool, simd, errors)) {
        llvm::errs() << "MISMATCH " << path << ": compiles in reference mode but not at width "
                     << width << ":\n" << errors;
        return 1;
      }
      for (size_t o = 0; o < reference.images.size(); ++o) {
        const char *against = "the reference";
        // An int output's floats are its ints' bits (Grid.h): every bit counts.
        bool integer = reference.outputs[o].integer;
        long at = firstDifference(reference.images[o], simd.images[o], /*anyNaN=*/!integer);
        if (at < 0 && width != 1) {
          against = "width 1";
          at = firstDifference(first.images[o], simd.images[o], /*anyNaN=*/false);
        }
        if (at < 0)
          continue;
        int channels = reference.outputs[o].channels;
        long pixel = at / channels;
        llvm::errs() << "MISMATCH " << path << ": output '" << reference.outputs[o].name
                     << "' at width " << width << " differs from " << against << ", pixel ("
                     << pixel % grid.xres << ", " << pixel / grid.xres << ") channel "
                     << at % channels << ": reference "
                     << shown(reference.images[o][at], integer) << ", width 1 "
                     << shown((width == 1 ? simd : first).images[o][at], integer) << ", SIMD "
                     << shown(simd.images[o][at], integer) << "\n";
        return 1;
      }
      if (width == 1)
        first = std::move(simd);
    }
    ++compared;
  }
  if (quiet)
    return rejected ? 1 : 0;
  if (referenceOnly)
    llvm::outs() << "osl-difftest: " << compared << " shaders compiled and shaded in reference "
                 << "mode; " << rejected << " rejected by the compiler\n";
  else
    llvm::outs() << "osl-difftest: " << compared << " shaders bit-identical to the reference at "
                 << "widths 1, 4, 8, 16; " << rejected << " rejected by the compiler\n";
  return rejected ? 1 : 0;
}
