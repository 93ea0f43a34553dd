// RUN: osl-opt %s -split-input-file --osl-convert-to-vector=width=8 | FileCheck %s
// RUN: osl-opt %s -split-input-file --osl-convert-to-vector=width=16 | FileCheck %s --check-prefix=W16
// RUN: osl-opt %s -split-input-file --osl-convert-to-vector="width=8 assume-compiled=true" \
// RUN:   | FileCheck %s --check-prefix=ASSUMED

// The shader becomes the batch kernel; a varying triple global is three
// rows of W floats, loaded from the globals block.
// CHECK-LABEL: func.func @osl_batch(%{{.+}}: !llvm.ptr, %{{.+}}: !llvm.ptr, %{{.+}}: i32) attributes {osl.shader_name = "globals_and_outputs"}
// CHECK: llvm.getelementptr %{{.+}}[0] : (!llvm.ptr) -> !llvm.ptr, f32
// CHECK: llvm.load %{{.+}} : !llvm.ptr -> vector<8xf32>
// CHECK: llvm.getelementptr %{{.+}}[8]
// CHECK: llvm.getelementptr %{{.+}}[16]
// Outputs written at the end of the shader store whole rows (the caller
// reads the first nactive lanes): plain stores, which forward to the
// caller's loads, where masked ones make them wait.
// CHECK: llvm.getelementptr %{{.+}}[0] : (!llvm.ptr) -> !llvm.ptr, f32
// CHECK: llvm.store %{{.+}}, %{{.+}} {alignment = 4 : i64} : vector<8xf32>, !llvm.ptr
// CHECK-NOT: llvm.intr.masked.store
// W16: llvm.load %{{.+}} : !llvm.ptr -> vector<16xf32>
func.func @globals_and_outputs() {
  %P = osl.global "P" : !osl.varying<vector<3xf32>>
  osl.output "Pout" = %P : !osl.varying<vector<3xf32>>
  return
}

// -----

// Uniform values stay scalar; a uniform operand of a varying op is
// broadcast once it meets varying data.
// CHECK-LABEL: osl.shader_name = "uniform_stays_scalar"
// CHECK: %[[S:.+]] = arith.mulf %{{.+}}, %{{.+}} : f32
// CHECK: %[[B:.+]] = vector.broadcast %[[S]] : f32 to vector<8xf32>
// CHECK: arith.addf %{{.+}}, %[[B]] : vector<8xf32>
func.func @uniform_stays_scalar() {
  %u = osl.global "u" : !osl.varying<f32>
  %two = arith.constant 2.0 : f32
  %s = osl.mul %two, %two : f32, f32 -> f32
  %r = osl.add %u, %s : !osl.varying<f32>, f32 -> !osl.varying<f32>
  osl.output "x" = %r : !osl.varying<f32>
  return
}

// -----

// OSL's safe division: a quotient that is not finite (x/0, inf/y, NaN,
// overflow) is 0, by a select on |q| < inf.
// CHECK-LABEL: osl.shader_name = "safe_division"
// CHECK: %[[Q:.+]] = arith.divf %{{.+}}, %{{.+}} : vector<8xf32>
// CHECK: %[[A:.+]] = math.absf %[[Q]] : vector<8xf32>
// CHECK: %[[F:.+]] = arith.cmpf olt, %[[A]], %{{.+}} : vector<8xf32>
// CHECK: arith.select %[[F]], %[[Q]], %{{.+}} : vector<8xi1>, vector<8xf32>
func.func @safe_division() {
  %u = osl.global "u" : !osl.varying<f32>
  %v = osl.global "v" : !osl.varying<f32>
  %q = osl.div %u, %v : !osl.varying<f32>, !osl.varying<f32> -> !osl.varying<f32>
  osl.output "q" = %q : !osl.varying<f32>
  return
}

// -----

// By a non-zero constant (a scalar or a triple's component) the division
// is plain, as OSL's scalar JIT emits it: inf / 2 stays inf.
// CHECK-LABEL: osl.shader_name = "division_by_constant"
// CHECK: arith.divf %{{.+}}, %{{.+}} : vector<8xf32>
// CHECK-NOT: math.absf
// CHECK: arith.divf %{{.+}}, %{{.+}} : vector<8xf32>
// CHECK-NOT: math.absf
// CHECK: arith.divf %{{.+}}, %{{.+}} : vector<8xf32>
// CHECK-NOT: math.absf
// CHECK: arith.divf %{{.+}}, %{{.+}} : vector<8xf32>
// CHECK: math.absf
func.func @division_by_constant() {
  %u = osl.global "u" : !osl.varying<f32>
  %p = osl.global "P" : !osl.varying<vector<3xf32>>
  %two = arith.constant 2.0 : f32
  %k = arith.constant dense<[1.0, 4.0, 0.0]> : vector<3xf32>
  %q = osl.div %u, %two : !osl.varying<f32>, f32 -> !osl.varying<f32>
  %t = osl.div %p, %k : !osl.varying<vector<3xf32>>, vector<3xf32> -> !osl.varying<vector<3xf32>>
  osl.output "q" = %q : !osl.varying<f32>
  osl.output "t" = %t : !osl.varying<vector<3xf32>>
  return
}

// -----

// Triples are lowered one component (one register) at a time.
// CHECK-LABEL: osl.shader_name = "triple_componentwise"
// CHECK-COUNT-3: math.sin %{{.+}} : vector<8xf32>
func.func @triple_componentwise() {
  %P = osl.global "P" : !osl.varying<vector<3xf32>>
  %s = osl.sin %P : !osl.varying<vector<3xf32>> -> !osl.varying<vector<3xf32>>
  osl.output "s" = %s : !osl.varying<vector<3xf32>>
  return
}

// -----

// Noise becomes a call of a library function built from its recipe,
// integer hashing and float math: no runtime call. Two calls of one recipe
// share it.
// CHECK-LABEL: osl.shader_name = "noise_is_a_library_function"
// CHECK: %[[A:.+]] = call @[[F:osl\.lib\.noise_perlin\.[0-9a-f]+]](%{{.+}}) {osl.keep_call} : (vector<3x8xf32>) -> vector<8xf32>
// CHECK: call @[[F]](%{{.+}}) {osl.keep_call}
// CHECK-NOT: call @osl.lib
// CHECK: func.func private @[[F]](%{{.+}}: vector<3x8xf32>) -> vector<8xf32>
// CHECK-SAME: osl.library_recipe = "noise perlin width 8 (!osl.varying<vector<3xf32>>) -> !osl.varying<f32>"
// CHECK: arith.xori %{{.+}}, %{{.+}} : vector<8xi32>
// CHECK-NOT: func.func private @osl.lib
// ASSUMED-LABEL: osl.shader_name = "noise_is_a_library_function"
// ASSUMED: func.func private @osl.lib.noise_perlin.{{[0-9a-f]+}}(vector<3x8xf32>) -> vector<8xf32>
// ASSUMED-NOT: arith.xori
func.func @noise_is_a_library_function() {
  %P = osl.global "P" : !osl.varying<vector<3xf32>>
  %n = osl.noise perlin(%P) : (!osl.varying<vector<3xf32>>) -> !osl.varying<f32>
  %m = osl.noise perlin(%P) : (!osl.varying<vector<3xf32>>) -> !osl.varying<f32>
  %s = osl.add %n, %m : !osl.varying<f32>, !osl.varying<f32> -> !osl.varying<f32>
  osl.output "n" = %s : !osl.varying<f32>
  return
}

