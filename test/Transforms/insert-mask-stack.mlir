// RUN: osl-opt %s -split-input-file --osl-insert-mask-stack | FileCheck %s

// Both arms run for every lane and the results merge per lane.
// CHECK-LABEL: func.func @varying_if_becomes_select
func.func @varying_if_becomes_select(%c: !osl.varying<i1>, %a: !osl.varying<f32>) {
  // CHECK-NOT: osl.if
  // CHECK: %[[T:.+]] = osl.sin %{{.+}}
  // CHECK: %[[E:.+]] = osl.cos %{{.+}}
  // CHECK: osl.select %{{.+}}, %[[T]], %[[E]] : !osl.varying<i1>, !osl.varying<f32>, !osl.varying<f32> -> !osl.varying<f32>
  %r = osl.if %c : !osl.varying<i1> -> !osl.varying<f32> {
    %s = osl.sin %a : !osl.varying<f32> -> !osl.varying<f32>
    osl.yield %s : !osl.varying<f32>
  } else {
    %s = osl.cos %a : !osl.varying<f32> -> !osl.varying<f32>
    osl.yield %s : !osl.varying<f32>
  }
  osl.output "x" = %r : !osl.varying<f32>
  return
}

// -----

// A uniform condition costs one branch and no masking.
// CHECK-LABEL: func.func @uniform_if_stays_a_branch
func.func @uniform_if_stays_a_branch(%c: i1, %a: !osl.varying<f32>) {
  // CHECK: scf.if %{{.+}} -> (!osl.varying<f32>) {
  // CHECK-NOT: osl.select
  // CHECK: scf.yield
  %r = osl.if %c : i1 -> !osl.varying<f32> {
    %s = osl.sin %a : !osl.varying<f32> -> !osl.varying<f32>
    osl.yield %s : !osl.varying<f32>
  } else {
    osl.yield %a : !osl.varying<f32>
  }
  osl.output "x" = %r : !osl.varying<f32>
  return
}

// -----

// The loop carries the active lanes, seeded with the batch's lanes; it
// runs while any lane is active, and lanes that left keep their value.
// CHECK-LABEL: func.func @varying_loop_carries_mask
func.func @varying_loop_carries_mask(%n: !osl.varying<f32>, %x: !osl.varying<f32>) {
  // CHECK: %[[BATCH:.+]] = osl.batch_mask : !osl.varying<i1>
  // CHECK: scf.while (%[[X:.+]] = %{{.+}}, %[[M:.+]] = %[[BATCH]])
  // CHECK:   %[[C:.+]] = osl.cmp "lt"
  // CHECK:   %[[STILL:.+]] = osl.and %[[M]], %[[C]]
  // CHECK:   %[[ANY:.+]] = osl.any %[[STILL]]
  // CHECK:   scf.condition(%[[ANY]]) %[[X]], %[[STILL]]
  // CHECK: } do {
  // CHECK: ^bb0(%[[X2:.+]]: !osl.varying<f32>, %[[M2:.+]]: !osl.varying<i1>):
  // CHECK:   %[[NEXT:.+]] = osl.add %[[X2]]
  // CHECK:   %[[KEEP:.+]] = osl.select %[[M2]], %[[NEXT]], %[[X2]]
  // CHECK:   scf.yield %[[KEEP]], %[[M2]]
  %r = osl.while (%x : !osl.varying<f32>) -> !osl.varying<f32> cond {
  ^bb0(%v: !osl.varying<f32>):
    %c = osl.cmp "lt", %v, %n : !osl.varying<f32>, !osl.varying<f32> -> !osl.varying<i1>
    osl.condition %c : !osl.varying<i1>, %v : !osl.varying<f32>
  } do {
  ^bb0(%v: !osl.varying<f32>):
    %one = arith.constant 1.0 : f32
    %v2 = osl.add %v, %one : !osl.varying<f32>, f32 -> !osl.varying<f32>
    osl.yield %v2 : !osl.varying<f32>
  }
  osl.output "x" = %r : !osl.varying<f32>
  return
}

// -----

