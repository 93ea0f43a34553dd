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

// -----

// x - x is 0 and x * 0 is 0 for any x (an inf or a NaN included), as OSL's
// optimizer folds them; x - y and x * y stay.
// CHECK-LABEL: func.func @sub_of_itself_and_mul_by_zero
// CHECK-NOT: osl.sub %[[U:.+]], %[[U]]
// CHECK: osl.sub %{{.+}}, %{{.+}} : !osl.varying<f32>, !osl.varying<f32>
// CHECK-NOT: osl.sub
// CHECK: osl.mul %{{.+}}, %{{.+}} : !osl.varying<f32>, !osl.varying<f32>
// CHECK-NOT: osl.mul
// CHECK: return
func.func @sub_of_itself_and_mul_by_zero() {
  %zero = arith.constant 0.0 : f32
  %zeros = arith.constant dense<0.0> : vector<3xf32>
  %u = osl.global "u" : !osl.varying<f32>
  %v = osl.global "v" : !osl.varying<f32>
  %p = osl.global "P" : !osl.varying<vector<3xf32>>
  %a = osl.sub %u, %u : !osl.varying<f32>, !osl.varying<f32> -> !osl.varying<f32>
  %b = osl.sub %u, %v : !osl.varying<f32>, !osl.varying<f32> -> !osl.varying<f32>
  %c = osl.sub %p, %p : !osl.varying<vector<3xf32>>, !osl.varying<vector<3xf32>> -> !osl.varying<vector<3xf32>>
  %d = osl.mul %u, %v : !osl.varying<f32>, !osl.varying<f32> -> !osl.varying<f32>
  %e = osl.mul %u, %zero : !osl.varying<f32>, f32 -> !osl.varying<f32>
  %f = osl.mul %zero, %u : f32, !osl.varying<f32> -> !osl.varying<f32>
  %g = osl.mul %p, %zeros : !osl.varying<vector<3xf32>>, vector<3xf32> -> !osl.varying<vector<3xf32>>
  osl.output "a" = %a : !osl.varying<f32>
  osl.output "b" = %b : !osl.varying<f32>
  osl.output "c" = %c : !osl.varying<vector<3xf32>>
  osl.output "d" = %d : !osl.varying<f32>
  osl.output "e" = %e : !osl.varying<f32>
  osl.output "f" = %f : !osl.varying<f32>
  osl.output "g" = %g : !osl.varying<vector<3xf32>>
  return
}