// -----

// A varying noise's uniform coordinate (a constant here) is broadcast before the
// call, so that the routine takes varying values only (the prebuilt
// library's signature). A call passing a constant may be inlined to fold
// it (osl-inline-library), so it is not kept a call, and the routine is
// built even where it is compiled already.
// CHECK-LABEL: osl.shader_name = "uniform_coordinate_broadcast_before_call"
// CHECK: %[[Y:.+]] = vector.broadcast %{{.+}} : f32 to vector<8xf32>
// CHECK: call @osl.lib.noise_perlin.{{[0-9a-f]+}}(%{{.+}}, %[[Y]]) : (vector<8xf32>, vector<8xf32>)
// CHECK: osl.library_recipe = "noise perlin width 8 (!osl.varying<f32>, !osl.varying<f32>) -> !osl.varying<f32>"
// CHECK-NOT: vector.broadcast %{{.+}} : f32 to vector<8xf32>
// CHECK: return
// ASSUMED-LABEL: osl.shader_name = "uniform_coordinate_broadcast_before_call"
// ASSUMED-NOT: osl.keep_call
// ASSUMED: func.func private @osl.lib.noise_perlin.{{[0-9a-f]+}}(%{{.+}}: vector<8xf32>, %{{.+}}: vector<8xf32>) -> vector<8xf32>
func.func @uniform_coordinate_broadcast_before_call() {
  %u = osl.global "u" : !osl.varying<f32>
  %y = arith.constant 0.5 : f32
  %n = osl.noise perlin(%u, %y) : (!osl.varying<f32>, f32) -> !osl.varying<f32>
  osl.output "n" = %n : !osl.varying<f32>
  return
}

// -----

// Cell and hash noise are small enough to inline anywhere: never kept a
// call, always built.
// ASSUMED-LABEL: osl.shader_name = "cell_noise_is_built"
// ASSUMED-NOT: osl.keep_call
// ASSUMED: func.func private @osl.lib.noise_cell.{{[0-9a-f]+}}(%{{.+}}: vector<8xf32>) -> vector<8xf32>
func.func @cell_noise_is_built() {
  %u = osl.global "u" : !osl.varying<f32>
  %n = osl.noise cell(%u) : (!osl.varying<f32>) -> !osl.varying<f32>
  osl.output "n" = %n : !osl.varying<f32>
  return
}

// -----

// A derivative taken through a noise that stays a call is differentiated
// by its dual routine (osl-derivatives), compiled too here: the routine is
// only declared. Along z, the routine's code is differentiated in place:
// it is built, compiled or not.
// ASSUMED-LABEL: osl.shader_name = "derivative_through_noise"
// ASSUMED: func.func private @osl.lib.noise_uperlin.{{[0-9a-f]+}}(vector<3x8xf32>) -> vector<8xf32>
func.func @derivative_through_noise() {
  %P = osl.global "P" : !osl.varying<vector<3xf32>>
  %n = osl.noise uperlin(%P) : (!osl.varying<vector<3xf32>>) -> !osl.varying<f32>
  %s = osl.mul %n, %n : !osl.varying<f32>, !osl.varying<f32> -> !osl.varying<f32>
  %d = osl.deriv x %s : !osl.varying<f32>
  osl.output "n" = %d : !osl.varying<f32>
  return
}

// -----

// ASSUMED-LABEL: osl.shader_name = "z_derivative_through_noise"
// ASSUMED-DAG: func.func private @osl.lib.noise_uperlin.{{[0-9a-f]+}}(%{{.+}}: vector<3x8xf32>) -> vector<8xf32>
// ASSUMED-DAG: func.func private @osl.lib.noise_perlin.{{[0-9a-f]+}}(vector<3x8xf32>) -> vector<8xf32>
func.func @z_derivative_through_noise() {
  %P = osl.global "P" : !osl.varying<vector<3xf32>>
  %n = osl.noise uperlin(%P) : (!osl.varying<vector<3xf32>>) -> !osl.varying<f32>
  %s = osl.mul %n, %n : !osl.varying<f32>, !osl.varying<f32> -> !osl.varying<f32>
  %d = osl.deriv z %s : !osl.varying<f32>
  %m = osl.noise perlin(%P) : (!osl.varying<vector<3xf32>>) -> !osl.varying<f32>
  %r = osl.add %d, %m : !osl.varying<f32>, !osl.varying<f32> -> !osl.varying<f32>
  osl.output "n" = %r : !osl.varying<f32>
  return
}

// -----

// OSL's Gabor noise ignores a 4th coordinate: the call of a point and a
// time is the 3D point's routine.
// CHECK-LABEL: osl.shader_name = "gabor_ignores_time"
// CHECK: call @osl.lib.noise_gabor.{{[0-9a-f]+}}(%{{[0-9]+}}, %{{.+}}) {osl.keep_call} : (vector<3x8xf32>, i32, f32, f32, f32, f32, f32, i32) -> vector<8xf32>
// CHECK: osl.library_recipe = "noise gabor width 8 (!osl.varying<vector<3xf32>>) -> !osl.varying<f32> derivs () anisotropic 0 filter operand"
func.func @gabor_ignores_time() {
  %P = osl.global "P" : !osl.varying<vector<3xf32>>
  %t = osl.global "time" : !osl.varying<f32>
  %n = osl.noise gabor(%P, %t) : (!osl.varying<vector<3xf32>>, !osl.varying<f32>) -> !osl.varying<f32>
  osl.output "n" = %n : !osl.varying<f32>
  return
}

// -----

// An int output's row holds its ints' bits: a float would round ints past
// 2^24 (hash values) before they are printed or written to an int TIFF.
// CHECK-LABEL: osl.shader_name = "int_output_as_bits"
// CHECK: arith.fptosi %{{.+}} : vector<8xf32> to vector<8xi32>
// CHECK: %[[I:.+]] = arith.select
// CHECK-NOT: arith.sitofp
// CHECK: %[[BITS:.+]] = llvm.bitcast %[[I]] : vector<8xi32> to vector<8xf32>
// CHECK: llvm.store %[[BITS]]
func.func @int_output_as_bits() {
  %u = osl.global "u" : !osl.varying<f32>
  %i = osl.convert %u : !osl.varying<f32> -> !osl.varying<i32>
  osl.output "i" = %i : !osl.varying<i32>
  return
}

// -----

