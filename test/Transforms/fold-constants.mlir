// RUN: osl-opt %s -split-input-file --osl-fold-constants | FileCheck %s

// Arithmetic on constants folds to the bits the lowering computes,
// including OSL's safe division (x/0 = 0).
// CHECK-LABEL: func.func @arithmetic
// CHECK-NOT: osl.
// CHECK-DAG: %[[SUM:.+]] = arith.constant 3.500000e+00 : f32
// CHECK-DAG: %[[ZERO:.+]] = arith.constant 0.000000e+00 : f32
// CHECK-DAG: %[[MOD:.+]] = arith.constant 1 : i32
// CHECK: osl.output "sum" = %[[SUM]]
// CHECK: osl.output "safe" = %[[ZERO]]
// CHECK: osl.output "mod" = %[[MOD]]
func.func @arithmetic() {
  %a = arith.constant 1.5 : f32
  %b = arith.constant 2.0 : f32
  %z = arith.constant 0.0 : f32
  %sum = osl.add %a, %b : f32, f32 -> f32
  %safe = osl.div %a, %z : f32, f32 -> f32
  %i7 = arith.constant 7 : i32
  %i3 = arith.constant 3 : i32
  %mod = osl.mod %i7, %i3 : i32, i32 -> i32
  osl.output "sum" = %sum : f32
  osl.output "safe" = %safe : f32
  osl.output "mod" = %mod : i32
  return
}

// -----

// Triples: componentwise arithmetic, construct and extract; a comparison
// of triples is true when every component is equal.
// CHECK-LABEL: func.func @triples
// CHECK-NOT: osl.
// CHECK-DAG: %[[SCALED:.+]] = arith.constant dense<[2.000000e+00, 4.000000e+00, 6.000000e+00]> : vector<3xf32>
// CHECK-DAG: %[[Y:.+]] = arith.constant 2.000000e+00 : f32
// CHECK-DAG: %[[EQ:.+]] = arith.constant false
// CHECK: osl.output "scaled" = %[[SCALED]]
// CHECK: osl.output "y" = %[[Y]]
// CHECK: osl.output "eq" = %[[EQ]]
func.func @triples() {
  %c = arith.constant dense<[1.0, 2.0, 3.0]> : vector<3xf32>
  %twos = arith.constant dense<2.0> : vector<3xf32>
  %scaled = osl.mul %c, %twos : vector<3xf32>, vector<3xf32> -> vector<3xf32>
  %two = arith.constant 2.0 : f32
  %one = arith.constant 1.0 : f32
  %t = osl.construct %one, %two, %one : f32, f32, f32 -> vector<3xf32>
  %y = osl.extract %t[1] : vector<3xf32> -> f32
  %eq = osl.cmp eq, %c, %t : vector<3xf32>, vector<3xf32> -> i1
  osl.output "scaled" = %scaled : vector<3xf32>
  osl.output "y" = %y : f32
  osl.output "eq" = %eq : i1
  return
}

// -----

// A constant condition decides an if (even one whose arms are varying) and
// a select; what is left is the chosen arm's code.
// CHECK-LABEL: func.func @constant_control_flow
// CHECK-NOT: osl.if
// CHECK-NOT: osl.select
// CHECK: %[[U:.+]] = osl.global "u"
// CHECK: %[[S:.+]] = osl.sin %[[U]]
// CHECK: osl.output "r" = %[[S]]
// CHECK: osl.output "s" = %[[U]]
func.func @constant_control_flow() {
  %u = osl.global "u" : !osl.varying<f32>
  %i0 = arith.constant 0 : i32
  %i1 = arith.constant 1 : i32
  %cond = osl.cmp lt, %i0, %i1 : i32, i32 -> i1
  %r = osl.if %cond : i1 -> !osl.varying<f32> {
    %s = osl.sin %u : !osl.varying<f32> -> !osl.varying<f32>
    osl.yield %s : !osl.varying<f32>
  } else {
    osl.yield %u : !osl.varying<f32>
  }
  %half = arith.constant 0.5 : f32
  %pick = osl.select %cond, %u, %half : i1, !osl.varying<f32>, f32 -> !osl.varying<f32>
  osl.output "r" = %r : !osl.varying<f32>
  osl.output "s" = %pick : !osl.varying<f32>
  return
}

// -----

// Left alone: transcendental functions (their folders would use the host's
// libm, not OSL's algorithms) and anything with a varying operand.
// CHECK-LABEL: func.func @not_folded
// CHECK: osl.sin
// CHECK: osl.add
func.func @not_folded() {
  %a = arith.constant 1.5 : f32
  %s = osl.sin %a : f32 -> f32
  %u = osl.global "u" : !osl.varying<f32>
  %b = osl.add %a, %u : f32, !osl.varying<f32> -> !osl.varying<f32>
  osl.output "s" = %s : f32
  osl.output "b" = %b : !osl.varying<f32>
  return
}
