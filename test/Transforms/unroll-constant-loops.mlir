// RUN: osl-opt %s -split-input-file --osl-unroll-constant-loops | FileCheck %s
// RUN: osl-opt %s -split-input-file --osl-unroll-constant-loops=max-trips=1 | FileCheck %s --check-prefix=TRIPS

// `a[n] = u * i; n += 1` for i in 1..2 then `c += a[k]` for k < n: the
// first loop unrolls (its index n folds at every trip), which makes n a
// constant the second loop then unrolls with; no select on an index is
// left.
// CHECK-LABEL: func.func @array_loops
// CHECK-NOT: osl.while
// CHECK-NOT: osl.select
// CHECK: %[[A0:.+]] = osl.mul %{{.+}}, %{{.+}} : !osl.varying<f32>, f32
// CHECK: %[[A1:.+]] = osl.mul %{{.+}}, %{{.+}} : !osl.varying<f32>, f32
// CHECK: %[[S0:.+]] = osl.add %{{.+}}, %[[A0]]
// CHECK: %[[S1:.+]] = osl.add %[[S0]], %[[A1]]
// CHECK: osl.output "c" = %[[S1]]
// Past max-trips, the first loop stays, and so does the second, whose
// bound is then unknown.
// TRIPS-LABEL: func.func @array_loops
// TRIPS: osl.while
// TRIPS: osl.while
// TRIPS-LABEL: func.func @no_array
func.func @array_loops() {
  %u = osl.global "u" : !osl.varying<f32>
  %zero = arith.constant 0.0 : f32
  %c0 = arith.constant 0 : i32
  %c1 = arith.constant 1 : i32
  %c3 = arith.constant 3 : i32
  %r:4 = osl.while(%zero, %zero, %c0, %c1 : f32, f32, i32, i32) -> f32, f32, i32, i32 cond {
  ^bb0(%a0: f32, %a1: f32, %n: i32, %i: i32):
    %go = osl.cmp lt, %i, %c3 : i32, i32 -> i1
    osl.condition %go : i1, %a0, %a1, %n, %i : f32, f32, i32, i32
  } do {
  ^bb0(%a0: f32, %a1: f32, %n: i32, %i: i32):
    %fi = osl.convert %i : i32 -> f32
    %v = osl.mul %u, %fi : !osl.varying<f32>, f32 -> !osl.varying<f32>
    %first = osl.cmp le, %n, %c0 : i32, i32 -> i1
    %b0 = osl.select %first, %v, %a0 : i1, !osl.varying<f32>, f32 -> !osl.varying<f32>
    %second = osl.cmp ge, %n, %c1 : i32, i32 -> i1
    %b1 = osl.select %second, %v, %a1 : i1, !osl.varying<f32>, f32 -> !osl.varying<f32>
    %n1 = osl.add %n, %c1 : i32, i32 -> i32
    %i1 = osl.add %i, %c1 : i32, i32 -> i32
    osl.yield %b0, %b1, %n1, %i1 : !osl.varying<f32>, !osl.varying<f32>, i32, i32
  }
  %s:2 = osl.while(%zero, %c0 : f32, i32) -> f32, i32 cond {
  ^bb0(%acc: f32, %k: i32):
    %go = osl.cmp lt, %k, %r#2 : i32, i32 -> i1
    osl.condition %go : i1, %acc, %k : f32, i32
  } do {
  ^bb0(%acc: f32, %k: i32):
    %first = osl.cmp le, %k, %c0 : i32, i32 -> i1
    %e = osl.select %first, %r#0, %r#1 : i1, f32, f32 -> f32
    %acc1 = osl.add %acc, %e : f32, f32 -> f32
    %k1 = osl.add %k, %c1 : i32, i32 -> i32
    osl.yield %acc1, %k1 : f32, i32
  }
  osl.output "c" = %s#0 : f32
  return
}

// -----