// Masked loops: scf.while carries vector types, osl.any becomes an OR
// reduction over the lanes.
// CHECK-LABEL: osl.shader_name = "masked_loop"
// CHECK: scf.while (%{{.+}} = %{{.+}}, %{{.+}} = %{{.+}}) : (vector<8xf32>, vector<8xi1>) -> (vector<8xf32>, vector<8xi1>)
// CHECK: vector.reduction <or>, %{{.+}} : vector<8xi1> into i1
func.func @masked_loop() {
  %u = osl.global "u" : !osl.varying<f32>
  %m = osl.batch_mask : !osl.varying<i1>
  %one = arith.constant 1.0 : f32
  %r:2 = scf.while (%x = %u, %mask = %m) : (!osl.varying<f32>, !osl.varying<i1>) -> (!osl.varying<f32>, !osl.varying<i1>) {
    %c = osl.cmp lt, %x, %one : !osl.varying<f32>, f32 -> !osl.varying<i1>
    %still = osl.and %mask, %c : !osl.varying<i1>, !osl.varying<i1> -> !osl.varying<i1>
    %any = osl.any %still : !osl.varying<i1>
    scf.condition(%any) %x, %still : !osl.varying<f32>, !osl.varying<i1>
  } do {
  ^bb0(%x: !osl.varying<f32>, %mask: !osl.varying<i1>):
    %x2 = osl.add %x, %x : !osl.varying<f32>, !osl.varying<f32> -> !osl.varying<f32>
    %keep = osl.select %mask, %x2, %x : !osl.varying<i1>, !osl.varying<f32>, !osl.varying<f32> -> !osl.varying<f32>
    scf.yield %keep, %mask : !osl.varying<f32>, !osl.varying<i1>
  }
  osl.output "x" = %r#0 : !osl.varying<f32>
  return
}

// -----

// Transforms between named spaces multiply by constant matrices.
// CHECK-LABEL: osl.shader_name = "transform_to_object"
// CHECK-COUNT-9: arith.mulf
func.func @transform_to_object() {
  %P = osl.global "P" : !osl.varying<vector<3xf32>>
  %t = osl.transform "common" to "object" point %P : !osl.varying<vector<3xf32>> -> !osl.varying<vector<3xf32>>
  osl.output "t" = %t : !osl.varying<vector<3xf32>>
  return
}

// -----

// logb reads the exponent bits of max(|x|, FLT_MIN): exact at powers of
// two, and -126 for 0 as in OSL.
// CHECK-LABEL: osl.shader_name = "logb_from_bits"
// CHECK: arith.bitcast %{{.+}} : vector<8xf32> to vector<8xi32>
// CHECK: arith.shrui
// CHECK: arith.sitofp
func.func @logb_from_bits() {
  %u = osl.global "u" : !osl.varying<f32>
  %l = osl.logb %u : !osl.varying<f32> -> !osl.varying<f32>
  osl.output "l" = %l : !osl.varying<f32>
  return
}

// -----

// Periodic noise (pnoise): the coordinates, then one period each.
// CHECK-LABEL: osl.shader_name = "periodic_noise"
// CHECK-NOT: osl.noise
// CHECK: arith.xori %{{.+}}, %{{.+}} : vector<8xi32>
func.func @periodic_noise() {
  %P = osl.global "P" : !osl.varying<vector<3xf32>>
  %per = arith.constant dense<[4.0, 3.0, 5.0]> : vector<3xf32>
  %n = osl.noise perlin(%P, %per) {periodic} : (!osl.varying<vector<3xf32>>, vector<3xf32>) -> !osl.varying<f32>
  osl.output "n" = %n : !osl.varying<f32>
  return
}

// -----

// blackbody reads its per-space table (the 5th root of the color at
// nonlinearly spaced temperatures) with a gather per lane; lanes at 12000 K
// and above integrate Planck's law over the 81 CIE samples, in a loop that
// runs only when some lane of the batch needs it. The result has no
// derivative (as in OSL).
// CHECK-LABEL: llvm.mlir.global internal constant @osl_planck_scale
// CHECK: llvm.mlir.global internal constant @osl_blackbody_r_Rec709
// CHECK-LABEL: osl.shader_name = "blackbody_varying"
// CHECK: llvm.getelementptr %{{.+}}[%{{.+}}] : (!llvm.ptr, vector<8xi32>) -> !llvm.vec<8 x ptr>, f32
// CHECK: llvm.intr.masked.gather %{{.+}} {alignment = 4 : i32, osl.no_derivative} : (!llvm.vec<8 x ptr>, vector<8xi1>, vector<8xf32>) -> vector<8xf32>
// CHECK: %[[HOT:.+]] = vector.reduction <or>, %{{.+}} : vector<8xi1> into i1
// CHECK: scf.if %[[HOT]] -> (vector<8xf32>, vector<8xf32>, vector<8xf32>)
// CHECK: scf.for %{{.+}} = %{{.+}} to %c81
// CHECK: llvm.load %{{.+}} {alignment = 4 : i64, osl.no_derivative} : !llvm.ptr -> f32
// CHECK: math.expm1 %{{.+}} : vector<8xf32>
// CHECK: arith.select %{{.+}} {osl.dual_rule = "none"} : vector<8xi1>, vector<8xf32>
func.func @blackbody_varying() {
  %u = osl.global "u" : !osl.varying<f32>
  %c = osl.blackbody "Rec709" %u : !osl.varying<f32> -> !osl.varying<vector<3xf32>>
  osl.output "C" = %c : !osl.varying<vector<3xf32>>
  return
}

// -----

// A uniform temperature stays scalar: plain loads, and the spectrum loop
// is guarded by the scalar condition itself.
// CHECK-LABEL: osl.shader_name = "blackbody_uniform"
// CHECK: llvm.load %{{.+}} {alignment = 4 : i64, osl.no_derivative} : !llvm.ptr -> f32
// CHECK-NOT: vector.reduction
// CHECK: scf.if %{{.+}} -> (f32, f32, f32)
func.func @blackbody_uniform() {
  %t = arith.constant 15000.0 : f32
  %c = osl.blackbody "ACEScg" %t : f32 -> vector<3xf32>
  osl.output "C" = %c : vector<3xf32>
  return
}

// -----

// wavelength_color interpolates the CIE observer between 5 nm samples and
// is black outside 380..780 nm.
// CHECK-LABEL: osl.shader_name = "wavelength_color"
// CHECK: llvm.intr.masked.gather
// CHECK: arith.select %{{.+}} {osl.dual_rule = "none"} : vector<8xi1>, vector<8xf32>
// CHECK-NOT: scf.if
func.func @wavelength_color() {
  %u = osl.global "u" : !osl.varying<f32>
  %c = osl.wavelength_color "Rec709" %u : !osl.varying<f32> -> !osl.varying<vector<3xf32>>
  osl.output "C" = %c : !osl.varying<vector<3xf32>>
  return
}

// -----

// transformc and luminance are straight-line lane arithmetic: hsv picks
// its sextant with selects, luminance is a dot with the space's Y row.
// CHECK-LABEL: osl.shader_name = "transformc_luminance"
// CHECK: math.floor %{{.+}} : vector<8xf32>
// CHECK: arith.cmpf olt, %{{.+}}, %{{.+}} : vector<8xf32>
// CHECK: arith.constant dense<0.2125{{[0-9]*}}> : vector<8xf32>
// CHECK-NOT: scf.if
// CHECK-NOT: llvm.intr.masked.gather
func.func @transformc_luminance() {
  %P = osl.global "P" : !osl.varying<vector<3xf32>>
  %c = osl.transformc "hsv" to "rgb" in "Rec709" %P : !osl.varying<vector<3xf32>> -> !osl.varying<vector<3xf32>>
  %l = osl.luminance "Rec709" %c : !osl.varying<vector<3xf32>> -> !osl.varying<f32>
  osl.output "L" = %l : !osl.varying<f32>
  return
}

