// RUN: osl-opt %s | osl-opt | FileCheck %s

// CHECK-LABEL: func.func @globals_params_outputs
func.func @globals_params_outputs() {
  // CHECK: %[[P:.+]] = osl.global "P" : !osl.varying<vector<3xf32>>
  %P = osl.global "P" : !osl.varying<vector<3xf32>>
  %one = arith.constant 1.0 : f32
  // CHECK: osl.param "freq"(%{{.+}}) : f32
  %f = osl.param "freq"(%one) : f32
  // CHECK: osl.noise perlin(%[[P]]) : (!osl.varying<vector<3xf32>>) -> !osl.varying<f32>
  %n = osl.noise perlin(%P) : (!osl.varying<vector<3xf32>>) -> !osl.varying<f32>
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

// CHECK-LABEL: func.func @color_ops
func.func @color_ops(%c: vector<3xf32>, %t: !osl.varying<f32>) {
  // CHECK: osl.transformc "hsv" to "rgb" in "ACEScg" %{{.+}} : vector<3xf32> -> vector<3xf32>
  %0 = osl.transformc "hsv" to "rgb" in "ACEScg" %c : vector<3xf32> -> vector<3xf32>
  // CHECK: osl.blackbody "Rec709" %{{.+}} : !osl.varying<f32> -> !osl.varying<vector<3xf32>>
  %1 = osl.blackbody "Rec709" %t : !osl.varying<f32> -> !osl.varying<vector<3xf32>>
  // CHECK: osl.wavelength_color "Rec709" %{{.+}} : !osl.varying<f32> -> !osl.varying<vector<3xf32>>
  %2 = osl.wavelength_color "Rec709" %t : !osl.varying<f32> -> !osl.varying<vector<3xf32>>
  // CHECK: osl.luminance "Rec709" %{{.+}} : vector<3xf32> -> f32
  %3 = osl.luminance "Rec709" %0 : vector<3xf32> -> f32
  return
}

// Gabor noise: the filter's derivatives of the point and the options.
// CHECK-LABEL: func.func @gabor_options
func.func @gabor_options(%bw: f32) {
  %P = osl.global "P" : !osl.varying<vector<3xf32>>
  %dx = osl.deriv x %P : !osl.varying<vector<3xf32>>
  %dy = osl.deriv y %P : !osl.varying<vector<3xf32>>
  %one = arith.constant 1 : i32
  %dir = arith.constant dense<[0.0, 1.0, 0.0]> : vector<3xf32>
  // CHECK: osl.noise gabor(%{{.+}}) derivs(%{{.+}}, %{{.+}} : !osl.varying<vector<3xf32>>, !osl.varying<vector<3xf32>>) anisotropic(%{{.+}} : i32) direction(%{{.+}} : vector<3xf32>) bandwidth(%{{.+}} : f32) : (!osl.varying<vector<3xf32>>) -> !osl.varying<f32>
  %n = osl.noise gabor(%P) derivs(%dx, %dy : !osl.varying<vector<3xf32>>, !osl.varying<vector<3xf32>>) anisotropic(%one : i32) direction(%dir : vector<3xf32>) bandwidth(%bw : f32) : (!osl.varying<vector<3xf32>>) -> !osl.varying<f32>
  osl.output "n" = %n : !osl.varying<f32>
  return
}

// CHECK-LABEL: func.func @texture_ops
func.func @texture_ops(%s: !osl.varying<f32>, %m: !osl.varying<i1>) {
  %zero = arith.constant 0.0 : f32
  %c0 = arith.constant 0 : i32
  // CHECK: osl.texture texture(%{{.+}}, %{{.+}}) derivs
  // CHECK-SAME: mask %{{.+}} : !osl.varying<i1>
  %r, %a, %err = osl.texture texture(%s, %s) derivs(%zero, %zero, %zero, %zero) options(%zero, %zero, %zero, %zero, %zero, %zero, %zero, %zero, %zero, %zero, %zero) channel %c0 subimage %c0 choices(%c0, %c0, %c0, %c0, %c0, %c0) mask %m : !osl.varying<i1> {candidates = [["a.tx"], ["default"], ["default"], ["default"], ["smartcubic"], [""]], nchannels = 1 : i32} : (!osl.varying<f32>, !osl.varying<f32>) (f32, f32, f32, f32) (f32, f32, f32, f32, f32, f32, f32, f32, f32, f32, f32) i32, i32(i32, i32, i32, i32, i32, i32) -> !osl.varying<f32>, !osl.varying<f32>, !osl.varying<i32>
  // CHECK: osl.first_lane %{{.+}}, %{{.+}} : !osl.varying<f32>, !osl.varying<i1> -> f32
  %f = osl.first_lane %s, %m : !osl.varying<f32>, !osl.varying<i1> -> f32
  // CHECK: osl.gettextureinfo "a.tx", "resolution" : i32, (i32, i32)
  %found, %res:2 = osl.gettextureinfo "a.tx", "resolution" : i32, (i32, i32)
  return
}

// CHECK-LABEL: func.func @string_calls
func.func @string_calls(%i: !osl.varying<i32>, %f: f32, %c: vector<3xf32>) {
  // CHECK: %[[FMT:.+]] = osl.string_constant "%s_%02d %g %g" : i32
  %fmt = osl.string_constant "%s_%02d %g %g" : i32
  %pre = osl.string_constant "tile" : i32
  // CHECK: %[[S:.+]] = osl.string_call "format" "sisft"(%[[FMT]], %{{.+}}, %{{.+}}, %{{.+}}, %{{.+}}) : (i32, i32, i32, f32, vector<3xf32>) -> i32
  %s = osl.string_call "format" "sisft"(%fmt, %pre, %pre, %f, %c) : (i32, i32, i32, f32, vector<3xf32>) -> i32
  // CHECK: osl.string_call "substr" "sii"(%[[S]], %{{.+}}, %{{.+}}) : (i32, !osl.varying<i32>, !osl.varying<i32>) -> !osl.varying<i32>
  %sub = osl.string_call "substr" "sii"(%s, %i, %i) : (i32, !osl.varying<i32>, !osl.varying<i32>) -> !osl.varying<i32>
  // CHECK: osl.string_call "stof" "s"(%{{.+}}) : (!osl.varying<i32>) -> !osl.varying<f32>
  %x = osl.string_call "stof" "s"(%sub) : (!osl.varying<i32>) -> !osl.varying<f32>
  // CHECK: osl.string_call "concat" ""() : () -> i32
  %empty = osl.string_call "concat" ""() : () -> i32
  return
}

// Closures: uniform or varying, built by component, product and sum.
// CHECK-LABEL: func.func @closures
// CHECK: osl.closure_empty : !osl.closure
// CHECK: osl.closure_component "microfacet"(%{{.+}}) : (i32, vector<3xf32>, vector<3xf32>, f32, f32, f32, i32) -> !osl.closure
// CHECK: osl.closure_component "diffuse"(%{{.+}}) : (!osl.varying<vector<3xf32>>, i32) -> !osl.varying<!osl.closure>
// CHECK: osl.closure_mul %{{.+}}, %{{.+}} : !osl.varying<!osl.closure>, vector<3xf32> -> !osl.varying<!osl.closure>
// CHECK: osl.closure_add %{{.+}}, %{{.+}} : !osl.varying<!osl.closure>, !osl.closure -> !osl.varying<!osl.closure>
// CHECK: osl.select %{{.+}}, %{{.+}}, %{{.+}} : !osl.varying<i1>, !osl.varying<!osl.closure>, !osl.closure -> !osl.varying<!osl.closure>
// CHECK: osl.output "Ci" = %{{.+}} : !osl.varying<!osl.closure>
func.func @closures(%n: !osl.varying<vector<3xf32>>, %c: !osl.varying<i1>, %dist: i32,
                    %u: vector<3xf32>, %a: f32, %refr: i32, %w: vector<3xf32>) {
  %empty = osl.closure_empty : !osl.closure
  %spec = osl.closure_component "microfacet"(%dist, %u, %u, %a, %a, %a, %refr) : (i32, vector<3xf32>, vector<3xf32>, f32, f32, f32, i32) -> !osl.closure
  %d = osl.closure_component "diffuse"(%n, %dist) : (!osl.varying<vector<3xf32>>, i32) -> !osl.varying<!osl.closure>
  %dw = osl.closure_mul %d, %w : !osl.varying<!osl.closure>, vector<3xf32> -> !osl.varying<!osl.closure>
  %sum = osl.closure_add %dw, %spec : !osl.varying<!osl.closure>, !osl.closure -> !osl.varying<!osl.closure>
  %ci = osl.select %c, %sum, %empty : !osl.varying<i1>, !osl.varying<!osl.closure>, !osl.closure -> !osl.varying<!osl.closure>
  osl.output "Ci" = %ci : !osl.varying<!osl.closure>
  return
}

// CHECK-LABEL: func.func @print_streams
func.func @print_streams(%fmt: i32, %u: !osl.varying<f32>, %m: !osl.varying<i1>) {
  // CHECK: osl.print "printf" "sf"(%{{.+}}, %{{.+}}) : i32, !osl.varying<f32>
  osl.print "printf" "sf"(%fmt, %u) : i32, !osl.varying<f32>
  // error's first operand names the reporting shader.
  // CHECK: osl.print "error" "ss"(%{{.+}}, %{{.+}}) mask %{{.+}} : !osl.varying<i1> : i32, i32
  osl.print "error" "ss"(%fmt, %fmt) mask %m : !osl.varying<i1> : i32, i32
  // CHECK: osl.print "fprintf" "ssf"(%{{.+}}, %{{.+}}, %{{.+}}) : i32, i32, !osl.varying<f32>
  osl.print "fprintf" "ssf"(%fmt, %fmt, %u) : i32, i32, !osl.varying<f32>
  return
}

// A closure is tested against the empty one for `if (Ci)`.
// CHECK-LABEL: func.func @closure_compare
// CHECK: osl.cmp ne, %{{.+}}, %{{.+}} : !osl.varying<!osl.closure>, !osl.closure -> !osl.varying<i1>
func.func @closure_compare(%c: !osl.varying<!osl.closure>) {
  %empty = osl.closure_empty : !osl.closure
  %0 = osl.cmp ne, %c, %empty : !osl.varying<!osl.closure>, !osl.closure -> !osl.varying<i1>
  return
}

// CHECK-LABEL: func.func @messages
func.func @messages(%s: i32, %c: !osl.varying<vector<3xf32>>, %k: !osl.closure, %m: !osl.varying<i1>) {
  // CHECK: osl.set_message "a" "color" "t"(%{{.+}}) mask %{{.+}} : !osl.varying<i1> : !osl.varying<vector<3xf32>>
  osl.set_message "a" "color" "t"(%c) mask %m : !osl.varying<i1> : !osl.varying<vector<3xf32>>
  // CHECK: osl.get_message "b" "string" "s"(%{{.+}}) : (i32) -> (!osl.varying<i32>, !osl.varying<i32>)
  %f, %v = osl.get_message "b" "string" "s"(%s) : (i32) -> (!osl.varying<i32>, !osl.varying<i32>)
  // CHECK: osl.set_message "c" "closure color" "k"(%{{.+}}) : !osl.closure
  osl.set_message "c" "closure color" "k"(%k) : !osl.closure
  return
}

// CHECK-LABEL: func.func @pick
func.func @pick(%i: !osl.varying<i32>, %a: !osl.varying<vector<3xf32>>, %b: vector<3xf32>,
                %k: vector<8xi32>, %x: vector<8xf32>) {
  // CHECK: osl.pick %{{.+}}, [%{{.+}}, %{{.+}}] : !osl.varying<i32>, [!osl.varying<vector<3xf32>>, vector<3xf32>] -> !osl.varying<vector<3xf32>>
  %p = osl.pick %i, [%a, %b] : !osl.varying<i32>, [!osl.varying<vector<3xf32>>, vector<3xf32>] -> !osl.varying<vector<3xf32>>
  // CHECK: osl.lane_pick %{{.+}}, [%{{.+}}, %{{.+}}] : vector<8xi32>, [vector<8xf32>, vector<8xf32>] -> vector<8xf32>
  %q = osl.lane_pick %k, [%x, %x] : vector<8xi32>, [vector<8xf32>, vector<8xf32>] -> vector<8xf32>
  return
}

// CHECK-LABEL: func.func @codegen_fence
func.func @codegen_fence(%k: vector<8xi32>, %n: i32) -> (vector<8xi32>, i32) {
  // CHECK: osl.codegen_fence %{{.+}} : vector<8xi32>
  %a = osl.codegen_fence %k : vector<8xi32>
  // CHECK: osl.codegen_fence %{{.+}} : i32
  %b = osl.codegen_fence %n : i32
  return %a, %b : vector<8xi32>, i32
}

// CHECK-LABEL: func.func @table_read
func.func @table_read(%i: !osl.varying<i32>, %j: i32) {
  // CHECK: osl.table_read dense<[2, 3, 5, 7]> : tensor<4xi32>[%{{.+}}] : !osl.varying<i32> -> !osl.varying<i32>
  %p = osl.table_read dense<[2, 3, 5, 7]> : tensor<4xi32>[%i] : !osl.varying<i32> -> !osl.varying<i32>
  // CHECK: osl.table_read dense<[5.000000e-01, 2.500000e-01]> : tensor<2xf32>[%{{.+}}] : i32 -> f32
  %f = osl.table_read dense<[0.5, 0.25]> : tensor<2xf32>[%j] : i32 -> f32
  return
}

// CHECK-LABEL: func.func @noise_by_kind
func.func @noise_by_kind(%k: !osl.varying<i32>, %x: f32, %y: !osl.varying<f32>) -> (!osl.varying<f32>, !osl.varying<f32>) {
  // CHECK: osl.noise_by_kind %{{.+}} : !osl.varying<i32>(%{{.+}}) : (f32) -> !osl.varying<f32>
  %a = osl.noise_by_kind %k : !osl.varying<i32>(%x) : (f32) -> !osl.varying<f32>
  // CHECK: osl.noise_by_kind %{{.+}} : !osl.varying<i32>(%{{.+}}, %{{.+}}, %{{.+}}, %{{.+}}) derivs(%{{.+}}, %{{.+}}, %{{.+}}, %{{.+}} : f32, !osl.varying<f32>, f32, !osl.varying<f32>) {periodic} : (f32, !osl.varying<f32>, f32, f32) -> !osl.varying<f32>
  %b = osl.noise_by_kind %k : !osl.varying<i32>(%x, %y, %x, %x) derivs(%x, %y, %x, %y : f32, !osl.varying<f32>, f32, !osl.varying<f32>) {periodic} : (f32, !osl.varying<f32>, f32, f32) -> !osl.varying<f32>
  return %a, %b : !osl.varying<f32>, !osl.varying<f32>
}

