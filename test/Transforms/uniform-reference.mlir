// RUN: osl-opt %s -split-input-file --osl-uniform-reference | FileCheck %s

// Every varying value becomes uniform (globals too), so the function is
// marked as reference code for the verifier.
// CHECK-LABEL: func.func @values
// CHECK-SAME: osl.reference
// CHECK: %[[U:.+]] = osl.global "u" : f32
// CHECK: osl.sin %[[U]] : f32 -> f32
// CHECK-NOT: !osl.varying
func.func @values() {
  %u = osl.global "u" : !osl.varying<f32>
  %s = osl.sin %u : !osl.varying<f32> -> !osl.varying<f32>
  osl.output "s" = %s : !osl.varying<f32>
  return
}

// -----

// A varying if and a varying loop become ordinary ones: their conditions,
// results and block arguments are uniform.
// CHECK-LABEL: func.func @control_flow
// CHECK: osl.if %{{.+}} : i1 -> f32 {
// CHECK: osl.while(%{{.+}} : f32) -> f32 cond {
// CHECK: ^bb0(%{{.+}}: f32):
// CHECK: osl.condition %{{.+}} : i1, %{{.+}} : f32
// CHECK-NOT: !osl.varying
func.func @control_flow() {
  %u = osl.global "u" : !osl.varying<f32>
  %half = arith.constant 0.5 : f32
  %c = osl.cmp lt, %u, %half : !osl.varying<f32>, f32 -> !osl.varying<i1>
  %r = osl.if %c : !osl.varying<i1> -> !osl.varying<f32> {
    osl.yield %u : !osl.varying<f32>
  } else {
    %n = osl.neg %u : !osl.varying<f32> -> !osl.varying<f32>
    osl.yield %n : !osl.varying<f32>
  }
  %l = osl.while (%r : !osl.varying<f32>) -> !osl.varying<f32> cond {
  ^bb0(%v: !osl.varying<f32>):
    %k = osl.cmp lt, %v, %half : !osl.varying<f32>, f32 -> !osl.varying<i1>
    osl.condition %k : !osl.varying<i1>, %v : !osl.varying<f32>
  } do {
  ^bb0(%v: !osl.varying<f32>):
    %v2 = osl.add %v, %half : !osl.varying<f32>, f32 -> !osl.varying<f32>
    osl.yield %v2 : !osl.varying<f32>
  }
  osl.output "x" = %l : !osl.varying<f32>
  return
}

// -----

// A broadcast of a uniform value has nothing left to spread: it goes, and
// its users take the value itself.
// CHECK-LABEL: func.func @broadcast
// CHECK-NOT: osl.broadcast
// CHECK: %[[C:.+]] = arith.constant 2.000000e+00 : f32
// CHECK: osl.add %{{.+}}, %[[C]] : f32, f32 -> f32
func.func @broadcast() {
  %u = osl.global "u" : !osl.varying<f32>
  %c = arith.constant 2.0 : f32
  %b = osl.broadcast %c : f32 -> !osl.varying<f32>
  %s = osl.add %u, %b : !osl.varying<f32>, !osl.varying<f32> -> !osl.varying<f32>
  osl.output "s" = %s : !osl.varying<f32>
  return
}