// -----

// osl.texture: per-point values go to rows of W floats in a block on the
// stack (allocated once, in the entry block), the runtime looks up the
// lanes of the mask, and the result rows are read back; the uniform
// choices become the file's address and OpenImageIO's wrap code (clamp is
// 2, black 1). A 2D lookup's result rows are marked with their row, where
// osl-derivatives finds their slopes (kTextureDsRow...).
// CHECK-LABEL: llvm.func @osl_rt_texture(!llvm.ptr, !llvm.ptr, !llvm.ptr, i32, i32, i32, i32, i32, i32, i32, i32, !llvm.ptr, i32, i32)
// CHECK-LABEL: osl.shader_name = "texture_lookup"
// CHECK: %[[BLOCK:.+]] = llvm.alloca %{{.+}} x i32 {alignment = 64 : i64}
// CHECK: llvm.store %{{.+}}, %{{.+}} {alignment = 4 : i64} : vector<8xf32>, !llvm.ptr
// CHECK: %[[WHERE:.+]] = llvm.mlir.addressof @osl_string_{{[0-9]+}} : !llvm.ptr
// CHECK: %[[FILE:.+]] = llvm.mlir.addressof @osl_string_{{[0-9]+}} : !llvm.ptr
// CHECK: arith.constant 2 : i32
// CHECK: %[[S:.+]] = llvm.select %{{.+}}, %{{.+}}, %{{.+}} : i1, i32
// CHECK: %[[T:.+]] = llvm.select
// CHECK: %[[R:.+]] = llvm.select
// CHECK: %[[BITS:.+]] = llvm.bitcast %{{.+}} : vector<8xi1> to i8
// CHECK: %[[MASK:.+]] = arith.extui %[[BITS]] : i8 to i32
// CHECK: llvm.call @osl_rt_texture(%[[WHERE]], %[[FILE]], %{{[^,]+}}, %{{[^,]+}}, %{{[^,]+}}, %{{[^,]+}}, %[[S]], %[[T]], %[[R]], %{{[^,]+}}, %{{[^,]+}}, %[[BLOCK]], %{{[^,]+}}, %[[MASK]])
// CHECK: llvm.load %{{.+}} {alignment = 4 : i64, osl.texture_result_row = 23 : i64} : !llvm.ptr -> vector<8xf32>
func.func @texture_lookup() {
  %u = osl.global "u" : !osl.varying<f32>
  %v = osl.global "v" : !osl.varying<f32>
  %one = arith.constant 1.0 : f32
  %zero = arith.constant 0.0 : f32
  %c0 = arith.constant 0 : i32
  %c1 = arith.constant 1 : i32
  %r, %a, %err = osl.texture texture(%u, %v) derivs(%zero, %zero, %zero, %zero) options(%zero, %zero, %zero, %one, %one, %one, %zero, %one, %zero, %zero, %zero) channel %c0 subimage %c0 choices(%c0, %c1, %c1, %c1, %c0, %c0) {candidates = [["ramp.tx"], ["clamp", "black"], ["clamp", "black"], ["clamp", "black"], ["smartcubic"], [""]], nchannels = 3 : i32} : (!osl.varying<f32>, !osl.varying<f32>) (f32, f32, f32, f32) (f32, f32, f32, f32, f32, f32, f32, f32, f32, f32, f32) i32, i32(i32, i32, i32, i32, i32, i32) -> !osl.varying<vector<3xf32>>, !osl.varying<f32>, !osl.varying<i32>
  osl.output "C" = %r : !osl.varying<vector<3xf32>>
  return
}

// -----

// Gabor noise: the 27 cells around the point are one loop; each cell's
// Poisson count and then its impulses are while loops that run until no
// lane has work left (counts differ per lane). The cell's generator
// multiplies by 3039177861 (-1255789435 as i32). Without derivatives of the
// point nothing of the filter is built (no 1e-6 test of |Dx P x Dy P|^2).
// CHECK-LABEL: osl.shader_name = "gabor_noise"
// CHECK-NOT: osl.noise
// CHECK-NOT: 9.99999997E-7
// CHECK: scf.for %{{.+}} = %{{.+}} to %{{.+}} step %{{.+}} iter_args(%{{.+}} = %{{.+}}) -> (vector<8xf32>)
// CHECK: %[[M:.+]] = arith.constant dense<-1255789435> : vector<8xi32>
// CHECK: arith.muli %{{.+}}, %[[M]] : vector<8xi32>
// CHECK: scf.while
// CHECK: %[[ANY:.+]] = vector.reduction <or>, %{{.+}} : vector<8xi1> into i1
// CHECK: scf.condition(%[[ANY]])
// CHECK: scf.while
// CHECK: vector.reduction <or>
// CHECK-NOT: 9.99999997E-7
// W16: scf.while {{.+}} -> (vector<16xi32>, vector<16xf32>, vector<16xi32>, vector<16xi1>)
func.func @gabor_noise() {
  %P = osl.global "P" : !osl.varying<vector<3xf32>>
  %n = osl.noise gabor(%P) : (!osl.varying<vector<3xf32>>) -> !osl.varying<f32>
  osl.output "n" = %n : !osl.varying<f32>
  return
}

// -----

// osl.first_lane: the lowest set bit of the mask picks the lane.
// CHECK-LABEL: osl.shader_name = "first_lane"
// CHECK: %[[BITS:.+]] = llvm.bitcast %{{.+}} : vector<8xi1> to i8
// CHECK: %[[WIDE:.+]] = arith.extui %[[BITS]] : i8 to i32
// CHECK: %[[LEAD:.+]] = "llvm.intr.cttz"(%[[WIDE]]) <{is_zero_poison = false}> : (i32) -> i32
// CHECK: vector.extractelement %{{.+}}[%[[LEAD]] : i32] : vector<8xf32>
func.func @first_lane() {
  %u = osl.global "u" : !osl.varying<f32>
  %m = osl.batch_mask : !osl.varying<i1>
  %f = osl.first_lane %u, %m : !osl.varying<f32>, !osl.varying<i1> -> f32
  osl.output "f" = %f : f32
  return
}

// -----

// int / and % of varying values by a uniform divisor known only at run
// time: no per-lane division (x86 has no vector one); the divisor's
// multiplier is one scalar division, each lane a multiply-high and shifts.
// CHECK-LABEL: osl.shader_name = "int_division_by_uniform"
// CHECK-NOT: arith.divsi %{{.+}} : vector<8xi32>
// CHECK: arith.divui %{{.+}}, %{{.+}} : i64
// CHECK: arith.mului_extended %{{.+}}, %{{.+}} : vector<8xi32>
// CHECK-NOT: arith.remsi %{{.+}} : vector<8xi32>
// CHECK: arith.mului_extended %{{.+}}, %{{.+}} : vector<8xi32>
// CHECK-NOT: arith.divsi %{{.+}} : vector<8xi32>
func.func @int_division_by_uniform() {
  %u = osl.global "u" : !osl.varying<f32>
  %m = osl.batch_mask : !osl.varying<i1>
  %big = arith.constant 1.0e+06 : f32
  %s = osl.mul %u, %big : !osl.varying<f32>, f32 -> !osl.varying<f32>
  %n = osl.convert %s : !osl.varying<f32> -> !osl.varying<i32>
  %d = osl.first_lane %n, %m : !osl.varying<i32>, !osl.varying<i1> -> i32
  %q = osl.div %n, %d : !osl.varying<i32>, i32 -> !osl.varying<i32>
  %r = osl.mod %n, %d : !osl.varying<i32>, i32 -> !osl.varying<i32>
  osl.output "q" = %q : !osl.varying<i32>
  osl.output "r" = %r : !osl.varying<i32>
  return
}

