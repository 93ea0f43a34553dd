// RUN: osl-opt %s -split-input-file --osl-approximate-math --canonicalize | FileCheck %s
// RUN: osl-opt %s -split-input-file --osl-approximate-math=level=fast | FileCheck %s --check-prefix=FAST
// RUN: osl-opt %s -split-input-file --osl-approximate-math=level=precise | FileCheck %s --check-prefix=PRECISE
// RUN: not osl-opt %s --osl-approximate-math=level=bogus 2>&1 | FileCheck %s --check-prefix=BOGUS
// BOGUS: Cannot find option named 'bogus'

// sin on 16 lanes becomes OSL's polynomial in vector registers (reduction
// by multiples of pi in four parts, then SLEEF's coefficients), never 16
// calls to sinf.
// CHECK-LABEL: func.func @sin_is_a_polynomial
// CHECK-NOT: math.sin
// CHECK-DAG: arith.constant dense<2.60831598E-6> : vector<16xf32>
// CHECK-DAG: math.roundeven
// CHECK: arith.mulf %{{.+}}, %{{.+}} : vector<16xf32>
func.func @sin_is_a_polynomial(%x: vector<16xf32>) -> vector<16xf32> {
  %s = math.sin %x : vector<16xf32>
  return %s : vector<16xf32>
}

// -----

// pow expands into OSL's exp2 and log2 (bit manipulation and polynomials),
// without calls.
// CHECK-LABEL: func.func @pow_is_inline
// CHECK-NOT: math.powf
// CHECK: arith.bitcast
// CHECK: arith.shli
func.func @pow_is_inline(%x: vector<8xf32>, %y: vector<8xf32>) -> vector<8xf32> {
  %p = math.powf %x, %y : vector<8xf32>
  return %p : vector<8xf32>
}

// -----

// A constant operand is not folded with the host's libm (e = 2.71828175):
// exp(1) becomes OSL's fast_exp arithmetic, with its fused multiply-adds
// (LLVM folds those later to what the kernel would compute per point).
// CHECK-LABEL: func.func @constant_is_not_folded_by_libm
// CHECK-NOT: math.exp
// CHECK-NOT: 2.71828175
// CHECK: math.fma
func.func @constant_is_not_folded_by_libm() -> f32 {
  %one = arith.constant 1.0 : f32
  %e = math.exp %one : f32
  return %e : f32
}

// -----

// fast: MLIR's polynomial sin (no roundeven: it reduces with floor), then
// OSL's rule that values a failed reduction pushes outside [-1, 1] are 0.
// CHECK-LABEL: func.func @fast_sin
// FAST-LABEL: func.func @fast_sin
// FAST-NOT: math.sin
// FAST-NOT: math.roundeven
// FAST: %[[OUT:.+]] = arith.cmpf ogt, %{{.+}}, %{{.+}} : vector<16xf32>
// FAST: arith.select %[[OUT]], %{{.+}}, %{{.+}} : vector<16xi1>, vector<16xf32>
func.func @fast_sin(%x: vector<16xf32>) -> vector<16xf32> {
  %s = math.sin %x : vector<16xf32>
  return %s : vector<16xf32>
}

// -----

// fast keeps OSL's atan (measured faster than MLIR's): its constant
// 0.430165678 appears; log10 is MLIR's log times 1/ln 10.
// CHECK-LABEL: func.func @fast_atan_is_osl
// FAST-LABEL: func.func @fast_atan_is_osl
// FAST-NOT: math.atan
// FAST-DAG: arith.constant dense<0.430165678> : vector<8xf32>
// FAST-DAG: arith.constant dense<0.434294492> : vector<8xf32>
// FAST-NOT: math.log10
func.func @fast_atan_is_osl(%x: vector<8xf32>) -> (vector<8xf32>, vector<8xf32>) {
  %a = math.atan %x : vector<8xf32>
  %l = math.log10 %x : vector<8xf32>
  return %a, %l : vector<8xf32>, vector<8xf32>
}

// -----

// precise: sin in double, one libm call per lane, rounded once to f32.
// CHECK-LABEL: func.func @precise_sin
// PRECISE-LABEL: func.func @precise_sin
// PRECISE: arith.extf %{{.+}} : vector<4xf32> to vector<4xf64>
// PRECISE-COUNT-4: call @sin(%{{.+}}) : (f64) -> f64
// PRECISE: arith.truncf %{{.+}} : vector<4xf64> to vector<4xf32>
func.func @precise_sin(%x: vector<4xf32>) -> vector<4xf32> {
  %s = math.sin %x : vector<4xf32>
  return %s : vector<4xf32>
}

// -----

// precise: a step LaneMath marks as internal to the function (log10 is a
// scaled log) is done in double, so the function is rounded once; a user's
// own arithmetic on the result stays float; floor stays one instruction.
// CHECK-LABEL: func.func @precise_scaled_log
// PRECISE-LABEL: func.func @precise_scaled_log
// PRECISE: %[[L:.+]] = call @log(%{{.+}}) : (f64) -> f64
// PRECISE: arith.mulf %[[L]], %{{.+}} {osl.one_rounding} : f64
// PRECISE: %[[M:.+]] = call @log(%{{.+}}) : (f64) -> f64
// PRECISE: %[[U:.+]] = arith.truncf %[[M]] : f64 to f32
// PRECISE: arith.mulf %[[U]], %{{.+}} : f32
// PRECISE: math.floor %{{.+}} : f32
// PRECISE-NOT: call @floor
func.func @precise_scaled_log(%x: f32, %y: f32) -> (f32, f32, f32) {
  %c = arith.constant 0.434294492 : f32
  %l = math.log %x : f32
  %s = arith.mulf %l, %c {osl.one_rounding} : f32
  %m = math.log %y : f32
  %u = arith.mulf %m, %c : f32
  %f = math.floor %x : f32
  return %s, %u, %f : f32, f32, f32
}

// -----

// precise: asin's sqrt(1 - x^2) (marked steps feeding atan2) is computed in
// double from the float argument.
// CHECK-LABEL: func.func @precise_asin_steps
// PRECISE-LABEL: func.func @precise_asin_steps
// PRECISE: arith.subf %{{.+}}, %{{.+}} {osl.one_rounding} : f64
// PRECISE: math.sqrt %{{.+}} {osl.one_rounding} : f64
// PRECISE: call @atan2(%{{.+}}, %{{.+}}) : (f64, f64) -> f64
func.func @precise_asin_steps(%x: f32) -> f32 {
  %one = arith.constant 1.0 : f32
  %a = arith.subf %one, %x {osl.one_rounding} : f32
  %b = arith.addf %one, %x {osl.one_rounding} : f32
  %p = arith.mulf %a, %b {osl.one_rounding} : f32
  %r = math.sqrt %p {osl.one_rounding} : f32
  %t = math.atan2 %x, %r {osl.one_rounding} : f32
  return %t : f32
}
