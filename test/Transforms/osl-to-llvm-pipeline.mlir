// The osl-to-llvm pipeline's options are the ones ShaderCompiler uses
// (OslToLLVMPipelineOptions): width, reference, count-lanes, math.
// RUN: osl-opt %s --osl-to-llvm="width=4" | FileCheck %s --check-prefix=W4
// RUN: osl-opt %s --osl-to-llvm="width=16" | FileCheck %s --check-prefix=W16
// RUN: osl-opt %s --osl-to-llvm="reference=true" | FileCheck %s --check-prefix=REF
// RUN: osl-opt %s --osl-to-llvm="width=8 count-lanes=true" | FileCheck %s --check-prefix=COUNT
// RUN: osl-opt %s --osl-to-llvm="width=8" | FileCheck %s --check-prefix=NOCOUNT

// A varying if: masked lanes at a width, a branch on one point in
// reference mode, and a count of active lanes per arm when asked.
// W4-LABEL: llvm.func @osl_batch
// W4-SAME: osl.shader_name = "branch_on_u"
// W4: llvm.load %{{.+}} {{.+}}osl.global_row = 33{{.+}} -> vector<4xf32>
// W4-NOT: llvm.cond_br
// W4: llvm.select %{{.+}} : vector<4xi1>, vector<4xf32>
// W16-LABEL: llvm.func @osl_batch
// W16: llvm.load %{{.+}} {{.+}}osl.global_row = 33{{.+}} -> vector<16xf32>
// REF-LABEL: llvm.func @osl_batch
// REF-SAME: osl.reference
// REF: llvm.load %{{.+}} {{.+}}osl.global_row = 33{{.+}} -> f32
// REF: llvm.cond_br
// COUNT: llvm.func @osl_rt_count_lanes(i32)
// COUNT-LABEL: llvm.func @osl_batch
// COUNT: llvm.call @osl_rt_count_lanes
// COUNT: llvm.call @osl_rt_count_lanes
// NOCOUNT-NOT: osl_rt_count_lanes
func.func @branch_on_u() attributes {osl.shader_type = "shader"} {
  %u = osl.global "u" : !osl.varying<f32>
  %v = osl.global "v" : !osl.varying<f32>
  %zero = arith.constant 0.000000e+00 : f32
  %out = osl.param "out"(%zero) : f32
  %half = arith.constant 5.000000e-01 : f32
  %c = osl.cmp gt, %u, %half {unordered} : !osl.varying<f32>, f32 -> !osl.varying<i1>
  %r = osl.if %c : !osl.varying<i1> -> !osl.varying<f32> {
    %s = osl.sin %u : !osl.varying<f32> -> !osl.varying<f32>
    osl.yield %s : !osl.varying<f32>
  } else {
    osl.yield %v : !osl.varying<f32>
  }
  osl.output "out" = %r : !osl.varying<f32>
  return
}