// -----

// osl.table_read: the table is one constant global; a varying index reads
// it with one gather, a uniform one with one load.
// (The module's globals print before its function.)
// CHECK: llvm.mlir.global internal constant @osl_table_0(dense<[2, 3, 5, 7, 11, 13, 17, 19]> : tensor<8xi32>)
// CHECK-NOT: @osl_table_1
// CHECK-LABEL: osl.shader_name = "table_read"
// CHECK: llvm.intr.masked.gather {{.+}} : (!llvm.vec<8 x ptr>, vector<8xi1>, vector<8xi32>) -> vector<8xi32>
// CHECK: llvm.load {{.+}} : !llvm.ptr -> i32
func.func @table_read() {
  %u = osl.global "u" : !osl.varying<f32>
  %m = osl.batch_mask : !osl.varying<i1>
  %eight = arith.constant 8.0 : f32
  %s = osl.mul %u, %eight : !osl.varying<f32>, f32 -> !osl.varying<f32>
  %i = osl.convert %s : !osl.varying<f32> -> !osl.varying<i32>
  %p = osl.table_read dense<[2, 3, 5, 7, 11, 13, 17, 19]> : tensor<8xi32>[%i] : !osl.varying<i32> -> !osl.varying<i32>
  %j = osl.first_lane %i, %m : !osl.varying<i32>, !osl.varying<i1> -> i32
  %q = osl.table_read dense<[2, 3, 5, 7, 11, 13, 17, 19]> : tensor<8xi32>[%j] : i32 -> i32
  osl.output "p" = %p : !osl.varying<i32>
  osl.output "q" = %q : i32
  return
}

// -----

// With Dx/Dy of the point, lanes where |Dx P x Dy P|^2 >= 1e-6 (and
// do_filter != 0, uniform) filter their kernels. A color result evaluates
// three times (seeds 0, 1, 2: three cell loops).
// CHECK-LABEL: osl.shader_name = "gabor_filtered_color"
// CHECK: arith.cmpi ne, %{{.+}}, %{{.+}} : i32
// CHECK: %[[TINY:.+]] = arith.constant dense<9.99999997E-7> : vector<8xf32>
// CHECK: arith.cmpf uge, %{{.+}}, %[[TINY]] : vector<8xf32>
// CHECK-COUNT-3: scf.for
// CHECK-NOT: scf.for
func.func @gabor_filtered_color() {
  %P = osl.global "P" : !osl.varying<vector<3xf32>>
  %filter = arith.constant 1 : i32
  %dx = osl.deriv x %P : !osl.varying<vector<3xf32>>
  %dy = osl.deriv y %P : !osl.varying<vector<3xf32>>
  %c = osl.noise gabor(%P) derivs(%dx, %dy : !osl.varying<vector<3xf32>>, !osl.varying<vector<3xf32>>) do_filter(%filter : i32) : (!osl.varying<vector<3xf32>>) -> !osl.varying<vector<3xf32>>
  osl.output "c" = %c : !osl.varying<vector<3xf32>>
  return
}

// -----

// osl.string_call: each operand's lanes are a row of 32-bit values in a
// block on the stack (a uniform operand is broadcast), the runtime runs
// the active lanes and the result row is read back. A compile-time string
// is interned by the first batch, which keeps its handle in a slot of the
// kernel's; a call on uniform operands is one lane.
// CHECK-LABEL: llvm.func @osl_rt_string_call(!llvm.ptr, i32, !llvm.ptr, !llvm.ptr, i32, i32)
// CHECK: llvm.mlir.global internal @[[SLOT:osl_string_[0-9]+_handle]](-1 : i32)
// CHECK-LABEL: llvm.func @osl_rt_string_intern_cached(!llvm.ptr, !llvm.ptr) -> i32
// CHECK-LABEL: osl.shader_name = "string_call"
// CHECK: %[[STOF:.+]] = llvm.alloca %{{.+}} x i32 {alignment = 64 : i64}
// CHECK: %[[FORMAT:.+]] = llvm.alloca %{{.+}} x i32 {alignment = 64 : i64}
// CHECK: %[[STRLEN:.+]] = llvm.alloca %{{.+}} x i32 {alignment = 64 : i64}
// CHECK: %[[SLOTADDR:.+]] = llvm.mlir.addressof @[[SLOT]] : !llvm.ptr
// CHECK: %[[PRE:.+]] = llvm.call @osl_rt_string_intern_cached(%{{.+}}, %[[SLOTADDR]]) : (!llvm.ptr, !llvm.ptr) -> i32
// CHECK: llvm.store %[[PRE]], %{{.+}} {alignment = 4 : i64} : i32, !llvm.ptr
// CHECK: %[[ONE:.+]] = arith.constant 1 : i32
// CHECK: llvm.call @osl_rt_string_call(%{{.+}}, %{{.+}}, %{{.+}}, %[[STRLEN]], %[[ONE]], %{{.+}})
// CHECK: llvm.load %{{.+}} {alignment = 4 : i64, osl.no_derivative} : !llvm.ptr -> i32
// CHECK: %[[PRES:.+]] = vector.broadcast %[[PRE]] : i32 to vector<8xi32>
// CHECK: llvm.store %[[PRES]], %{{.+}} {alignment = 4 : i64} : vector<8xi32>, !llvm.ptr
// CHECK: llvm.store %{{.+}}, %{{.+}} {alignment = 4 : i64} : vector<8xf32>, !llvm.ptr
// CHECK: %[[BITS:.+]] = llvm.bitcast %{{.+}} : vector<8xi1> to i8
// CHECK: %[[MASK:.+]] = arith.extui %[[BITS]] : i8 to i32
// CHECK: llvm.call @osl_rt_string_call(%{{.+}}, %{{.+}}, %{{.+}}, %[[FORMAT]], %{{.+}}, %[[MASK]])
// CHECK: %[[S:.+]] = llvm.load %{{.+}} {alignment = 4 : i64, osl.no_derivative} : !llvm.ptr -> vector<8xi32>
// CHECK: llvm.store %[[S]]
// CHECK: llvm.call @osl_rt_string_call(%{{.+}}, %{{.+}}, %{{.+}}, %[[STOF]],
// CHECK: llvm.load %{{.+}} {alignment = 4 : i64, osl.no_derivative} : !llvm.ptr -> vector<8xf32>
// W16: llvm.load %{{.+}} {alignment = 4 : i64, osl.no_derivative} : !llvm.ptr -> vector<16xf32>
func.func @string_call() {
  %u = osl.global "u" : !osl.varying<f32>
  %pre = osl.string_constant "tile" : i32
  %n = osl.string_call "strlen" "s"(%pre) : (i32) -> i32
  %s = osl.string_call "format" "sf"(%pre, %u) : (i32, !osl.varying<f32>) -> !osl.varying<i32>
  %f = osl.string_call "stof" "s"(%s) : (!osl.varying<i32>) -> !osl.varying<f32>
  osl.output "f" = %f : !osl.varying<f32>
  osl.output "n" = %n : i32
  return
}

