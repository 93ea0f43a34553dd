// RUN: osl-opt %s -split-input-file --osl-outline-library=inline-ops=0 | FileCheck %s
// RUN: osl-opt %s -split-input-file --osl-outline-library=inline-ops=3 | FileCheck %s --check-prefix=SMALL
// RUN: osl-opt %s -split-input-file --osl-outline-library="inline-ops=3 inline-budget=4" \
// RUN:   | FileCheck %s --check-prefix=BUDGET
// RUN: osl-opt %s -split-input-file --osl-outline-library=outline=false | FileCheck %s --check-prefix=INLINE
// RUN: osl-opt %s -split-input-file --osl-outline-library="inline-ops=100 inline-always-ops=1" \
// RUN:   | FileCheck %s --check-prefix=FOLDS

// Two calls of one routine with one signature share one private function
// taking the outside values the region read; its body is the region's code.
// CHECK-LABEL: func.func @same_signature_shares
// CHECK: %[[A:.+]] = call @[[F:osl\.lib\.noise_perlin\.[0-9a-f]+]](%arg0) : (vector<4xf32>) -> vector<4xf32>
// CHECK: %[[B:.+]] = call @[[F]](%arg1) : (vector<4xf32>) -> vector<4xf32>
// CHECK: arith.addf %[[A]], %[[B]]
// CHECK-NOT: scf.execute_region
// CHECK: func.func private @[[F]](%[[X:.+]]: vector<4xf32>) -> vector<4xf32>
// CHECK-NEXT: %[[Y:.+]] = arith.mulf %[[X]], %[[X]]
// CHECK-NEXT: return %[[Y]]
// CHECK-NOT: func.func private
// INLINE-LABEL: func.func @same_signature_shares
// INLINE-NOT: scf.execute_region
// INLINE: arith.mulf %arg0, %arg0
// INLINE: arith.mulf %arg1, %arg1
// INLINE-NOT: call
func.func @same_signature_shares(%x: vector<4xf32>, %y: vector<4xf32>) -> vector<4xf32> {
  %a = scf.execute_region -> vector<4xf32> {
    %m = arith.mulf %x, %x : vector<4xf32>
    scf.yield %m : vector<4xf32>
  } {osl.library = "noise_perlin"}
  %b = scf.execute_region -> vector<4xf32> {
    %m = arith.mulf %y, %y : vector<4xf32>
    scf.yield %m : vector<4xf32>
  } {osl.library = "noise_perlin"}
  %s = arith.addf %a, %b : vector<4xf32>
  return %s : vector<4xf32>
}

// -----

// Another width (a uniform call: scalars) is another function.
// CHECK-LABEL: func.func @other_types_other_function
// CHECK: call @[[V:osl\.lib\.noise_perlin\.[0-9a-f]+]](%arg0) : (vector<4xf32>)
// CHECK: call @[[S:osl\.lib\.noise_perlin\.[0-9a-f]+]](%arg1) : (f32)
// CHECK-DAG: func.func private @[[V]](%{{.+}}: vector<4xf32>) -> vector<4xf32>
// CHECK-DAG: func.func private @[[S]](%{{.+}}: f32) -> f32
func.func @other_types_other_function(%x: vector<4xf32>, %y: f32) -> (vector<4xf32>, f32) {
  %a = scf.execute_region -> vector<4xf32> {
    %m = arith.mulf %x, %x : vector<4xf32>
    scf.yield %m : vector<4xf32>
  } {osl.library = "noise_perlin"}
  %b = scf.execute_region -> f32 {
    %m = arith.mulf %y, %y : f32
    scf.yield %m : f32
  } {osl.library = "noise_perlin"}
  return %a, %b : vector<4xf32>, f32
}

// -----

// One operand passed twice: the region reads one outside value where the
// other read two, so the bodies differ and so must the functions.
// CHECK-LABEL: func.func @aliased_operands
// CHECK: call @[[TWO:osl\.lib\.noise_uperlin\.[0-9a-f]+]](%arg0, %arg1) : (f32, f32) -> f32
// CHECK: call @[[ONE:osl\.lib\.noise_uperlin\.[0-9a-f]+]](%arg0) : (f32) -> f32
// CHECK-DAG: func.func private @[[TWO]](%{{.+}}: f32, %{{.+}}: f32) -> f32
// CHECK-DAG: func.func private @[[ONE]](%{{.+}}: f32) -> f32
func.func @aliased_operands(%x: f32, %y: f32) -> (f32, f32) {
  %a = scf.execute_region -> f32 {
    %m = arith.subf %x, %y : f32
    scf.yield %m : f32
  } {osl.library = "noise_uperlin"}
  %b = scf.execute_region -> f32 {
    %m = arith.subf %x, %x : f32
    scf.yield %m : f32
  } {osl.library = "noise_uperlin"}
  return %a, %b : f32, f32
}

