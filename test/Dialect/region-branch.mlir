// RUN: osl-opt %s -split-input-file --control-flow-sink | FileCheck %s

// osl.if and osl.while describe their control flow through
// RegionBranchOpInterface, so MLIR's own region passes understand them:
// control-flow-sink moves a value used in one arm only into that arm (each
// point runs an arm at most once).

// CHECK-LABEL: func.func @sink_into_then_arm
// CHECK: osl.if
// CHECK-NEXT: osl.sin
// CHECK: } else {
// CHECK-NOT: osl.sin
func.func @sink_into_then_arm(%c: !osl.varying<i1>, %x: !osl.varying<f32>) {
  %s = osl.sin %x : !osl.varying<f32> -> !osl.varying<f32>
  %r = osl.if %c : !osl.varying<i1> -> !osl.varying<f32> {
    osl.yield %s : !osl.varying<f32>
  } else {
    osl.yield %x : !osl.varying<f32>
  }
  osl.output "out" = %r : !osl.varying<f32>
  return
}

// -----

// A uniform value may flow into a varying result before
// osl-varying-propagation (the edges compare base types).
// CHECK-LABEL: func.func @uniform_into_varying_result
// CHECK: osl.if
// CHECK: osl.yield %{{.+}} : f32
func.func @uniform_into_varying_result(%c: !osl.varying<i1>, %a: f32, %b: !osl.varying<f32>) {
  %r = osl.if %c : !osl.varying<i1> -> !osl.varying<f32> {
    osl.yield %a : f32
  } else {
    osl.yield %b : !osl.varying<f32>
  }
  osl.output "out" = %r : !osl.varying<f32>
  return
}