// -----

// getchar of one string for the whole batch at a varying index (a font's
// text): the string's bytes are asked for once and each active lane in the
// string gathers its byte, sign-extended; lanes outside it get 0.
// CHECK-LABEL: osl.shader_name = "getchar_uniform_string"
// CHECK-NOT: osl_rt_string_call(
// CHECK: %[[LEN:.+]] = llvm.alloca %{{.+}} x i32 {alignment = 64 : i64}
// CHECK: %[[BYTES:.+]] = llvm.call @osl_rt_string_bytes(%{{.+}}, %[[LEN]]) : (i32, !llvm.ptr) -> !llvm.ptr
// CHECK: %[[N:.+]] = llvm.load %[[LEN]] {alignment = 4 : i64} : !llvm.ptr -> i32
// CHECK: %[[NS:.+]] = vector.splat %[[N]] : vector<8xi32>
// CHECK: %[[LOW:.+]] = arith.cmpi sge, %[[I:.+]], %{{.+}} : vector<8xi32>
// CHECK: %[[HIGH:.+]] = arith.cmpi slt, %[[I]], %[[NS]] : vector<8xi32>
// CHECK: %[[IN:.+]] = arith.andi %[[LOW]], %[[HIGH]] : vector<8xi1>
// CHECK: %[[READ:.+]] = arith.andi %[[IN]], %{{.+}} : vector<8xi1>
// CHECK: %[[ADDRS:.+]] = llvm.getelementptr %[[BYTES]][%[[I]]] : (!llvm.ptr, vector<8xi32>) -> !llvm.vec<8 x ptr>, i8
// CHECK: %[[B:.+]] = llvm.intr.masked.gather %[[ADDRS]], %[[READ]], %{{.+}} {alignment = 1 : i32, osl.no_derivative} : (!llvm.vec<8 x ptr>, vector<8xi1>, vector<8xi8>) -> vector<8xi8>
// CHECK: arith.extsi %[[B]] : vector<8xi8> to vector<8xi32>
func.func @getchar_uniform_string() {
  %u = osl.global "u" : !osl.varying<f32>
  %text = osl.string_constant "Hello" : i32
  %i = osl.convert %u : !osl.varying<f32> -> !osl.varying<i32>
  %c = osl.string_call "getchar" "si"(%text, %i) : (i32, !osl.varying<i32>) -> !osl.varying<i32>
  osl.output "c" = %c : !osl.varying<i32>
  return
}

// -----

// osl.count_lanes: the set lanes of the mask, counted, go to the runtime.
// CHECK-LABEL: osl.shader_name = "count_lanes"
// CHECK: %[[BITS:.+]] = llvm.bitcast %{{.+}} : vector<8xi1> to i8
// CHECK: %[[WIDE:.+]] = arith.extui %[[BITS]] : i8 to i32
// CHECK: %[[N:.+]] = llvm.intr.ctpop(%[[WIDE]]) : (i32) -> i32
// CHECK: llvm.call @osl_rt_count_lanes(%[[N]]) : (i32) -> ()
func.func @count_lanes() {
  %m = osl.batch_mask : !osl.varying<i1>
  osl.count_lanes %m : !osl.varying<i1>
  return
}

// -----

// A closure is an i32 handle per lane: each closure op is one runtime call
// per batch on rows of 32-bit values, and Ci's handles are stored with
// their bits (a bitcast, not a conversion to float). A uniform closure
// takes one lane; the empty closure is handle 0.
// CHECK-LABEL: osl.shader_name = "closures"
// CHECK: llvm.call @osl_rt_closure_component(%{{.+}}, %{{.+}}, %{{.+}}, %{{.+}}) : (i32, !llvm.ptr, i32, i32) -> ()
// CHECK: llvm.load %{{.+}} : !llvm.ptr -> vector<8xi32>
// CHECK: llvm.call @osl_rt_closure_mul(%{{.+}}, %{{.+}}, %{{.+}}) : (!llvm.ptr, i32, i32) -> ()
// CHECK: llvm.call @osl_rt_closure_component
// CHECK: llvm.load %{{.+}} : !llvm.ptr -> i32
// CHECK: llvm.call @osl_rt_closure_add
// CHECK: arith.constant 0 : i32
// CHECK: arith.select %{{.+}}, %{{.+}}, %{{.+}} : vector<8xi1>, vector<8xi32>
// CHECK: llvm.bitcast %{{.+}} : vector<8xi32> to vector<8xf32>
// CHECK: llvm.store
func.func @closures() {
  %N = osl.global "N" : !osl.varying<vector<3xf32>>
  %u = osl.global "u" : !osl.varying<f32>
  %half = arith.constant 5.000000e-01 : f32
  %w = arith.constant dense<[1.0, 0.5, 0.25]> : vector<3xf32>
  %label = arith.constant 0 : i32
  %d = osl.closure_component "diffuse"(%N, %label) : (!osl.varying<vector<3xf32>>, i32) -> !osl.varying<!osl.closure>
  %dw = osl.closure_mul %d, %w : !osl.varying<!osl.closure>, vector<3xf32> -> !osl.varying<!osl.closure>
  %e = osl.closure_component "emission"() : () -> !osl.closure
  %sum = osl.closure_add %dw, %e : !osl.varying<!osl.closure>, !osl.closure -> !osl.varying<!osl.closure>
  %empty = osl.closure_empty : !osl.closure
  %c = osl.cmp gt, %u, %half : !osl.varying<f32>, f32 -> !osl.varying<i1>
  %ci = osl.select %c, %sum, %empty : !osl.varying<i1>, !osl.varying<!osl.closure>, !osl.closure -> !osl.varying<!osl.closure>
  osl.output "Ci" = %ci : !osl.varying<!osl.closure>
  return
}

// -----

// A float output stores one canonical NaN for every NaN (the widths must
// agree bit for bit, and scalar and vector code may leave different
// payloads), negative as x86's default NaN; int outputs and closures need
// no such step.
// CHECK-LABEL: osl.shader_name = "canonical_nan"
// CHECK: %[[NAN:.+]] = arith.constant dense<0xFFC00000> : vector<8xf32>
// CHECK: %[[ISNAN:.+]] = arith.cmpf uno, %[[V:.+]], %[[V]] : vector<8xf32>
// CHECK: %[[OUT:.+]] = arith.select %[[ISNAN]], %[[NAN]], %[[V]] : vector<8xi1>, vector<8xf32>
// CHECK: llvm.store %[[OUT]]
func.func @canonical_nan() {
  %u = osl.global "u" : !osl.varying<f32>
  %l = osl.log %u : !osl.varying<f32> -> !osl.varying<f32>
  osl.output "f" = %l : !osl.varying<f32>
  return
}

// -----

