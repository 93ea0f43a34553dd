// RUN: osl-opt %s -split-input-file --osl-inline-library=inline-ops=0 | FileCheck %s
// RUN: osl-opt %s -split-input-file --osl-inline-library=inline-ops=3 | FileCheck %s --check-prefix=SMALL
// RUN: osl-opt %s -split-input-file --osl-inline-library="inline-ops=3 inline-budget=4" \
// RUN:   | FileCheck %s --check-prefix=BUDGET
// RUN: osl-opt %s -split-input-file --osl-inline-library=keep-calls=false | FileCheck %s --check-prefix=INLINE
// RUN: osl-opt %s -split-input-file --osl-inline-library="inline-ops=100 inline-always-ops=1" \
// RUN:   | FileCheck %s --check-prefix=FOLDS

// With inline-ops, a function without loops whose ops (its return
// included) times its calls is at most that goes back in place (a call
// would spill more than it computes); a bigger one, one called more often,
// or one with a loop however small, stays a function. With inline-ops=0
// every call stays; with keep-calls=false none does.
// CHECK-LABEL: func.func @small_functions_inline
// CHECK: call @osl.lib.noise_hash.1(%arg0)
// CHECK: call @osl.lib.noise_perlin.1(%arg0)
// CHECK: call @osl.lib.noise_cell.1(%arg0, %arg1)
// CHECK: call @osl.lib.noise_simplex.1(%arg0)
// CHECK: call @osl.lib.noise_simplex.1(%arg0)
// CHECK-DAG: func.func private @osl.lib.noise_hash.1(
// CHECK-DAG: func.func private @osl.lib.noise_perlin.1(
// CHECK-DAG: func.func private @osl.lib.noise_cell.1(
// CHECK-DAG: func.func private @osl.lib.noise_simplex.1(
// SMALL-LABEL: func.func @small_functions_inline
// SMALL: %[[M:.+]] = arith.mulf %arg0, %arg0 : f32
// SMALL: call @osl.lib.noise_perlin.1(%arg0)
// SMALL: call @osl.lib.noise_cell.1(%arg0, %arg1)
// SMALL: call @osl.lib.noise_simplex.1(%arg0)
// SMALL: call @osl.lib.noise_simplex.1(%arg0)
// SMALL: return %[[M]],
// SMALL-NOT: noise_hash
// SMALL: func.func private @osl.lib.noise_perlin.1(
// SMALL: func.func private @osl.lib.noise_cell.1(
// SMALL: scf.for
// SMALL: func.func private @osl.lib.noise_simplex.1(
// INLINE-LABEL: func.func @small_functions_inline
// INLINE-NOT: call
// INLINE: scf.for
// INLINE-NOT: call
// INLINE: return
// INLINE-NOT: func.func private
func.func @small_functions_inline(%x: f32, %n: index) -> (f32, f32, f32, f32, f32) {
  %a = call @osl.lib.noise_hash.1(%x) : (f32) -> f32
  %b = call @osl.lib.noise_perlin.1(%x) : (f32) -> f32
  %c = call @osl.lib.noise_cell.1(%x, %n) : (f32, index) -> f32
  %d = call @osl.lib.noise_simplex.1(%x) : (f32) -> f32
  %e = call @osl.lib.noise_simplex.1(%x) : (f32) -> f32
  return %a, %b, %c, %d, %e : f32, f32, f32, f32, f32
}
func.func private @osl.lib.noise_hash.1(%x: f32) -> f32 attributes {osl.library_recipe = "h"} {
  %m = arith.mulf %x, %x : f32
  return %m : f32
}
func.func private @osl.lib.noise_perlin.1(%x: f32) -> f32 attributes {osl.library_recipe = "p"} {
  %m = arith.mulf %x, %x : f32
  %p = arith.addf %m, %x : f32
  %q = arith.mulf %p, %m : f32
  return %q : f32
}
func.func private @osl.lib.noise_cell.1(%x: f32, %n: index) -> f32 attributes {osl.library_recipe = "c"} {
  %c0 = arith.constant 0 : index
  %c1 = arith.constant 1 : index
  %r = scf.for %i = %c0 to %n step %c1 iter_args(%acc = %x) -> f32 {
    %s = arith.mulf %acc, %x : f32
    scf.yield %s : f32
  }
  return %r : f32
}
func.func private @osl.lib.noise_simplex.1(%x: f32) -> f32 attributes {osl.library_recipe = "s"} {
  %m = arith.addf %x, %x : f32
  return %m : f32
}

