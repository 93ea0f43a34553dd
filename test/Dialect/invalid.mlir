// RUN: osl-opt %s -split-input-file -verify-diagnostics

func.func @add_mixes_float_and_int(%a: f32, %b: i32) {
  // expected-error @+1 {{operands must share one type accepted by this op}}
  %0 = osl.add %a, %b : f32, i32 -> f32
  return
}

// -----

func.func @sin_of_int(%a: i32) {
  // expected-error @+1 {{operands must share one type accepted by this op}}
  %0 = osl.sin %a : i32 -> i32
  return
}

// -----

func.func @result_type_differs(%a: f32) {
  // expected-error @+1 {{result type 'vector<3xf32>' must match operand type 'f32'}}
  %0 = osl.neg %a : f32 -> vector<3xf32>
  return
}

// -----

func.func @unknown_global() {
  // expected-error @+1 {{unknown shader global 'Q'}}
  %0 = osl.global "Q" : !osl.varying<f32>
  return
}

// -----

func.func @uniform_global() {
  // expected-error @+1 {{shader globals are varying}}
  %0 = osl.global "u" : f32
  return
}

// -----

func.func @global_wrong_shape() {
  // expected-error @+1 {{global 'P' has type vector<3xf32>}}
  %0 = osl.global "P" : !osl.varying<f32>
  return
}

// -----

// expected-error @+1 {{varying element must be f32, i32, i1, vector<3xf32> or !osl.closure, got 'f64'}}
func.func @varying_of_f64(%a: !osl.varying<f64>) {
  return
}

// -----

func.func @compare_unknown_predicate(%a: f32) {
  // expected-error @+1 {{invalid predicate attribute specification: "near"}}
  %0 = osl.cmp "near", %a, %a : f32, f32 -> i1
  return
}

// -----

func.func @select_condition_not_bool(%a: f32) {
  // expected-error @+1 {{operand #0 must be i1 or !osl.varying<i1>}}
  %0 = osl.select %a, %a, %a : f32, f32, f32 -> f32
  return
}

// -----

func.func @broadcast_to_uniform(%a: f32) {
  // expected-error @+1 {{turns a uniform T (or a varying one) into !osl.varying<T>}}
  %0 = osl.broadcast %a : f32 -> f32
  return
}

// -----

func.func @broadcast_to_other_type(%a: f32) {
  // expected-error @+1 {{turns a uniform T (or a varying one) into !osl.varying<T>}}
  %0 = osl.broadcast %a : f32 -> !osl.varying<i32>
  return
}

// -----

func.func @convert_triple_to_int(%a: vector<3xf32>) {
  // expected-error @+1 {{cannot convert 'vector<3xf32>' to 'i32'}}
  %0 = osl.convert %a : vector<3xf32> -> i32
  return
}

// -----

func.func @noise_unknown_name(%a: f32) {
  // expected-error @+1 {{invalid kind attribute specification: "pink"}}
  %0 = osl.noise "pink"(%a) : (f32) -> f32
  return
}

// -----

func.func @noise_bad_domain(%a: f32, %p: vector<3xf32>) {
  // expected-error @+1 {{domain must be (float), (float, float), (triple) or (triple, float)}}
  %0 = osl.noise perlin(%a, %p) : (f32, vector<3xf32>) -> f32
  return
}

// -----

func.func @transform_bad_kind(%p: vector<3xf32>) {
  // expected-error @+1 {{invalid kind attribute specification: "color"}}
  %0 = osl.transform "common" to "object" "color" %p : vector<3xf32> -> vector<3xf32>
  return
}

// -----

func.func @spline_too_few_knots(%x: f32, %k: f32) {
  // expected-error @+1 {{basis 'catmull-rom' needs at least 4 knots}}
  %0 = osl.spline catmullrom %x [%k, %k, %k] : f32, f32, f32, f32 -> f32
  return
}

// -----

func.func @spline_unknown_basis(%x: f32, %k: f32) {
  // expected-error @+1 {{invalid basis attribute specification: "cosine"}}
  %0 = osl.spline "cosine" %x [%k, %k, %k, %k] : f32, f32, f32, f32, f32 -> f32
  return
}

// -----

func.func @if_yields_wrong_type(%c: i1, %a: f32, %b: i32) {
  // expected-error @+1 {{along control flow edge from Region #1 to parent results: source type #0 'i32' should match input type #0 'f32'}}
  %0 = osl.if %c : i1 -> f32 {
    osl.yield %a : f32
  } else {
    osl.yield %b : i32
  }
  return
}