// An output inside a branch stores only the batch's active lanes.
// CHECK-LABEL: osl.shader_name = "output_in_branch"
// CHECK: %[[LANES:.+]] = arith.constant dense<[0, 1, 2, 3, 4, 5, 6, 7]> : vector<8xi32>
// CHECK: %[[N:.+]] = vector.broadcast %{{.+}} : i32 to vector<8xi32>
// CHECK: %[[MASK:.+]] = arith.cmpi slt, %[[LANES]], %[[N]] : vector<8xi32>
// CHECK: llvm.intr.masked.store %{{.+}}, %{{.+}}, %[[MASK]]
func.func @output_in_branch() {
  %u = osl.global "u" : !osl.varying<f32>
  %c = arith.constant true
  scf.if %c {
    osl.output "f" = %u : !osl.varying<f32>
  }
  return
}

// -----

// osl.print: every live point prints, so even uniform operands take W
// lanes (broadcast) and the mask is the live lanes and the print's own.
// CHECK-LABEL: llvm.func @osl_rt_print(!llvm.ptr, i32, !llvm.ptr, !llvm.ptr, i32, i32)
// CHECK-LABEL: osl.shader_name = "print"
// CHECK: %[[ROWS:.+]] = llvm.alloca %{{.+}} x i32 {alignment = 64 : i64}
// CHECK: vector.broadcast %{{.+}} : i32 to vector<8xi32>
// CHECK: %[[LIVE:.+]] = arith.cmpi slt
// CHECK: %[[BOTH:.+]] = arith.andi %[[LIVE]], %{{.+}} : vector<8xi1>
// CHECK: %[[BITS:.+]] = llvm.bitcast %[[BOTH]] : vector<8xi1> to i8
// CHECK: llvm.call @osl_rt_print(%{{.+}}, %{{.+}}, %{{.+}}, %[[ROWS]], %{{.+}}, %{{.+}})
func.func @print() {
  %u = osl.global "u" : !osl.varying<f32>
  %half = arith.constant 0.5 : f32
  %c = osl.cmp gt, %u, %half : !osl.varying<f32>, f32 -> !osl.varying<i1>
  %fmt = osl.string_constant "u = %g\n" : i32
  osl.print "printf" "sf"(%fmt, %u) mask %c : !osl.varying<i1> : i32, !osl.varying<f32>
  return
}

// -----

// A shader's own comparisons are unordered as in OSL's JIT (true with a
// NaN); library comparisons stay ordered, and != is unordered either way.
// Triples: == and-s the components, != or-s them.
// CHECK-LABEL: osl.shader_name = "unordered_comparisons"
// CHECK: arith.cmpf ult, %{{.+}}, %{{.+}} : vector<8xf32>
// CHECK: arith.cmpf olt, %{{.+}}, %{{.+}} : vector<8xf32>
// CHECK: arith.cmpf ueq
// CHECK: arith.cmpf ueq
// CHECK: arith.andi
// CHECK: arith.cmpf ueq
// CHECK: arith.andi
// CHECK: arith.cmpf une
// CHECK: arith.cmpf une
// CHECK: arith.ori
// CHECK: arith.cmpf une
// CHECK: arith.ori
func.func @unordered_comparisons() {
  %u = osl.global "u" : !osl.varying<f32>
  %p = osl.global "P" : !osl.varying<vector<3xf32>>
  %one = arith.constant 1.0 : f32
  %zero = arith.constant dense<0.0> : vector<3xf32>
  %a = osl.cmp lt, %u, %one {unordered} : !osl.varying<f32>, f32 -> !osl.varying<i1>
  %b = osl.cmp lt, %u, %one : !osl.varying<f32>, f32 -> !osl.varying<i1>
  %c = osl.cmp eq, %p, %zero {unordered} : !osl.varying<vector<3xf32>>, vector<3xf32> -> !osl.varying<i1>
  %d = osl.cmp ne, %p, %zero {unordered} : !osl.varying<vector<3xf32>>, vector<3xf32> -> !osl.varying<i1>
  %ab = osl.and %a, %b : !osl.varying<i1>, !osl.varying<i1> -> !osl.varying<i1>
  %cd = osl.and %c, %d : !osl.varying<i1>, !osl.varying<i1> -> !osl.varying<i1>
  %all = osl.and %ab, %cd : !osl.varying<i1>, !osl.varying<i1> -> !osl.varying<i1>
  %f = osl.convert %all : !osl.varying<i1> -> !osl.varying<f32>
  osl.output "r" = %f : !osl.varying<f32>
  return
}

// -----

// isconstant() is answered at lowering, after parameters are bound and
// constants folded: 1 for a constant, 0 for anything computed.
// CHECK-LABEL: osl.shader_name = "is_constant"
// CHECK-DAG: %[[ONE:.+]] = arith.constant 1 : i32
// CHECK-DAG: %[[ZERO:.+]] = arith.constant 0 : i32
// CHECK: arith.addi %[[ONE]], %[[ZERO]] : i32
func.func @is_constant() {
  %u = osl.global "u" : !osl.varying<f32>
  %two = arith.constant 2.0 : f32
  %a = osl.is_constant %two : f32
  %b = osl.is_constant %u : !osl.varying<f32>
  %sum = osl.add %a, %b : i32, i32 -> i32
  osl.output "x" = %sum : i32
  return
}

// -----

// Messages: the value's rows go to the runtime, getmessage reads them back
// with a found row after them, and the kernel forgets the last batch's
// messages on entry.
// CHECK-LABEL: osl.shader_name = "messages"
// CHECK: llvm.call @osl_rt_message_reset() : () -> ()
// CHECK: llvm.call @osl_rt_setmessage
// CHECK: llvm.call @osl_rt_getmessage
// CHECK: llvm.load %{{.+}} {alignment = 4 : i64, osl.no_derivative} : !llvm.ptr -> vector<8xi32>
// CHECK-COUNT-3: llvm.load %{{.+}} {alignment = 4 : i64, osl.no_derivative} : !llvm.ptr -> vector<8xf32>
func.func @messages() {
  %u = osl.global "u" : !osl.varying<f32>
  %c = osl.global "P" : !osl.varying<vector<3xf32>>
  osl.set_message "m" "color" "t"(%c) : !osl.varying<vector<3xf32>>
  %zero = arith.constant dense<0.0> : vector<3xf32>
  %found, %v = osl.get_message "m" "color" "t"(%zero) : (vector<3xf32>) -> (!osl.varying<i32>, !osl.varying<vector<3xf32>>)
  osl.output "o" = %v : !osl.varying<vector<3xf32>>
  return
}

// -----

