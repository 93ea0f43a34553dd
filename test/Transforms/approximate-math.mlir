// RUN: osl-opt %s -split-input-file --osl-approximate-math | FileCheck %s

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
// exp(1) folds through OSL's fast_exp arithmetic to what the kernel would
// compute per point.
// CHECK-LABEL: func.func @constant_is_not_folded_by_libm
// CHECK-NOT: math.exp
// CHECK-NOT: 2.71828175
// CHECK: arith.constant 2.71827602 : f32
func.func @constant_is_not_folded_by_libm() -> f32 {
  %one = arith.constant 1.0 : f32
  %e = math.exp %one : f32
  return %e : f32
}