// -----

func.func @while_back_edge_count(%a: f32, %c: i1) {
  // expected-error @+1 {{region control flow edge from Region #1 to Region #0: source has 0 operands, but target successor needs 1}}
  %0 = osl.while (%a : f32) -> f32 cond {
  ^bb0(%x: f32):
    osl.condition %c : i1, %x : f32
  } do {
  ^bb0(%x: f32):
    osl.yield
  }
  return
}

// -----

func.func @periodic_noise_without_periods(%p: vector<3xf32>, %t: f32) {
  // expected-error @+1 {{periodic noise takes one period per coordinate, of its type}}
  %0 = osl.noise perlin(%p, %t) {periodic} : (vector<3xf32>, f32) -> f32
  return
}

// -----

func.func @luminance_loses_varying(%c: !osl.varying<vector<3xf32>>) {
  // expected-error @+1 {{result must be varying exactly when the operand is}}
  %0 = osl.luminance "Rec709" %c : !osl.varying<vector<3xf32>> -> f32
  return
}

// -----

func.func @transformc_without_space(%c: vector<3xf32>) {
  // expected-error @+1 {{color space names must not be empty}}
  %0 = osl.transformc "" to "hsv" in "Rec709" %c : vector<3xf32> -> vector<3xf32>
  return
}

// -----

func.func @options_on_perlin(%p: vector<3xf32>, %b: f32) {
  // expected-error @+1 {{only gabor noise takes options and derivatives}}
  %0 = osl.noise perlin(%p) bandwidth(%b : f32) : (vector<3xf32>) -> f32
  return
}

// -----

func.func @gabor_float_anisotropic(%p: vector<3xf32>, %m: f32) {
  // expected-error @+1 {{noise option 'anisotropic' has the wrong type 'f32'}}
  %0 = osl.noise gabor(%p) anisotropic(%m : f32) : (vector<3xf32>) -> f32
  return
}

// -----

func.func @gabor_one_deriv(%x: f32, %y: f32) {
  // expected-error @+1 {{derivs must be Dx then Dy of each point coordinate}}
  %0 = osl.noise gabor(%x, %y) derivs(%x, %y : f32, f32) : (f32, f32) -> f32
  return
}

// -----

func.func @gabor_deriv_of_wrong_type(%p: vector<3xf32>, %d: f32) {
  // expected-error @+1 {{derivs must be Dx then Dy of each point coordinate}}
  %0 = osl.noise gabor(%p) derivs(%d, %d : f32, f32) : (vector<3xf32>) -> f32
  return
}

// -----

func.func @texture_bad_kind(%s: !osl.varying<f32>) {
  %zero = arith.constant 0.0 : f32
  %c0 = arith.constant 0 : i32
  // expected-error @+1 {{invalid kind attribute specification: "4d"}}
  %r, %a, %err = osl.texture "4d"(%s, %s) derivs(%zero, %zero, %zero, %zero) options(%zero, %zero, %zero, %zero, %zero, %zero, %zero, %zero, %zero, %zero, %zero) channel %c0 subimage %c0 choices(%c0, %c0, %c0, %c0, %c0, %c0) {candidates = [["a.tx"], ["default"], ["default"], ["default"], ["smartcubic"], [""]], nchannels = 1 : i32} : (!osl.varying<f32>, !osl.varying<f32>) (f32, f32, f32, f32) (f32, f32, f32, f32, f32, f32, f32, f32, f32, f32, f32) i32, i32(i32, i32, i32, i32, i32, i32) -> !osl.varying<f32>, !osl.varying<f32>, !osl.varying<i32>
  return
}

// -----

func.func @string_call_unknown_function(%s: i32) {
  // expected-error @+1 {{unknown string function 'reverse'}}
  %0 = osl.string_call "reverse" "s"(%s) : (i32) -> i32
  return
}

// -----

func.func @gettextureinfo_floats_and_strings() {
  // expected-error @+1 {{answers with floats or with strings, not both}}
  %found, %v = osl.gettextureinfo "a.tx", "texturetype" {floats, strings} : i32, (f32)
  return
}

// -----

func.func @gettextureinfo_mixed_types() {
  // expected-error @+1 {{values must all be 'f32'}}
  %found, %v:2 = osl.gettextureinfo "a.tx", "averagecolor" {floats} : i32, (f32, i32)
  return
}

// -----