// -----

// The copies share one budget per kernel, cheapest first: with
// inline-budget=4 the hash (2 ops, return included) goes in place, and then
// the cell noise (3) no longer fits, though alone it would.
// SMALL-LABEL: func.func @one_budget_per_kernel
// SMALL-NOT: call
// SMALL: return
// BUDGET-LABEL: func.func @one_budget_per_kernel
// BUDGET: %[[A:.+]] = call @osl.lib.noise_cell.2(%arg0)
// BUDGET: %[[B:.+]] = arith.addf %arg0, %arg0 : f32
// BUDGET: return %[[A]], %[[B]]
// BUDGET-NOT: noise_hash
// BUDGET: func.func private @osl.lib.noise_cell.2
func.func @one_budget_per_kernel(%x: f32) -> (f32, f32) {
  %a = call @osl.lib.noise_cell.2(%x) : (f32) -> f32
  %b = call @osl.lib.noise_hash.2(%x) : (f32) -> f32
  return %a, %b : f32, f32
}
func.func private @osl.lib.noise_cell.2(%x: f32) -> f32 attributes {osl.library_recipe = "c2"} {
  %m = arith.mulf %x, %x : f32
  %p = arith.addf %m, %x : f32
  return %p : f32
}
func.func private @osl.lib.noise_hash.2(%x: f32) -> f32 attributes {osl.library_recipe = "h2"} {
  %m = arith.addf %x, %x : f32
  return %m : f32
}

// -----

// Past inline-always-ops, a body goes back only where a copy gains: a call
// passing a constant (it folds) or a call in a loop (its spills repeat).
// A routine called once with varying operands stays a call.
// FOLDS-LABEL: func.func @bigger_bodies_inline_where_they_gain
// FOLDS: %[[ONCE:.+]] = call @osl.lib.noise_perlin.3(%arg0)
// FOLDS: %[[TWO:.+]] = arith.constant 2.0
// FOLDS: %[[C:.+]] = arith.mulf %[[TWO]], %[[TWO]]
// FOLDS: arith.subf %[[C]], %[[TWO]]
// FOLDS: scf.for
// FOLDS-NOT: call
// FOLDS: arith.mulf %arg1, %arg1
// FOLDS: arith.subf
// FOLDS: scf.yield
// FOLDS: func.func private @osl.lib.noise_perlin.3(
// FOLDS-NOT: noise_simplex
// FOLDS-NOT: noise_cell
func.func @bigger_bodies_inline_where_they_gain(%x: f32, %y: f32) -> (f32, f32, f32) {
  %once = call @osl.lib.noise_perlin.3(%x) : (f32) -> f32
  %two = arith.constant 2.0 : f32
  %constant = call @osl.lib.noise_simplex.3(%two) : (f32) -> f32
  %c0 = arith.constant 0 : index
  %c1 = arith.constant 1 : index
  %c4 = arith.constant 4 : index
  %looped = scf.for %i = %c0 to %c4 step %c1 iter_args(%acc = %y) -> (f32) {
    %n = func.call @osl.lib.noise_cell.3(%y) : (f32) -> f32
    %s = arith.addf %acc, %n : f32
    scf.yield %s : f32
  }
  return %once, %constant, %looped : f32, f32, f32
}
func.func private @osl.lib.noise_perlin.3(%x: f32) -> f32 attributes {osl.library_recipe = "p3"} {
  %m = arith.mulf %x, %x : f32
  %a = arith.subf %m, %x : f32
  return %a : f32
}
func.func private @osl.lib.noise_simplex.3(%x: f32) -> f32 attributes {osl.library_recipe = "s3"} {
  %m = arith.mulf %x, %x : f32
  %a = arith.subf %m, %x : f32
  return %a : f32
}
func.func private @osl.lib.noise_cell.3(%x: f32) -> f32 attributes {osl.library_recipe = "c3"} {
  %m = arith.mulf %x, %x : f32
  %a = arith.subf %m, %x : f32
  return %a : f32
}

// -----

// A call its site keeps (osl.keep_call) stays a call at any inline-ops,
// and a declaration (a routine compiled before) is left alone; a small
// routine's other calls go back in place, and a routine no call is left to
// is erased.
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