// -----

// Two routines read the same two values in swapped roles: the same types,
// but not the same function.
// CHECK-LABEL: func.func @swapped_roles
// CHECK: call @[[F:osl\.lib\.noise_simplex\.[0-9a-f]+]](%arg0, %arg1)
// CHECK-NOT: call @[[F]]
// CHECK: call @osl.lib.noise_simplex
func.func @swapped_roles(%x: f32, %y: f32) -> (f32, f32) {
  %a = scf.execute_region -> f32 {
    %m = arith.subf %x, %y : f32
    scf.yield %m : f32
  } {osl.library = "noise_simplex"}
  %b = scf.execute_region -> f32 {
    %c = arith.constant 2.0 : f32
    %m = arith.mulf %y, %c : f32
    %n = arith.subf %m, %x : f32
    scf.yield %n : f32
  } {osl.library = "noise_simplex"}
  return %a, %b : f32, f32
}

// -----

// A region without the library attribute is not touched.
// CHECK-LABEL: func.func @plain_region
// CHECK: scf.execute_region
// CHECK-NOT: call
func.func @plain_region(%x: f32) -> f32 {
  %a = scf.execute_region -> f32 {
    %m = arith.mulf %x, %x : f32
    scf.yield %m : f32
  }
  return %a : f32
}

// -----

// The same ops on the same values with another constant (a builder may
// specialise on a constant option): another body, so another function,
// numbered after the first.
// CHECK-LABEL: func.func @other_constant_other_function
// CHECK: call @[[F:osl\.lib\.noise_gabor\.[0-9a-f]+]](%arg0)
// CHECK: call @[[F]].1(%arg0)
// CHECK: call @[[F]](%arg0)
// CHECK: func.func private @[[F]](
// CHECK: arith.constant 2.0
// CHECK: func.func private @[[F]].1(
// CHECK: arith.constant 3.0
func.func @other_constant_other_function(%x: f32) -> (f32, f32, f32) {
  %a = scf.execute_region -> f32 {
    %c = arith.constant 2.0 : f32
    %m = arith.mulf %x, %c : f32
    scf.yield %m : f32
  } {osl.library = "noise_gabor"}
  %b = scf.execute_region -> f32 {
    %c = arith.constant 3.0 : f32
    %m = arith.mulf %x, %c : f32
    scf.yield %m : f32
  } {osl.library = "noise_gabor"}
  %d = scf.execute_region -> f32 {
    %c = arith.constant 2.0 : f32
    %m = arith.mulf %x, %c : f32
    scf.yield %m : f32
  } {osl.library = "noise_gabor"}
  return %a, %b, %d : f32, f32, f32
}

// -----

// With inline-ops, a function without loops whose ops times its calls is
// at most that goes back in place (a call would spill more than it
// computes); a bigger one, one called more often, or one with a loop
// however small, stays a function.
// SMALL-LABEL: func.func @small_functions_inline
// SMALL-NOT: scf.execute_region
// SMALL: %[[M:.+]] = arith.mulf %arg0, %arg0 : f32
// SMALL: call @osl.lib.noise_perlin.{{[0-9a-f]+}}(%arg0)
// SMALL: call @osl.lib.noise_cell.{{[0-9a-f]+}}(%arg0, %arg1)
// SMALL: call @[[TWICE:osl\.lib\.noise_simplex\.[0-9a-f]+]](%arg0)
// SMALL: call @[[TWICE]](%arg0)
// SMALL: return %[[M]],
// SMALL-NOT: noise_hash
// SMALL: func.func private @osl.lib.noise_perlin
// SMALL: func.func private @osl.lib.noise_cell
// SMALL: scf.for
// SMALL: func.func private @[[TWICE]]
func.func @small_functions_inline(%x: f32, %n: index) -> (f32, f32, f32, f32, f32) {
  %a = scf.execute_region -> f32 {
    %m = arith.mulf %x, %x : f32
    scf.yield %m : f32
  } {osl.library = "noise_hash"}
  %b = scf.execute_region -> f32 {
    %m = arith.mulf %x, %x : f32
    %p = arith.addf %m, %x : f32
    %q = arith.mulf %p, %m : f32
    scf.yield %q : f32
  } {osl.library = "noise_perlin"}
  %c = scf.execute_region -> f32 {
    %c0 = arith.constant 0 : index
    %c1 = arith.constant 1 : index
    %r = scf.for %i = %c0 to %n step %c1 iter_args(%acc = %x) -> f32 {
      %s = arith.mulf %acc, %x : f32
      scf.yield %s : f32
    }
    scf.yield %r : f32
  } {osl.library = "noise_cell"}
  %d = scf.execute_region -> f32 {
    %m = arith.addf %x, %x : f32
    scf.yield %m : f32
  } {osl.library = "noise_simplex"}
  %e = scf.execute_region -> f32 {
    %m = arith.addf %x, %x : f32
    scf.yield %m : f32
  } {osl.library = "noise_simplex"}
  return %a, %b, %c, %d, %e : f32, f32, f32, f32, f32
}