func.func @string_call_kinds_count(%s: i32) {
  // expected-error @+1 {{needs one kind letter per operand, got 'ss' for 1}}
  %0 = osl.string_call "strlen" "ss"(%s) : (i32) -> i32
  return
}

// -----

func.func @string_call_kinds_signature(%s: i32) {
  // expected-error @+1 {{operand kinds 'si' do not fit startswith's 'ss'}}
  %0 = osl.string_call "startswith" "si"(%s, %s) : (i32, i32) -> i32
  return
}

// -----

func.func @string_call_operand_type(%s: i32, %f: f32) {
  // expected-error @+1 {{operand 1 of kind 'i' must be 'i32'}}
  %0 = osl.string_call "getchar" "si"(%s, %f) : (i32, f32) -> i32
  return
}

// -----

func.func @string_call_result_type(%s: i32) {
  // expected-error @+1 {{result must be 'f32'}}
  %0 = osl.string_call "stof" "s"(%s) : (i32) -> i32
  return
}

// -----

// The loop's own checks run after its terminators verified (found by the
// osl-opt fuzzer: a condition without operands was read past its end).
func.func @while_condition_without_operands(%x: f32) {
  %r = osl.while (%x : f32) -> f32 cond {
  ^bb0(%a: f32):
    // expected-error @+1 {{expected 1 or more operands, but found 0}}
    "osl.condition"() : () -> ()
  } do {
  ^bb0(%a: f32):
    osl.yield %a : f32
  }
  return
}

// -----

func.func @unknown_closure(%n: vector<3xf32>) {
  // expected-error @+1 {{unknown closure 'velvet'}}
  %0 = osl.closure_component "velvet"(%n) : (vector<3xf32>) -> !osl.closure
  return
}

// -----

// Keyword parameters are operands too: dielectric_bsdf takes its 8
// positional parameters, then label, thinfilm_thickness and thinfilm_ior.
func.func @closure_operand_count(%n: vector<3xf32>) {
  // expected-error @+1 {{closure 'dielectric_bsdf' takes 11 operands (positional, then keywords), got 1}}
  %0 = osl.closure_component "dielectric_bsdf"(%n) : (vector<3xf32>) -> !osl.closure
  return
}

// -----

func.func @closure_operand_kind(%f: f32, %label: i32) {
  // expected-error @+1 {{operand 0 of kind 'n' must be 'vector<3xf32>'}}
  %0 = osl.closure_component "diffuse"(%f, %label) : (f32, i32) -> !osl.closure
  return
}

// -----

func.func @closure_keyword_count(%n: vector<3xf32>) {
  // expected-error @+1 {{closure 'diffuse' takes 2 operands (positional, then keywords), got 1}}
  %0 = osl.closure_component "diffuse"(%n) : (vector<3xf32>) -> !osl.closure
  return
}

// -----

func.func @closure_weight_is_a_color(%c: !osl.closure, %f: f32) {
  // expected-error @+1 {{operand #1 must be vector<3xf32> or !osl.varying<vector<3xf32>>}}
  %0 = osl.closure_mul %c, %f : !osl.closure, f32 -> !osl.closure
  return
}

// -----

func.func @print_unknown_stream(%s: i32) {
  // expected-error @+1 {{unknown print stream 'log'}}
  osl.print "log" "s"(%s) : i32
  return
}

// -----

func.func @print_fprintf_needs_file(%s: i32, %f: f32) {
  // expected-error @+1 {{operand kinds 'sf' must start with 'ss' for fprintf}}
  osl.print "fprintf" "sf"(%s, %f) : i32, f32
  return
}

// -----

func.func @print_operand_type(%s: i32, %f: f32) {
  // expected-error @+1 {{operand 1 of kind 'i' must be 'i32'}}
  osl.print "printf" "si"(%s, %f) : i32, f32
  return
}

// -----

// Closures compare for equality only.
func.func @closure_ordered_compare(%c: !osl.closure) {
  // expected-error @+1 {{compares two values of one type}}
  %0 = osl.cmp lt, %c, %c : !osl.closure, !osl.closure -> i1
  return
}

// -----

func.func @message_kinds(%f: f32) {
  // expected-error @+1 {{needs one kind letter per value}}
  osl.set_message "m" "float" "ff"(%f) : f32
  return
}

// -----

func.func @message_kind_type(%f: f32) {
  // expected-error @+1 {{value 0 of kind 'i' must be 'i32'}}
  osl.set_message "m" "int" "i"(%f) : f32
  return
}