// splineinverse is a call of a library function per basis, knot count and
// signature (its bisection is a loop around a whole spline evaluation).
// Each knot is an argument of its own, equal knots too, so that its code is
// the same whatever the knots and its recipe can name a prebuilt object:
// assumed compiled, the function is only declared. spline itself stays
// inline (constant knots fold into it).
// CHECK-LABEL: osl.shader_name = "splineinverse_call"
// CHECK: %[[K1:.+]] = arith.constant 2.500000e-01 : f32
// CHECK: call @[[INV:osl.lib.splineinverse_catmull_rom.[0-9a-f]+]](%{{.+}}, %{{.+}}, %[[K1]], %[[K1]], %{{.+}}, %{{.+}}) {osl.keep_call} : (vector<8xf32>, f32, f32, f32, f32, f32) -> vector<8xf32>
// CHECK-NOT: osl.library =
// CHECK: func.func private @[[INV]](
// CHECK-SAME: osl.library_recipe = "splineinverse catmull-rom width 8 (vector<8xf32>, f32, f32, f32, f32, f32) -> vector<8xf32>"
// CHECK: scf.while
// ASSUMED-LABEL: osl.shader_name = "splineinverse_call"
// ASSUMED: func.func private @osl.lib.splineinverse_catmull_rom.{{[0-9a-f]+}}(vector<8xf32>, f32, f32, f32, f32, f32) -> vector<8xf32>
// ASSUMED-NOT: scf.while
func.func @splineinverse_call() {
  %u = osl.global "u" : !osl.varying<f32>
  %k0 = arith.constant 0.0 : f32
  %k1 = arith.constant 0.25 : f32
  %k2 = arith.constant 0.75 : f32
  %k3 = arith.constant 1.0 : f32
  %x = osl.splineinverse catmullrom %u [%k0, %k1, %k1, %k2, %k3] : !osl.varying<f32>, f32, f32, f32, f32, f32 -> !osl.varying<f32>
  %y = osl.spline catmullrom %u [%k0, %k1, %k2, %k3] : !osl.varying<f32>, f32, f32, f32, f32 -> !osl.varying<f32>
  osl.output "x" = %x : !osl.varying<f32>
  osl.output "y" = %y : !osl.varying<f32>
  return
}

// -----

// A noise whose kind differs per point is one call of a noise_by_kind
// routine, which tests each kind some lane has and calls its routine:
// built when not compiled before, only declared when it is, with the
// routines its object calls listed and declared beside it. Its uniform
// operands (the zero derivatives here) are broadcast: one signature.
// CHECK-LABEL: osl.shader_name = "noise_by_kind_is_one_call"
// CHECK: call @[[BYKIND:osl.lib.noise_by_kind.[0-9a-f]+]](%{{.+}}, %{{.+}}, %{{.+}}, %{{.+}}) {osl.keep_call} : (vector<8xi32>, vector<3x8xf32>, vector<3x8xf32>, vector<3x8xf32>) -> vector<8xf32>
// CHECK: func.func private @[[BYKIND]](
// CHECK-SAME: osl.library_recipe = "noise by kind width 8 (!osl.varying<vector<3xf32>>) derivs (!osl.varying<vector<3xf32>>, !osl.varying<vector<3xf32>>) -> !osl.varying<f32>"
// CHECK: arith.cmpi eq, %arg0, %{{.+}} : vector<8xi32>
// CHECK: vector.reduction <or>
// CHECK: scf.if
// CHECK: call @osl.lib.noise_perlin.{{[0-9a-f]+}}(%arg1) {osl.keep_call}
// CHECK: arith.select
// CHECK-COUNT-6: call @osl.lib.noise_
// CHECK: return
// ASSUMED-LABEL: osl.shader_name = "noise_by_kind_is_one_call"
// ASSUMED: call @[[BYKIND:osl.lib.noise_by_kind.[0-9a-f]+]](
// ASSUMED: func.func private @[[BYKIND]](vector<8xi32>, vector<3x8xf32>, vector<3x8xf32>, vector<3x8xf32>) -> vector<8xf32>
// ASSUMED-SAME: osl.library_callees = [@[[PERLIN:osl.lib.noise_perlin.[0-9a-f]+]], @osl.lib.noise_uperlin.{{[0-9a-f]+}}, @osl.lib.noise_cell.{{[0-9a-f]+}}, @osl.lib.noise_hash.{{[0-9a-f]+}}, @osl.lib.noise_gabor.{{[0-9a-f]+}}, @osl.lib.noise_simplex.{{[0-9a-f]+}}, @osl.lib.noise_usimplex.{{[0-9a-f]+}}]
// ASSUMED: func.func private @[[PERLIN]](vector<3x8xf32>) -> vector<8xf32>
// ASSUMED-NOT: scf.if
func.func @noise_by_kind_is_one_call() {
  %P = osl.global "P" : !osl.varying<vector<3xf32>>
  %u = osl.global "u" : !osl.varying<f32>
  %k = osl.convert %u : !osl.varying<f32> -> !osl.varying<i32>
  %z = arith.constant dense<0.0> : vector<3xf32>
  %n = osl.noise_by_kind %k : !osl.varying<i32>(%P) derivs(%z, %z : vector<3xf32>, vector<3xf32>) : (!osl.varying<vector<3xf32>>) -> !osl.varying<f32>
  osl.output "n" = %n : !osl.varying<f32>
  return
}

// -----

// A derivative through a noise by kind goes through each kind's call:
// the tests are made in place, in the kernel (osl-derivatives then
// differentiates the calls one by one).
// ASSUMED-LABEL: osl.shader_name = "derivative_through_noise_by_kind"
// ASSUMED-NOT: noise_by_kind
// ASSUMED: vector.reduction <or>
// ASSUMED: scf.if
// ASSUMED: call @osl.lib.noise_perlin_periodic.{{[0-9a-f]+}}(
// ASSUMED-COUNT-4: call @osl.lib.noise_
// ASSUMED: osl.lane_deriv x
// ASSUMED-NOT: noise_by_kind
func.func @derivative_through_noise_by_kind() {
  %u = osl.global "u" : !osl.varying<f32>
  %k = osl.convert %u : !osl.varying<f32> -> !osl.varying<i32>
  %p = arith.constant 4.0 : f32
  %n = osl.noise_by_kind %k : !osl.varying<i32>(%u, %p) {periodic} : (!osl.varying<f32>, f32) -> !osl.varying<f32>
  %d = osl.deriv x %n : !osl.varying<f32>
  osl.output "n" = %d : !osl.varying<f32>
  return
}

// -----

// osl.pick of triples: one osl.lane_pick per component, over the elements'
// components; a uniform element is spread over the lanes of a varying pick.
// CHECK-LABEL: osl.shader_name = "pick_triples"
// CHECK: %[[CX:.+]] = vector.broadcast %{{.+}} : f32 to vector<8xf32>
// CHECK: %[[CY:.+]] = vector.broadcast %{{.+}} : f32 to vector<8xf32>
// CHECK: %[[CZ:.+]] = vector.broadcast %{{.+}} : f32 to vector<8xf32>
// CHECK: osl.lane_pick %[[I:.+]], [%{{.+}}, %[[CX]]] : vector<8xi32>, [vector<8xf32>, vector<8xf32>] -> vector<8xf32>
// CHECK: osl.lane_pick %[[I]], [%{{.+}}, %[[CY]]] :
// CHECK: osl.lane_pick %[[I]], [%{{.+}}, %[[CZ]]] :
// CHECK-NOT: osl.lane_pick
func.func @pick_triples() {
  %p = osl.global "P" : !osl.varying<vector<3xf32>>
  %u = osl.global "u" : !osl.varying<f32>
  %i = osl.convert %u : !osl.varying<f32> -> !osl.varying<i32>
  %c = arith.constant dense<[1.0, 2.0, 3.0]> : vector<3xf32>
  %r = osl.pick %i, [%p, %c] : !osl.varying<i32>, [!osl.varying<vector<3xf32>>, vector<3xf32>] -> !osl.varying<vector<3xf32>>
  osl.output "r" = %r : !osl.varying<vector<3xf32>>
  return
}