// -----

// The copies share one budget per kernel, cheapest first: with
// inline-budget=4 the hash (2 ops, return included) goes in place, and then
// the cell noise (3) no longer fits, though alone it would.
// SMALL-LABEL: func.func @one_budget_per_kernel
// SMALL-NOT: call
// SMALL: return
// BUDGET-LABEL: func.func @one_budget_per_kernel
// BUDGET: %[[A:.+]] = call @osl.lib.noise_cell.{{[0-9a-f]+}}(%arg0)
// BUDGET: %[[B:.+]] = arith.addf %arg0, %arg0 : f32
// BUDGET: return %[[A]], %[[B]]
// BUDGET-NOT: noise_hash
// BUDGET: func.func private @osl.lib.noise_cell
func.func @one_budget_per_kernel(%x: f32) -> (f32, f32) {
  %a = scf.execute_region -> f32 {
    %m = arith.mulf %x, %x : f32
    %p = arith.addf %m, %x : f32
    scf.yield %p : f32
  } {osl.library = "noise_cell"}
  %b = scf.execute_region -> f32 {
    %m = arith.addf %x, %x : f32
    scf.yield %m : f32
  } {osl.library = "noise_hash"}
  return %a, %b : f32, f32
}

// -----

// Past inline-always-ops, a body goes back only where a copy gains: a call
// passing a constant (it folds) or a call in a loop (its spills repeat).
// A call made once with varying operands stays a call.
// FOLDS-LABEL: func.func @bigger_bodies_inline_where_they_gain
// FOLDS: %[[ONCE:.+]] = call @osl.lib.noise_perlin.{{[0-9a-f]+}}(%arg0)
// FOLDS: %[[C:.+]] = arith.mulf %arg0, %cst
// FOLDS: arith.addf %[[C]], %cst
// FOLDS: scf.for
// FOLDS-NOT: call
// FOLDS: arith.mulf %arg1, %arg1
// FOLDS: arith.addf
// FOLDS: scf.yield
// FOLDS-NOT: noise_simplex
// FOLDS-NOT: noise_cell
func.func @bigger_bodies_inline_where_they_gain(%x: f32, %y: f32) -> (f32, f32, f32) {
  %once = scf.execute_region -> f32 {
    %m = arith.mulf %x, %x : f32
    %a = arith.subf %m, %x : f32
    scf.yield %a : f32
  } {osl.library = "noise_perlin"}
  %two = arith.constant 2.0 : f32
  %constant = scf.execute_region -> f32 {
    %m = arith.mulf %x, %two : f32
    %a = arith.addf %m, %two : f32
    scf.yield %a : f32
  } {osl.library = "noise_simplex"}
  %c0 = arith.constant 0 : index
  %c1 = arith.constant 1 : index
  %c4 = arith.constant 4 : index
  %looped = scf.for %i = %c0 to %c4 step %c1 iter_args(%acc = %y) -> (f32) {
    %n = scf.execute_region -> f32 {
      %m = arith.mulf %y, %y : f32
      %a = arith.addf %m, %y : f32
      scf.yield %a : f32
    } {osl.library = "noise_cell"}
    %s = arith.addf %acc, %n : f32
    scf.yield %s : f32
  }
  return %once, %constant, %looped : f32, f32, f32
}

// -----

