// RUN: osl-opt %s -split-input-file --canonicalize | FileCheck %s

// 0^y is 0 for a y not known to be 0, as OSL's optimizer folds it (where y
// is 0 at run time OSL's own pow would give 1); 0^0 stays a pow.
// CHECK-LABEL: func.func @pow_of_zero
// CHECK: %[[ZERO:.+]] = arith.constant 0.000000e+00 : f32
// CHECK: %[[SPLAT:.+]] = osl.broadcast %[[ZERO]]
// CHECK: osl.pow
// CHECK: osl.output "p" = %[[SPLAT]]
func.func @pow_of_zero() {
  %zero = arith.constant 0.0 : f32
  %u = osl.global "u" : !osl.varying<f32>
  %p = osl.pow %zero, %u : f32, !osl.varying<f32> -> !osl.varying<f32>
  %q = osl.pow %zero, %zero : f32, f32 -> f32
  osl.output "p" = %p : !osl.varying<f32>
  osl.output "q" = %q : f32
  return
}
