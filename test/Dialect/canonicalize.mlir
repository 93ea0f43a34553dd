// RUN: osl-opt %s -split-input-file --canonicalize | FileCheck %s

// 0^y is 0 for a y not known to be 0, as OSL's optimizer folds it (where y
// is 0 at run time OSL's own pow would give 1); x^0 is 1, 0^0 included,
// as OSL's optimizer decides y = 0 first.
// CHECK-LABEL: func.func @pow_of_zero
// CHECK-DAG: %[[ZERO:.+]] = arith.constant 0.000000e+00 : f32
// CHECK-DAG: %[[ONE:.+]] = arith.constant 1.000000e+00 : f32
// CHECK: %[[SPLAT:.+]] = osl.broadcast %[[ZERO]]
// CHECK-NOT: osl.pow
// CHECK: osl.output "p" = %[[SPLAT]]
// CHECK: osl.output "q" = %[[ONE]]
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

// pow(x, c) for the constants OSL's optimizer rewrites: 1 (x), 2 (x*x),
// 0.5 (sqrt), -0.5 (inversesqrt), 1/3 (cbrt), a float exponent of a triple
// (the front end's splat) included; 0 gives 1 for a triple too; other
// exponents, triple exponents of different values, and a constant base
// (OSL evaluates its pow, which clamps) stay pows.
// CHECK-LABEL: func.func @pow_of_constant_exponent
// CHECK-DAG: %[[ONE:.+]] = arith.constant 1.000000e+00 : f32
// CHECK-DAG: %[[U:.+]] = osl.global "u"
// CHECK-DAG: %[[P:.+]] = osl.global "P"
// CHECK: osl.output "one" = %[[U]]
// CHECK: %[[SQ:.+]] = osl.mul %[[U]], %[[U]]
// CHECK: osl.output "two" = %[[SQ]]
// CHECK: %[[SQRT:.+]] = osl.sqrt %[[U]]
// CHECK: osl.output "half" = %[[SQRT]]
// CHECK: %[[RSQRT:.+]] = osl.inversesqrt %[[U]]
// CHECK: osl.output "minus_half" = %[[RSQRT]]
// CHECK: %[[CBRT:.+]] = osl.cbrt %[[P]]
// CHECK: osl.output "third" = %[[CBRT]]
// CHECK: %[[ONES:.+]] = osl.construct %[[ONE]], %[[ONE]], %[[ONE]]
// CHECK: %[[VONES:.+]] = osl.broadcast %[[ONES]]
// CHECK: osl.output "zero" = %[[VONES]]
// CHECK: %[[OTHER:.+]] = osl.pow %[[U]]
// CHECK: osl.output "other" = %[[OTHER]]
// CHECK: %[[TRIPLE:.+]] = osl.pow %[[P]]
// CHECK: osl.output "triple" = %[[TRIPLE]]
// CHECK: %[[BOTH:.+]] = osl.pow %{{.+}}, %{{.+}} : f32, f32
// CHECK: osl.output "both_constant" = %[[BOTH]]
func.func @pow_of_constant_exponent() {
  %u = osl.global "u" : !osl.varying<f32>
  %P = osl.global "P" : !osl.varying<vector<3xf32>>
  %c0 = arith.constant 0.0 : f32
  %zeros = arith.constant dense<0.0> : vector<3xf32>
  %c1 = arith.constant 1.0 : f32
  %c2 = arith.constant 2.0 : f32
  %half = arith.constant 0.5 : f32
  %mhalf = arith.constant -0.5 : f32
  %third = arith.constant dense<0.333333343> : vector<3xf32>
  %other = arith.constant 3.0 : f32
  %t = arith.constant dense<[0.5, 1.0, 2.0]> : vector<3xf32>
  %a = osl.pow %u, %c1 : !osl.varying<f32>, f32 -> !osl.varying<f32>
  osl.output "one" = %a : !osl.varying<f32>
  %b = osl.pow %u, %c2 : !osl.varying<f32>, f32 -> !osl.varying<f32>
  osl.output "two" = %b : !osl.varying<f32>
  %c = osl.pow %u, %half : !osl.varying<f32>, f32 -> !osl.varying<f32>
  osl.output "half" = %c : !osl.varying<f32>
  %d = osl.pow %u, %mhalf : !osl.varying<f32>, f32 -> !osl.varying<f32>
  osl.output "minus_half" = %d : !osl.varying<f32>
  %e = osl.pow %P, %third : !osl.varying<vector<3xf32>>, vector<3xf32> -> !osl.varying<vector<3xf32>>
  osl.output "third" = %e : !osl.varying<vector<3xf32>>
  %f = osl.pow %P, %zeros : !osl.varying<vector<3xf32>>, vector<3xf32> -> !osl.varying<vector<3xf32>>
  osl.output "zero" = %f : !osl.varying<vector<3xf32>>
  %g = osl.pow %u, %other : !osl.varying<f32>, f32 -> !osl.varying<f32>
  osl.output "other" = %g : !osl.varying<f32>
  %h = osl.pow %P, %t : !osl.varying<vector<3xf32>>, vector<3xf32> -> !osl.varying<vector<3xf32>>
  osl.output "triple" = %h : !osl.varying<vector<3xf32>>
  // Both constant: OSL's own (clamped) pow, not x*x (1e20^2 is FLT_MAX).
  %big = arith.constant 1.0e20 : f32
  %i = osl.pow %big, %c2 : f32, f32 -> f32
  osl.output "both_constant" = %i : f32
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

// -----

// A broadcast whose value a pass made varying (an unrolled loop's result)
// is the value itself.
// CHECK-LABEL: func.func @broadcast_of_varying
// CHECK-NOT: osl.broadcast
// CHECK: osl.output "b" = %[[U:.+]] :
func.func @broadcast_of_varying() {
  %u = osl.global "u" : !osl.varying<f32>
  %b = osl.broadcast %u : !osl.varying<f32> -> !osl.varying<f32>
  osl.output "b" = %b : !osl.varying<f32>
  return
}

// -----

// A noise by kind whose kind is a constant is that kind's noise; Gabor
// keeps the derivatives for its filter, other kinds drop them. A periodic
// simplex kind (0) is left to the lowering.
// CHECK-LABEL: func.func @noise_of_constant_kind
// CHECK: osl.noise cell(%arg0) : (vector<3xf32>) -> f32
// CHECK: osl.noise gabor(%arg0) derivs(%arg1, %arg1 : vector<3xf32>, vector<3xf32>)
// CHECK: osl.noise_by_kind %{{.+}} : i32(%arg0, %arg0) derivs({{.+}}) {periodic}
func.func @noise_of_constant_kind(%p: vector<3xf32>, %d: vector<3xf32>) -> (f32, f32, f32) {
  %cell = arith.constant 2 : i32
  %gabor = arith.constant 6 : i32
  %simplex = arith.constant 4 : i32
  %a = osl.noise_by_kind %cell : i32(%p) derivs(%d, %d : vector<3xf32>, vector<3xf32>) : (vector<3xf32>) -> f32
  %b = osl.noise_by_kind %gabor : i32(%p) derivs(%d, %d : vector<3xf32>, vector<3xf32>) : (vector<3xf32>) -> f32
  %c = osl.noise_by_kind %simplex : i32(%p, %p) derivs(%d, %d : vector<3xf32>, vector<3xf32>) {periodic} : (vector<3xf32>, vector<3xf32>) -> f32
  return %a, %b, %c : f32, f32, f32
}


// -----

// A pick at a constant index is that element; a pick over one value
// repeated is that value; a uniform element does not replace a varying
// pick (its type differs).
// CHECK-LABEL: func.func @pick_folds
// CHECK-SAME: (%[[I:.+]]: !osl.varying<i32>, %[[X:.+]]: !osl.varying<f32>, %[[Y:.+]]: f32, %[[L:.+]]: vector<4xf32>, %[[M:.+]]: vector<4xf32>)
// CHECK: %[[U:.+]] = osl.pick
// CHECK: osl.output "a" = %[[X]]
// CHECK: osl.output "b" = %[[X]]
// CHECK: osl.output "c" = %[[U]]
// CHECK-NOT: osl.lane_pick
// CHECK: return %[[M]]
func.func @pick_folds(%i: !osl.varying<i32>, %x: !osl.varying<f32>, %y: f32,
                      %l: vector<4xf32>, %m: vector<4xf32>) -> vector<4xf32> {
  %c1 = arith.constant 1 : i32
  %a = osl.pick %c1, [%y, %x] : i32, [f32, !osl.varying<f32>] -> !osl.varying<f32>
  %b = osl.pick %i, [%x, %x, %x] : !osl.varying<i32>, [!osl.varying<f32>, !osl.varying<f32>, !osl.varying<f32>] -> !osl.varying<f32>
  %c = osl.pick %c1, [%x, %y] : i32, [!osl.varying<f32>, f32] -> !osl.varying<f32>
  osl.output "a" = %a : !osl.varying<f32>
  osl.output "b" = %b : !osl.varying<f32>
  osl.output "c" = %c : !osl.varying<f32>
  %k = arith.constant dense<1> : vector<4xi32>
  %p = osl.lane_pick %k, [%l, %m] : vector<4xi32>, [vector<4xf32>, vector<4xf32>] -> vector<4xf32>
  return %p : vector<4xf32>
}

// -----

// A fence on a constant is the constant (a hash of constant keys folds
// whole); a fence on a computed value stays.
// CHECK-LABEL: func.func @codegen_fence_folds
// CHECK-SAME: (%[[X:.+]]: vector<4xi32>)
// CHECK-DAG: %[[C:.+]] = arith.constant dense<-6> : vector<4xi32>
// CHECK-DAG: %[[F:.+]] = osl.codegen_fence %[[X]]
// CHECK: return %[[C]], %[[F]]
func.func @codegen_fence_folds(%x: vector<4xi32>) -> (vector<4xi32>, vector<4xi32>) {
  %c = arith.constant dense<-6> : vector<4xi32>
  %a = osl.codegen_fence %c : vector<4xi32>
  %b = osl.codegen_fence %x : vector<4xi32>
  return %a, %b : vector<4xi32>, vector<4xi32>
}