// A loop inside a varying if starts with the arm's mask, so lanes that
// took the other arm never keep it iterating.
// CHECK-LABEL: func.func @loop_inside_varying_if_uses_arm_mask
func.func @loop_inside_varying_if_uses_arm_mask(%c: !osl.varying<i1>, %n: !osl.varying<f32>, %x: !osl.varying<f32>) {
  // CHECK: %[[NOT:.+]] = osl.not %[[COND:.+]] :
  // CHECK: scf.while (%{{.+}} = %{{.+}}, %{{.+}} = %[[COND]])
  // CHECK-NOT: osl.batch_mask
  %r = osl.if %c : !osl.varying<i1> -> !osl.varying<f32> {
    %l = osl.while (%x : !osl.varying<f32>) -> !osl.varying<f32> cond {
    ^bb0(%v: !osl.varying<f32>):
      %lt = osl.cmp "lt", %v, %n : !osl.varying<f32>, !osl.varying<f32> -> !osl.varying<i1>
      osl.condition %lt : !osl.varying<i1>, %v : !osl.varying<f32>
    } do {
    ^bb0(%v: !osl.varying<f32>):
      %one = arith.constant 1.0 : f32
      %v2 = osl.add %v, %one : !osl.varying<f32>, f32 -> !osl.varying<f32>
      osl.yield %v2 : !osl.varying<f32>
    }
    osl.yield %l : !osl.varying<f32>
  } else {
    osl.yield %x : !osl.varying<f32>
  }
  osl.output "x" = %r : !osl.varying<f32>
  return
}

// -----

// A varying if inside a varying loop masks its nested loop with the
// loop's active lanes AND the condition: the stack has two levels.
// CHECK-LABEL: func.func @nested_loop_in_if_in_loop
func.func @nested_loop_in_if_in_loop(%n: !osl.varying<f32>, %x: !osl.varying<f32>, %c: !osl.varying<i1>) {
  // CHECK: scf.while
  // CHECK: } do {
  // CHECK: ^bb0(%{{.+}}: !osl.varying<f32>, %[[OUTER:.+]]: !osl.varying<i1>):
  // CHECK:   %[[ARM:.+]] = osl.and %[[OUTER]], %{{.+}}
  // CHECK:   scf.while (%{{.+}} = %{{.+}}, %{{.+}} = %[[ARM]])
  %r = osl.while (%x : !osl.varying<f32>) -> !osl.varying<f32> cond {
  ^bb0(%v: !osl.varying<f32>):
    %lt = osl.cmp "lt", %v, %n : !osl.varying<f32>, !osl.varying<f32> -> !osl.varying<i1>
    osl.condition %lt : !osl.varying<i1>, %v : !osl.varying<f32>
  } do {
  ^bb0(%v: !osl.varying<f32>):
    %inner = osl.if %c : !osl.varying<i1> -> !osl.varying<f32> {
      %l = osl.while (%v : !osl.varying<f32>) -> !osl.varying<f32> cond {
      ^bb0(%w: !osl.varying<f32>):
        %lt2 = osl.cmp "lt", %w, %n : !osl.varying<f32>, !osl.varying<f32> -> !osl.varying<i1>
        osl.condition %lt2 : !osl.varying<i1>, %w : !osl.varying<f32>
      } do {
      ^bb0(%w: !osl.varying<f32>):
        %half = arith.constant 0.5 : f32
        %w2 = osl.add %w, %half : !osl.varying<f32>, f32 -> !osl.varying<f32>
        osl.yield %w2 : !osl.varying<f32>
      }
      osl.yield %l : !osl.varying<f32>
    } else {
      osl.yield %v : !osl.varying<f32>
    }
    %one = arith.constant 1.0 : f32
    %v2 = osl.add %inner, %one : !osl.varying<f32>, f32 -> !osl.varying<f32>
    osl.yield %v2 : !osl.varying<f32>
  }
  osl.output "x" = %r : !osl.varying<f32>
  return
}

// -----

// A uniform loop with a varying body stays an ordinary loop.
// CHECK-LABEL: func.func @uniform_loop_varying_body
func.func @uniform_loop_varying_body(%x: !osl.varying<f32>) {
  // CHECK: scf.while (%{{.+}} = %{{.+}}, %{{.+}} = %{{.+}}) : (i32, !osl.varying<f32>) -> (i32, !osl.varying<f32>)
  // CHECK-NOT: osl.any
  // CHECK-NOT: osl.batch_mask
  %zero = arith.constant 0 : i32
  %r:2 = osl.while (%zero, %x : i32, !osl.varying<f32>) -> i32, !osl.varying<f32> cond {
  ^bb0(%i: i32, %s: !osl.varying<f32>):
    %six = arith.constant 6 : i32
    %lt = osl.cmp "lt", %i, %six : i32, i32 -> i1
    osl.condition %lt : i1, %i, %s : i32, !osl.varying<f32>
  } do {
  ^bb0(%i: i32, %s: !osl.varying<f32>):
    %one = arith.constant 1 : i32
    %i2 = osl.add %i, %one : i32, i32 -> i32
    %s2 = osl.add %s, %s : !osl.varying<f32>, !osl.varying<f32> -> !osl.varying<f32>
    osl.yield %i2, %s2 : i32, !osl.varying<f32>
  }
  osl.output "x" = %r#1 : !osl.varying<f32>
  return
}
