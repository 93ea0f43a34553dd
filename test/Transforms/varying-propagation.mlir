// RUN: osl-opt %s -split-input-file --osl-varying-propagation | FileCheck %s

// A value computed from a global is varying; one computed from constants
// and parameters stays uniform and scalar.
// CHECK-LABEL: func.func @data_dependence
func.func @data_dependence() {
  %u = osl.global "u" : !osl.varying<f32>
  %one = arith.constant 1.0 : f32
  %f = osl.param "freq"(%one) : f32
  // CHECK: osl.mul %{{.+}}, %{{.+}} : f32, f32 -> f32
  %uniform = osl.mul %f, %f : f32, f32 -> f32
  // CHECK: osl.mul %{{.+}}, %{{.+}} : !osl.varying<f32>, f32 -> !osl.varying<f32>
  %varying = osl.mul %u, %uniform : !osl.varying<f32>, f32 -> f32
  // CHECK: osl.sin %{{.+}} : !osl.varying<f32> -> !osl.varying<f32>
  %s = osl.sin %varying : f32 -> f32
  osl.output "a" = %uniform : f32
  osl.output "b" = %s : f32
  return
}

// -----

// Both arms assign constants, but which one a point gets depends on u:
// the merged value is varying. Uniform constants flowing into the varying
// result get an explicit broadcast.
// CHECK-LABEL: func.func @assigned_under_varying_if
func.func @assigned_under_varying_if() {
  %u = osl.global "u" : !osl.varying<f32>
  %half = arith.constant 0.5 : f32
  %c = osl.cmp gt, %u, %half : !osl.varying<f32>, f32 -> !osl.varying<i1>
  %one = arith.constant 1.0 : f32
  %two = arith.constant 2.0 : f32
  // CHECK: %[[R:.+]] = osl.if %{{.+}} : !osl.varying<i1> -> !osl.varying<f32> {
  // CHECK:   %[[B1:.+]] = osl.broadcast %{{.+}} : f32 -> !osl.varying<f32>
  // CHECK:   osl.yield %[[B1]] : !osl.varying<f32>
  // CHECK: } else {
  // CHECK:   osl.broadcast
  %r = osl.if %c : !osl.varying<i1> -> f32 {
    osl.yield %one : f32
  } else {
    osl.yield %two : f32
  }
  // CHECK: osl.add %[[R]], %{{.+}} : !osl.varying<f32>, f32 -> !osl.varying<f32>
  %s = osl.add %r, %one : f32, f32 -> f32
  osl.output "x" = %s : f32
  return
}

// -----

// A uniform condition keeps uniform values uniform.
// CHECK-LABEL: func.func @uniform_if_stays_uniform
func.func @uniform_if_stays_uniform() {
  %one = arith.constant 1.0 : f32
  %f = osl.param "freq"(%one) : f32
  %c = osl.cmp gt, %f, %one : f32, f32 -> i1
  // CHECK: osl.if %{{.+}} : i1 -> f32
  // CHECK-NOT: osl.broadcast
  %r = osl.if %c : i1 -> f32 {
    osl.yield %one : f32
  } else {
    osl.yield %f : f32
  }
  osl.output "x" = %r : f32
  return
}

// -----

// The trip count depends on u, so the counter and the sum are varying in
// every iteration and after the loop, though each starts uniform.
// CHECK-LABEL: func.func @loop_with_varying_trip_count
func.func @loop_with_varying_trip_count() {
  %u = osl.global "u" : !osl.varying<f32>
  %zero = arith.constant 0.0 : f32
  %one = arith.constant 1.0 : f32
  %ten = arith.constant 10.0 : f32
  %n = osl.mul %u, %ten : !osl.varying<f32>, f32 -> !osl.varying<f32>
  // CHECK: %[[I0:.+]] = osl.broadcast %{{.+}} : f32 -> !osl.varying<f32>
  // CHECK: %[[S0:.+]] = osl.broadcast %{{.+}} : f32 -> !osl.varying<f32>
  // CHECK: osl.while(%[[I0]], %[[S0]] : !osl.varying<f32>, !osl.varying<f32>) -> !osl.varying<f32>, !osl.varying<f32> cond {
  // CHECK: ^bb0(%{{.+}}: !osl.varying<f32>, %{{.+}}: !osl.varying<f32>):
  %r:2 = osl.while (%zero, %zero : f32, f32) -> f32, f32 cond {
  ^bb0(%i: f32, %sum: f32):
    // CHECK: osl.cmp lt, %{{.+}}, %{{.+}} : !osl.varying<f32>, !osl.varying<f32> -> !osl.varying<i1>
    %c = osl.cmp lt, %i, %n : f32, !osl.varying<f32> -> i1
    osl.condition %c : i1, %i, %sum : f32, f32
  } do {
  ^bb0(%i: f32, %sum: f32):
    %i2 = osl.add %i, %one : f32, f32 -> f32
    %s2 = osl.add %sum, %one : f32, f32 -> f32
    osl.yield %i2, %s2 : f32, f32
  }
  osl.output "x" = %r#1 : f32
  return
}

// -----

// A uniform loop whose body accumulates a varying value: only that
// carried value becomes varying; the counter stays uniform.
// CHECK-LABEL: func.func @uniform_loop_with_varying_body
func.func @uniform_loop_with_varying_body() {
  %u = osl.global "u" : !osl.varying<f32>
  %zero = arith.constant 0 : i32
  %six = arith.constant 6 : i32
  %inc = arith.constant 1 : i32
  %fz = arith.constant 0.0 : f32
  // CHECK: osl.while(%{{.+}}, %{{.+}} : i32, !osl.varying<f32>) -> i32, !osl.varying<f32>
  %r:2 = osl.while (%zero, %fz : i32, f32) -> i32, f32 cond {
  ^bb0(%i: i32, %sum: f32):
    // CHECK: osl.cmp lt, %{{.+}}, %{{.+}} : i32, i32 -> i1
    %c = osl.cmp lt, %i, %six : i32, i32 -> i1
    osl.condition %c : i1, %i, %sum : i32, f32
  } do {
  ^bb0(%i: i32, %sum: f32):
    %i2 = osl.add %i, %inc : i32, i32 -> i32
    %s2 = osl.add %sum, %u : f32, !osl.varying<f32> -> f32
    osl.yield %i2, %s2 : i32, f32
  }
  osl.output "x" = %r#1 : f32
  return
}

// -----

// Whether a value is constant is one answer for the whole batch: the
// result of is_constant stays uniform even for a varying operand.
// CHECK-LABEL: func.func @is_constant_stays_uniform
// CHECK: osl.is_constant %{{.+}} : !osl.varying<f32>
// CHECK: osl.add %{{.+}}, %{{.+}} : i32, i32 -> i32
func.func @is_constant_stays_uniform() {
  %u = osl.global "u" : !osl.varying<f32>
  %c = osl.is_constant %u : !osl.varying<f32>
  %s = osl.add %c, %c : i32, i32 -> i32
  osl.output "x" = %s : i32
  return
}
