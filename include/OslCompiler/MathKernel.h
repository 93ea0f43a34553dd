//===- MathKernel.h - one library math function as an array kernel -*- C++ -*-===//
//
// Compiles one OSL math function (its lane builder from LaneMath.h, with
// OSL's edge rules) into `kernel(x, y, out, n)` over arrays at a width and
// an implementation, through the same osl-approximate-math, lowering and
// JIT as shaders. The stability tests and bench/osl-mathbench use it to
// measure each implementation against a double-precision evaluation of the
// same function.
//
//===----------------------------------------------------------------------===//
#ifndef OSLCOMPILER_MATHKERNEL_H
#define OSLCOMPILER_MATHKERNEL_H

#include "OslRuntime/Jit.h"

#include "llvm/Support/Error.h"

#include <cstdint>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

namespace osl::math {

/// How the math ops of a function are computed.
enum class Impl {
  Fast,      ///< --math=fast: MLIR's polynomial approximations
  Default,   ///< --math=default: OSL's algorithms
  Precise,   ///< --math=precise: f64 libm per lane, rounded to f32
  Polynomial, ///< MLIR's polynomial approximations for every op (measured
              ///< only: the fast level picks between it and OSL's)
  Libmvec,   ///< glibc's vector math (_ZGV*), scalar libm at width 1;
             ///< measured only (results differ between widths)
  Reference, ///< the whole function in f64 with libm: writes doubles
             ///< (noise: the f32 kernel through osl-evaluate-in-double)
};
const char *implName(Impl impl);

/// A library function and the documented error bound of each
/// implementation (indexed by Impl::Fast, Default, Precise, Polynomial). A
/// result is within bound when its error is at most `ulp` or at most `abs`
/// absolutely; `ulp` counts ULPs of the exact value, except at Precise
/// where it counts representable floats from the correctly rounded result.
struct Function {
  const char *name;
  int arity;
  /// Useful domain of every argument, [lo, hi]: half the samples are
  /// uniform in it, half have log-uniform magnitudes in [magLo, max(|lo|,
  /// |hi|)] (either sign the domain allows; none when magLo is 0).
  double lo, hi, magLo;
  double ulp[4];
  double abs[4];
  /// A noise function (2D): no math ops, so every level computes the same
  /// thing; its reference is the same kernel evaluated in double by
  /// osl-evaluate-in-double.
  bool noise = false;
};
const std::vector<Function> &functions();
const Function *findFunction(const std::string &name);

/// Dense sample of a function's domain (deterministic), `n` points per
/// argument row: x[0..n), and y[0..n) for binary functions.
void sampleDomain(const Function &f, size_t n, std::vector<float> &x,
                  std::vector<float> &y);
/// Edge inputs: 0, -0, denormals, FLT_MIN, huge, +-Inf, NaN, negative
/// bases... (pairs for binary functions).
void edgeInputs(const Function &f, std::vector<float> &x, std::vector<float> &y);

/// Error of a float result against the double reference, in ULPs of the
/// reference's float magnitude (2^-149 below FLT_MIN).
double ulpError(float result, double reference);

class Kernel {
public:
  /// `x`, `y`, `out` have n elements (out: doubles for Impl::Reference);
  /// n must be a multiple of the width.
  using Fn = void (*)(const float *x, const float *y, void *out, int64_t n);

  static llvm::Expected<std::unique_ptr<Kernel>> compile(const Function &f, Impl impl,
                                                         int width);
  void run(const float *x, const float *y, void *out, int64_t n) const {
    fn(x, y, out, n);
  }
  /// Runs on any n: pads the tail to a multiple of the width.
  void runPadded(const std::vector<float> &x, const std::vector<float> &y,
                 std::vector<float> &out) const;
  void runReference(const std::vector<float> &x, const std::vector<float> &y,
                    std::vector<double> &out) const;
  int width() const { return w; }

private:
  Fn fn = nullptr;
  int w = 1;
  std::unique_ptr<Jit> jit;
};

/// Distance in representable floats between a and b (ULPs where they are
/// the same size), counting across zero: floats are ordered as integers.
inline int64_t floatSteps(float a, float b) {
  auto ordered = [](float v) {
    int32_t i;
    std::memcpy(&i, &v, sizeof i);
    return i < 0 ? int64_t(INT32_MIN) - i : int64_t(i);
  };
  int64_t d = ordered(a) - ordered(b);
  return d < 0 ? -d : d;
}

} // namespace osl::math

#endif // OSLCOMPILER_MATHKERNEL_H