// A routine built from a recipe is a function already: a call its site
// keeps (osl.keep_call) stays a call at any inline-ops, and a declaration
// (a routine compiled before) is left alone; a small one's other calls go
// back in place as a region's would, and a routine no call is left to is
// erased.
// CHECK-LABEL: func.func @recipe_functions
// CHECK: call @osl.lib.noise_perlin.1(%arg0) {osl.keep_call}
// CHECK: call @osl.lib.noise_cell.1(%arg0)
// CHECK: call @osl.lib.noise_simplex.1(%arg0) {osl.keep_call}
// CHECK-DAG: func.func private @osl.lib.noise_perlin.1(%{{.+}}: f32) -> f32
// CHECK-DAG: func.func private @osl.lib.noise_cell.1(%{{.+}}: f32) -> f32
// CHECK-DAG: func.func private @osl.lib.noise_simplex.1(f32) -> f32
// CHECK-NOT: noise_hash
// SMALL-LABEL: func.func @recipe_functions
// SMALL: call @osl.lib.noise_perlin.1(%arg0) {osl.keep_call}
// SMALL-NOT: call @osl.lib.noise_cell
// SMALL: arith.addf %arg0, %arg0
// SMALL: call @osl.lib.noise_simplex.1(%arg0) {osl.keep_call}
// SMALL-DAG: func.func private @osl.lib.noise_perlin.1(
// SMALL-DAG: func.func private @osl.lib.noise_simplex.1(f32) -> f32
// SMALL-NOT: func.func private @osl.lib.noise_cell
// SMALL-NOT: noise_hash
// INLINE-LABEL: func.func @recipe_functions
// INLINE: arith.mulf %arg0, %arg0
// INLINE: arith.addf %arg0, %arg0
// INLINE: call @osl.lib.noise_simplex.1(%arg0) {osl.keep_call}
// FOLDS-LABEL: func.func @recipe_functions
// FOLDS: call @osl.lib.noise_cell.1(%arg0)
func.func @recipe_functions(%x: f32) -> (f32, f32, f32) {
  %a = call @osl.lib.noise_perlin.1(%x) {osl.keep_call} : (f32) -> f32
  %b = call @osl.lib.noise_cell.1(%x) : (f32) -> f32
  %c = call @osl.lib.noise_simplex.1(%x) {osl.keep_call} : (f32) -> f32
  return %a, %b, %c : f32, f32, f32
}
func.func private @osl.lib.noise_perlin.1(%x: f32) -> f32 attributes {osl.library_recipe = "p"} {
  %m = arith.mulf %x, %x : f32
  return %m : f32
}
func.func private @osl.lib.noise_cell.1(%x: f32) -> f32 attributes {osl.library_recipe = "c"} {
  %m = arith.addf %x, %x : f32
  return %m : f32
}
func.func private @osl.lib.noise_simplex.1(f32) -> f32 attributes {osl.library_recipe = "s"}
func.func private @osl.lib.noise_hash.1(%x: f32) -> f32 attributes {osl.library_recipe = "h"} {
  return %x : f32
}

// -----

// A routine compiled before whose object calls others (noise_by_kind)
// lists them: no call in the module is left to them, yet they stay
// declared, so that their objects are linked beside it.
// CHECK-LABEL: func.func @routine_callees_stay
// CHECK: call @osl.lib.noise_by_kind.1(%arg0, %arg1) {osl.keep_call}
// CHECK-DAG: func.func private @osl.lib.noise_perlin.2(f32) -> f32
// CHECK-DAG: func.func private @osl.lib.noise_cell.2(f32) -> f32
// CHECK-NOT: noise_hash
// SMALL-LABEL: func.func @routine_callees_stay
// INLINE-LABEL: func.func @routine_callees_stay
// FOLDS-LABEL: func.func @routine_callees_stay
func.func @routine_callees_stay(%k: i32, %x: f32) -> f32 {
  %a = call @osl.lib.noise_by_kind.1(%k, %x) {osl.keep_call} : (i32, f32) -> f32
  return %a : f32
}
func.func private @osl.lib.noise_by_kind.1(i32, f32) -> f32 attributes {osl.library_recipe = "k", osl.library_callees = [@osl.lib.noise_perlin.2, @osl.lib.noise_cell.2]}
func.func private @osl.lib.noise_perlin.2(f32) -> f32 attributes {osl.library_recipe = "p"}
func.func private @osl.lib.noise_cell.2(f32) -> f32 attributes {osl.library_recipe = "c"}
func.func private @osl.lib.noise_hash.2(f32) -> f32 attributes {osl.library_recipe = "h"}

// -----

// Without outlining (the double-precision reference), a routine whose
// code calls other routines comes in place with their code too: no call
// is left to a function with code.
// INLINE-LABEL: func.func @nested_routines_inline
// INLINE-NOT: call @
// INLINE: arith.mulf %arg0, %arg0
// INLINE-NOT: call @
// INLINE: return
// INLINE-NOT: func.func private @osl.lib
// CHECK-LABEL: func.func @nested_routines_inline
// SMALL-LABEL: func.func @nested_routines_inline
// FOLDS-LABEL: func.func @nested_routines_inline
// BUDGET-LABEL: func.func @nested_routines_inline
func.func @nested_routines_inline(%x: f32) -> f32 {
  %a = call @osl.lib.noise_by_kind.3(%x) {osl.keep_call} : (f32) -> f32
  return %a : f32
}
func.func private @osl.lib.noise_by_kind.3(%x: f32) -> f32 attributes {osl.library_recipe = "k3"} {
  %m = call @osl.lib.noise_perlin.3(%x) {osl.keep_call} : (f32) -> f32
  return %m : f32
}
func.func private @osl.lib.noise_perlin.3(%x: f32) -> f32 attributes {osl.library_recipe = "p3"} {
  %m = arith.mulf %x, %x : f32
  return %m : f32
}