// A counted loop that indexes no array gains nothing from unrolling.
// CHECK-LABEL: func.func @no_array
// CHECK: osl.while
func.func @no_array() {
  %u = osl.global "u" : !osl.varying<f32>
  %zero = arith.constant 0.0 : f32
  %c0 = arith.constant 0 : i32
  %c1 = arith.constant 1 : i32
  %c3 = arith.constant 3 : i32
  %r:2 = osl.while(%zero, %c0 : f32, i32) -> f32, i32 cond {
  ^bb0(%acc: f32, %i: i32):
    %go = osl.cmp lt, %i, %c3 : i32, i32 -> i1
    osl.condition %go : i1, %acc, %i : f32, i32
  } do {
  ^bb0(%acc: f32, %i: i32):
    %acc1 = osl.add %acc, %u : f32, !osl.varying<f32> -> !osl.varying<f32>
    %i1 = osl.add %i, %c1 : i32, i32 -> i32
    osl.yield %acc1, %i1 : !osl.varying<f32>, i32
  }
  osl.output "d" = %r#0 : f32
  return
}

// -----

// Nor does one that only reads a long array (osl.pick reads memory at any
// index): a guard, since only select chains on a carried index count.
// CHECK-LABEL: func.func @reads_by_pick
// CHECK: osl.while
// CHECK: osl.pick
func.func @reads_by_pick() {
  %u = osl.global "u" : !osl.varying<f32>
  %zero = arith.constant 0.0 : f32
  %start = osl.broadcast %zero : f32 -> !osl.varying<f32>
  %c0 = arith.constant 0 : i32
  %c1 = arith.constant 1 : i32
  %c3 = arith.constant 3 : i32
  %r:2 = osl.while(%start, %c0 : !osl.varying<f32>, i32) -> !osl.varying<f32>, i32 cond {
  ^bb0(%acc: !osl.varying<f32>, %i: i32):
    %go = osl.cmp lt, %i, %c3 : i32, i32 -> i1
    osl.condition %go : i1, %acc, %i : !osl.varying<f32>, i32
  } do {
  ^bb0(%acc: !osl.varying<f32>, %i: i32):
    %e = osl.pick %i, [%u, %u, %zero] : i32, [!osl.varying<f32>, !osl.varying<f32>, f32] -> !osl.varying<f32>
    %acc1 = osl.add %acc, %e : !osl.varying<f32>, !osl.varying<f32> -> !osl.varying<f32>
    %i1 = osl.add %i, %c1 : i32, i32 -> i32
    osl.yield %acc1, %i1 : !osl.varying<f32>, i32
  }
  osl.output "d" = %r#0 : !osl.varying<f32>
  return
}

// -----

// A bound known only per point (or at run time) leaves the loop as it is.
// CHECK-LABEL: func.func @unknown_bound
// CHECK: osl.while
// CHECK: osl.select
func.func @unknown_bound(%bound: i32) {
  %zero = arith.constant 0.0 : f32
  %one = arith.constant 1.0 : f32
  %c0 = arith.constant 0 : i32
  %c1 = arith.constant 1 : i32
  %r:3 = osl.while(%zero, %zero, %c0 : f32, f32, i32) -> f32, f32, i32 cond {
  ^bb0(%a0: f32, %a1: f32, %i: i32):
    %go = osl.cmp lt, %i, %bound : i32, i32 -> i1
    osl.condition %go : i1, %a0, %a1, %i : f32, f32, i32
  } do {
  ^bb0(%a0: f32, %a1: f32, %i: i32):
    %first = osl.cmp le, %i, %c0 : i32, i32 -> i1
    %b0 = osl.select %first, %one, %a0 : i1, f32, f32 -> f32
    %i1 = osl.add %i, %c1 : i32, i32 -> i32
    osl.yield %b0, %a1, %i1 : f32, f32, i32
  }
  osl.output "c" = %r#0 : f32
  return
}
