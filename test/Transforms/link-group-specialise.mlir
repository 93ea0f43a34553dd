// Specialisation after linking (what ShaderCompiler runs for a group):
// instance values become constants, folding crosses layers, and a value
// that was varying only through what folded away becomes uniform, so the
// control flow it decided disappears instead of being masked.
// RUN: osl-opt %s -split-input-file --osl-link-group --osl-bind-params --osl-fold-constants --canonicalize --osl-varying-propagation --osl-insert-mask-stack | FileCheck %s

// `pick` is 0: the upstream layer's output is the constant 0.75, so the
// root's varying-looking if is decided at compile time.
// CHECK-LABEL: func.func @decided_by_instance_value
// CHECK-NOT: scf.if
// CHECK-NOT: arith.select
// CHECK-NOT: osl.select
// CHECK-NOT: osl.noise
// CHECK: %[[ONE:.+]] = arith.constant {{.*}}dense<1.000000e+00> : vector<3xf32>
// CHECK: osl.output "Cout" = %[[ONE]] {{.*}}: vector<3xf32>
module {
  func.func @up() attributes {osl.layer = "up"} {
    %u = osl.global "u" : !osl.varying<f32>
    %zero = arith.constant 0 : i32
    %pick = osl.param "pick"(%zero) : i32
    %cz = arith.constant 0 : i32
    %use_u = osl.cmp ne, %pick, %cz : i32, i32 -> i1
    %c = arith.constant 0.75 : f32
    %out = osl.select %use_u, %u, %c : i1, !osl.varying<f32>, f32 -> !osl.varying<f32>
    osl.output "out" = %out : !osl.varying<f32>
    return
  }
  func.func @decided_by_instance_value() attributes {osl.layer = "decided_by_instance_value"} {
    %p = osl.global "P" : !osl.varying<vector<3xf32>>
    %zero = arith.constant 0.0 : f32
    %in = osl.param "in"(%zero) {osl.connect = ["up", "out"]} : f32
    %t = arith.constant 0.5 : f32
    %cond = osl.cmp gt, %in, %t : f32, f32 -> i1
    %r = osl.if %cond : i1 -> !osl.varying<vector<3xf32>> {
      %one = arith.constant dense<1.0> : vector<3xf32>
      osl.yield %one : vector<3xf32>
    } else {
      %n = osl.noise perlin(%p) : (!osl.varying<vector<3xf32>>) -> !osl.varying<vector<3xf32>>
      osl.yield %n : !osl.varying<vector<3xf32>>
    }
    osl.output "Cout" = %r : !osl.varying<vector<3xf32>>
    return
  }
}

// -----

// The same group with `pick` 1: the output is u, the if stays varying and
// is masked.
// CHECK-LABEL: func.func @decided_per_point
// CHECK: osl.cmp gt, {{.*}} -> !osl.varying<i1>
// CHECK: scf.if
// CHECK: osl.noise
// CHECK: osl.select
module {
  func.func @up() attributes {osl.layer = "up"} {
    %u = osl.global "u" : !osl.varying<f32>
    %one = arith.constant 1 : i32
    %pick = osl.param "pick"(%one) : i32
    %cz = arith.constant 0 : i32
    %use_u = osl.cmp ne, %pick, %cz : i32, i32 -> i1
    %c = arith.constant 0.75 : f32
    %out = osl.select %use_u, %u, %c : i1, !osl.varying<f32>, f32 -> !osl.varying<f32>
    osl.output "out" = %out : !osl.varying<f32>
    return
  }
  func.func @decided_per_point() attributes {osl.layer = "decided_per_point"} {
    %p = osl.global "P" : !osl.varying<vector<3xf32>>
    %zero = arith.constant 0.0 : f32
    %in = osl.param "in"(%zero) {osl.connect = ["up", "out"]} : f32
    %t = arith.constant 0.5 : f32
    %cond = osl.cmp gt, %in, %t : f32, f32 -> i1
    %r = osl.if %cond : i1 -> !osl.varying<vector<3xf32>> {
      %one = arith.constant dense<1.0> : vector<3xf32>
      osl.yield %one : vector<3xf32>
    } else {
      %n = osl.noise perlin(%p) : (!osl.varying<vector<3xf32>>) -> !osl.varying<vector<3xf32>>
      osl.yield %n : !osl.varying<vector<3xf32>>
    }
    osl.output "Cout" = %r : !osl.varying<vector<3xf32>>
    return
  }
}
