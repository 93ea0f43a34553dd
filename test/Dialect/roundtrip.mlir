// RUN: osl-opt %s | osl-opt | FileCheck %s

// CHECK-LABEL: func.func @globals_params_outputs
func.func @globals_params_outputs() {
  // CHECK: %[[P:.+]] = osl.global "P" : !osl.varying<vector<3xf32>>
  %P = osl.global "P" : !osl.varying<vector<3xf32>>
  %one = arith.constant 1.0 : f32
  // CHECK: osl.param "freq"(%{{.+}}) : f32
  %f = osl.param "freq"(%one) : f32
  // CHECK: osl.noise "perlin"(%[[P]]) : (!osl.varying<vector<3xf32>>) -> !osl.varying<f32>
  %n = osl.noise "perlin"(%P) : (!osl.varying<vector<3xf32>>) -> !osl.varying<f32>
  // CHECK: osl.output "Cout" = %{{.+}} : !osl.varying<f32>
  osl.output "Cout" = %n : !osl.varying<f32>
  return
}

// CHECK-LABEL: func.func @control_flow
func.func @control_flow(%c: i1, %a: f32) {
  // CHECK: osl.if %{{.+}} : i1 -> f32 {
  %0 = osl.if %c : i1 -> f32 {
    osl.yield %a : f32
  } else {
    osl.yield %a : f32
  }
  // CHECK: osl.while(%{{.+}} : f32) -> f32 cond {
  %1 = osl.while (%0 : f32) -> f32 cond {
  ^bb0(%x: f32):
    osl.condition %c : i1, %x : f32
  } do {
  ^bb0(%x: f32):
    osl.yield %x : f32
  }
  return
}