// -----

func.func @message_results_varying(%f: f32) {
  // expected-error @+1 {{results must be the values' types, varying}}
  %found, %v = osl.get_message "m" "float" "f"(%f) : (f32) -> (!osl.varying<i32>, f32)
  return
}

// -----

// Before osl-varying-propagation a uniform value may flow into a varying
// slot: the control-flow edges compare base types.
func.func @if_uniform_into_varying(%c: !osl.varying<i1>, %a: f32, %b: !osl.varying<f32>) {
  // expected-error @+1 {{along control flow edge from Region #0 to parent results: source type #0 'i32' should match input type #0 '!osl.varying<f32>'}}
  %0 = osl.if %c : !osl.varying<i1> -> !osl.varying<f32> {
    %i = arith.constant 1 : i32
    osl.yield %i : i32
  } else {
    osl.yield %a : f32
  }
  return
}

// -----

func.func @table_read_uniform_result_of_varying_index(%i: !osl.varying<i32>) {
  // expected-error @+1 {{the result must be the table's element, varying as the index}}
  %0 = osl.table_read dense<[1, 2]> : tensor<2xi32>[%i] : !osl.varying<i32> -> i32
  return
}

// -----

func.func @table_read_f64(%i: i32) {
  // expected-error @+1 {{the table must be a non-empty 1-D list of f32 or i32}}
  %0 = osl.table_read dense<[1.0, 2.0]> : tensor<2xf64>[%i] : i32 -> f32
  return
}

// -----

func.func @noise_by_kind_float_kind(%k: f32, %p: vector<3xf32>) {
  // expected-error @+1 {{kind must be an i32}}
  %0 = osl.noise_by_kind %k : f32(%p) derivs(%p, %p : vector<3xf32>, vector<3xf32>) : (vector<3xf32>) -> f32
  return
}

// -----

func.func @noise_by_kind_without_derivs(%k: i32, %p: vector<3xf32>) {
  // expected-error @+1 {{derivs must be Dx then Dy of each point coordinate}}
  %0 = osl.noise_by_kind %k : i32(%p) : (vector<3xf32>) -> f32
  return
}

// -----

func.func @noise_by_kind_1d_with_derivs(%k: i32, %x: f32) {
  // expected-error @+1 {{a 1D noise takes no derivs}}
  %0 = osl.noise_by_kind %k : i32(%x) derivs(%x, %x : f32, f32) : (f32) -> f32
  return
}


// -----

func.func @pick_uniform_result_of_varying_index(%i: !osl.varying<i32>, %x: f32) {
  // expected-error @+1 {{the result must be varying when the index or an element is}}
  %0 = osl.pick %i, [%x, %x] : !osl.varying<i32>, [f32, f32] -> f32
  return
}

// -----

func.func @pick_mixed_elements(%i: i32, %x: f32, %n: i32) {
  // expected-error @+1 {{every element must be of the result's type}}
  %0 = osl.pick %i, [%x, %n] : i32, [f32, i32] -> f32
  return
}

// -----

// The fence is for the hash's i32 lanes: not floats, not triples.
func.func @codegen_fence_of_floats(%x: vector<8xf32>) {
  // expected-error @+1 {{operand #0 must be}}
  %0 = osl.codegen_fence %x : vector<8xf32>
  return
}

// -----

func.func @lane_pick_index_lanes(%i: vector<4xi32>, %x: vector<8xf32>) {
  // expected-error @+1 {{the index must be i32, a scalar or one per lane of the result}}
  %0 = osl.lane_pick %i, [%x, %x] : vector<4xi32>, [vector<8xf32>, vector<8xf32>] -> vector<8xf32>
  return
}

// -----

func.func @lane_pick_tensor_index(%i: tensor<8xi32>, %x: vector<8xf32>) {
  // expected-error @+1 {{the index must be i32, a scalar or one per lane of the result}}
  %0 = osl.lane_pick %i, [%x, %x] : tensor<8xi32>, [vector<8xf32>, vector<8xf32>] -> vector<8xf32>
  return
}

// -----

func.func @lane_pick_2d_lanes(%i: vector<2x4xi32>, %x: vector<2x4xf32>) {
  // expected-error @+1 {{the result must be f32, f64 or i32, or one 1-D vector of them}}
  %0 = osl.lane_pick %i, [%x, %x] : vector<2x4xi32>, [vector<2x4xf32>, vector<2x4xf32>] -> vector<2x4xf32>
  return
}
