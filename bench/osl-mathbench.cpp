//===- osl-mathbench.cpp - error and speed of each math implementation ----===//
//
// For every library math function, each implementation (--math=fast,
// default, precise; MLIR's polynomial approximations for every op, which
// fast picks from; glibc's libmvec for comparison) at widths 1, 4, 8
// and 16: max ULP and max absolute error against the function evaluated in
// double with glibc's libm, over a dense sweep of its domain (results in
// the normal range up to 2^126), the largest distance in representable
// floats from the correctly rounded result, the number of edge inputs (0, -0,
// denormals, huge, Inf) where it gives NaN and OSL's default gives a
// number, and single-thread ns per point. One CSV row each; the chart and
// table are drawn from it by bench/math_chart.py. Not a test: timings
// depend on the machine; compare rows of one run.
//
//   osl-mathbench [--sweep N] [--only NAME,...] > math.csv
//
//===----------------------------------------------------------------------===//
#include "OslCompiler/MathKernel.h"

#include "llvm/Support/TargetSelect.h"
#include "llvm/Support/raw_ostream.h"

#include <algorithm>
#include <cfloat>
#include <chrono>
#include <cmath>
#include <cstring>
#include <dlfcn.h>
#include <sstream>

using namespace osl::math;

namespace {

bool inRange(double ref) {
  double a = std::fabs(ref);
  return std::isfinite(ref) && (a == 0 || (a >= FLT_MIN && a <= 0x1p126));
}

/// Best of 5 runs of enough repetitions over a 4096-point buffer.
double nsPerPoint(const Kernel &k, const std::vector<float> &x, const std::vector<float> &y) {
  const int64_t n = 4096;
  std::vector<float> bx(x.begin(), x.begin() + n), by(y.begin(), y.begin() + n), out(n);
  int reps = 1;
  double best = INFINITY;
  for (int trial = 0; trial < 8; ++trial) {
    auto start = std::chrono::steady_clock::now();
    for (int r = 0; r < reps; ++r)
      k.run(bx.data(), by.data(), out.data(), n);
    double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (s < 2e-3 && trial < 3) { // calibrate: at least 2 ms per trial
      reps = std::max(reps * 2, int(reps * 2.5e-3 / std::max(s, 1e-7)));
      continue;
    }
    best = std::min(best, s * 1e9 / double(n * reps));
  }
  return best;
}

} // namespace

int main(int argc, char **argv) {
  size_t sweep = 1 << 17; // the stability tests' sweep
  std::string only;
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    if (a == "--sweep" && i + 1 < argc) {
      sweep = std::strtoul(argv[++i], nullptr, 10);
    } else if (a == "--only" && i + 1 < argc) {
      only = "," + std::string(argv[++i]) + ",";
    } else {
      llvm::errs() << "usage: osl-mathbench [--sweep N] [--only NAME,...]\n";
      return 2;
    }
  }
  if (sweep < 4096) {
    llvm::errs() << "osl-mathbench: --sweep must be at least 4096\n";
    return 2;
  }
  llvm::InitializeNativeTarget();
  llvm::InitializeNativeTargetAsmPrinter();
  // The JIT resolves _ZGV* symbols in the process: load libmvec globally.
  if (!dlopen("libmvec.so.1", RTLD_NOW | RTLD_GLOBAL)) {
    llvm::errs() << "osl-mathbench: cannot load libmvec.so.1: " << dlerror() << "\n";
    return 1;
  }
  llvm::outs() << "function,impl,width,max_ulp,max_abs,cr_steps,ns_per_point,nan_edges,points,bound_ulp,bound_abs\n";
  for (const Function &f : functions()) {
    if (!only.empty() && only.find("," + std::string(f.name) + ",") == std::string::npos)
      continue;
    std::vector<float> x, y, ex, ey;
    sampleDomain(f, sweep, x, y);
    edgeInputs(f, ex, ey);
    auto reference = Kernel::compile(f, Impl::Reference, 16);
    auto oslKernel = Kernel::compile(f, Impl::Default, 16);
    if (!reference || !oslKernel) {
      llvm::errs() << "osl-mathbench: " << f.name << ": cannot compile the reference\n";
      llvm::consumeError(reference.takeError());
      llvm::consumeError(oslKernel.takeError());
      return 1;
    }
    std::vector<double> ref;
    (*reference)->runReference(x, y, ref);
    std::vector<float> oslEdges;
    (*oslKernel)->runPadded(ex, ey, oslEdges);
    // Timing inputs: a shuffled slice of the sweep, so branches see a mix.
    std::vector<size_t> order(x.size());
    for (size_t i = 0; i < order.size(); ++i)
      order[i] = (i * 2654435761u) % x.size();
    std::vector<float> tx, ty;
    for (size_t i = 0; i < 4096; ++i) {
      tx.push_back(x[order[i]]);
      ty.push_back(y[order[i]]);
    }
    for (Impl impl : {Impl::Fast, Impl::Default, Impl::Precise, Impl::Polynomial,
                      Impl::Libmvec})
      for (int width : {1, 4, 8, 16}) {
        // Noise has no math ops: every implementation is the same code.
        if (f.noise && impl != Impl::Default)
          continue;
        auto k = Kernel::compile(f, impl, width);
        if (!k) {
          llvm::errs() << "osl-mathbench: " << llvm::toString(k.takeError()) << "\n";
          return 1;
        }
        std::vector<float> r, edges;
        (*k)->runPadded(x, y, r);
        double maxUlp = 0, maxAbs = 0;
        int64_t maxSteps = 0;
        size_t points = 0;
        for (size_t i = 0; i < x.size(); ++i) {
          if (!inRange(ref[i]))
            continue;
          ++points;
          maxUlp = std::max(maxUlp, ulpError(r[i], ref[i]));
          maxAbs = std::max(maxAbs, std::fabs(double(r[i]) - ref[i]));
          maxSteps = std::max(maxSteps, floatSteps(r[i], float(ref[i])));
        }
        (*k)->runPadded(ex, ey, edges);
        int nanEdges = 0;
        for (size_t i = 0; i < ex.size(); ++i)
          nanEdges += std::isnan(edges[i]) && !std::isnan(oslEdges[i]) &&
                      !std::isnan(ex[i]) && !std::isnan(ey[i]);
        double ns = nsPerPoint(**k, tx, ty);
        std::ostringstream row;
        row.precision(4);
        row << f.name << "," << implName(impl) << "," << width << "," << maxUlp << ","
            << maxAbs << "," << maxSteps << "," << ns << "," << nanEdges << "," << points;
        // The documented bound (MathKernel.cpp); libmvec has none of ours.
        if (impl == Impl::Libmvec)
          row << ",,\n";
        else
          row << "," << f.ulp[int(impl)] << "," << f.abs[int(impl)] << "\n";
        llvm::outs() << row.str();
        llvm::outs().flush();
      }
  }
  return 0;
}
