// RUN: osl-opt %s -split-input-file --osl-insert-mask-stack | FileCheck %s
// RUN: osl-opt %s -split-input-file --osl-insert-mask-stack=count-lanes=true | FileCheck %s --check-prefix=COUNT

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
  // CHECK:   %[[C:.+]] = osl.cmp lt
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
    %c = osl.cmp lt, %v, %n : !osl.varying<f32>, !osl.varying<f32> -> !osl.varying<i1>
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

// A condition that changes what it forwards (`while (x++ < n)`): lanes
// that evaluated it take the new value, lanes that left before keep theirs.
// CHECK-LABEL: func.func @varying_condition_with_side_effect
func.func @varying_condition_with_side_effect(%n: !osl.varying<f32>, %x: !osl.varying<f32>) {
  // CHECK: scf.while (%[[X:.+]] = %{{.+}}, %[[M:.+]] = %{{.+}})
  // CHECK:   %[[INC:.+]] = osl.add %[[X]]
  // CHECK:   %[[C:.+]] = osl.cmp lt, %[[X]]
  // CHECK:   %[[STILL:.+]] = osl.and %[[M]], %[[C]]
  // CHECK:   %[[ANY:.+]] = osl.any %[[STILL]]
  // CHECK:   %[[FWD:.+]] = osl.select %[[M]], %[[INC]], %[[X]]
  // CHECK:   scf.condition(%[[ANY]]) %[[FWD]], %[[STILL]]
  %r = osl.while (%x : !osl.varying<f32>) -> !osl.varying<f32> cond {
  ^bb0(%v: !osl.varying<f32>):
    %one = arith.constant 1.0 : f32
    %v2 = osl.add %v, %one : !osl.varying<f32>, f32 -> !osl.varying<f32>
    %c = osl.cmp lt, %v, %n : !osl.varying<f32>, !osl.varying<f32> -> !osl.varying<i1>
    osl.condition %c : !osl.varying<i1>, %v2 : !osl.varying<f32>
  } do {
  ^bb0(%v: !osl.varying<f32>):
    osl.yield %v : !osl.varying<f32>
  }
  osl.output "x" = %r : !osl.varying<f32>
  return
}

// -----

// A loop inside a varying if starts with the arm's mask (the batch's live
// lanes AND the condition), so lanes that took the other arm, or are past
// the end of a partial batch, never keep it iterating.
// CHECK-LABEL: func.func @loop_inside_varying_if_uses_arm_mask
func.func @loop_inside_varying_if_uses_arm_mask(%c: !osl.varying<i1>, %n: !osl.varying<f32>, %x: !osl.varying<f32>) {
  // CHECK: %[[ENTRY:.+]] = osl.batch_mask
  // CHECK: %[[ARM:.+]] = osl.and %[[ENTRY]], %arg0 :
  // CHECK: scf.while (%{{.+}} = %{{.+}}, %{{.+}} = %[[ARM]])
  %r = osl.if %c : !osl.varying<i1> -> !osl.varying<f32> {
    %l = osl.while (%x : !osl.varying<f32>) -> !osl.varying<f32> cond {
    ^bb0(%v: !osl.varying<f32>):
      %lt = osl.cmp lt, %v, %n : !osl.varying<f32>, !osl.varying<f32> -> !osl.varying<i1>
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
    %lt = osl.cmp lt, %v, %n : !osl.varying<f32>, !osl.varying<f32> -> !osl.varying<i1>
    osl.condition %lt : !osl.varying<i1>, %v : !osl.varying<f32>
  } do {
  ^bb0(%v: !osl.varying<f32>):
    %inner = osl.if %c : !osl.varying<i1> -> !osl.varying<f32> {
      %l = osl.while (%v : !osl.varying<f32>) -> !osl.varying<f32> cond {
      ^bb0(%w: !osl.varying<f32>):
        %lt2 = osl.cmp lt, %w, %n : !osl.varying<f32>, !osl.varying<f32> -> !osl.varying<i1>
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
    %lt = osl.cmp lt, %i, %six : i32, i32 -> i1
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

// -----

// Nested varying ifs: each level runs both arms and merges with its own
// condition, so a lane sees the value of the innermost arm it took.
// CHECK-LABEL: func.func @nested_varying_if
// CHECK-NOT: osl.if
// CHECK: %[[IN:.+]] = osl.select %[[C2:.+]], %[[A:.+]], %[[B:.+]] :
// CHECK: %[[OUT:.+]] = osl.select %[[C1:.+]], %[[IN]], %{{.+}} :
// CHECK: osl.output "x" = %[[OUT]]
func.func @nested_varying_if(%c1: !osl.varying<i1>, %c2: !osl.varying<i1>, %x: !osl.varying<f32>) {
  %r = osl.if %c1 : !osl.varying<i1> -> !osl.varying<f32> {
    %one = arith.constant 1.0 : f32
    %a = osl.add %x, %one : !osl.varying<f32>, f32 -> !osl.varying<f32>
    %inner = osl.if %c2 : !osl.varying<i1> -> !osl.varying<f32> {
      %b2 = osl.mul %a, %a : !osl.varying<f32>, !osl.varying<f32> -> !osl.varying<f32>
      osl.yield %b2 : !osl.varying<f32>
    } else {
      osl.yield %a : !osl.varying<f32>
    }
    osl.yield %inner : !osl.varying<f32>
  } else {
    osl.yield %x : !osl.varying<f32>
  }
  osl.output "x" = %r : !osl.varying<f32>
  return
}

// -----

// break and continue under varying conditions in nested loops (the front
// end's flags). The inner loop is seeded with the outer loop's mask and its
// condition clears lanes whose break flag is set; continue only guards the
// rest of the body, and lanes that left keep their values.
// CHECK-LABEL: func.func @break_continue_nested
// CHECK: scf.while (%{{.+}} = %{{.+}}, %{{.+}} = %{{.+}}) : (!osl.varying<f32>, i32)
// CHECK: } do {
// CHECK: scf.while (%{{.+}} = %{{.+}}, %[[BRK0:.+]] = %{{.+}}, %{{.+}} = %{{.+}}, %[[SEED:.+]] = %{{.+}}) : (!osl.varying<f32>, !osl.varying<i1>, !osl.varying<i32>, !osl.varying<i1>)
// CHECK:   %[[STAY:.+]] = osl.not %[[BRK:.+]] :
// CHECK:   %[[COND:.+]] = osl.and %[[STAY]], %{{.+}} :
// CHECK:   %[[LIVE:.+]] = osl.and %[[MASK:.+]], %[[COND]] :
// CHECK:   %[[ANY:.+]] = osl.any %[[LIVE]]
// CHECK:   scf.condition(%[[ANY]])
// CHECK: } do {
// CHECK: ^bb0(%{{.+}}: !osl.varying<f32>, %{{.+}}: !osl.varying<i1>, %{{.+}}: !osl.varying<i32>, %[[M:.+]]: !osl.varying<i1>):
// CHECK:   osl.select %[[M]]
// CHECK:   scf.yield %{{.+}}, %{{.+}}, %{{.+}}, %[[M]]
func.func @break_continue_nested() attributes {osl.shader_type = "shader"} {
  %c1_i32 = arith.constant 1 : i32
  %cst = arith.constant 1.000000e+00 : f32
  %cst_0 = arith.constant 5.000000e-01 : f32
  %true = arith.constant true
  %cst_1 = arith.constant 2.500000e-01 : f32
  %false = arith.constant false
  %c4_i32 = arith.constant 4 : i32
  %c0_i32 = arith.constant 0 : i32
  %cst_2 = arith.constant 0.000000e+00 : f32
  %0 = osl.global "u" : !osl.varying<f32>
  %1 = osl.global "v" : !osl.varying<f32>
  %2 = osl.broadcast %cst_2 : f32 -> !osl.varying<f32>
  %3:2 = osl.while(%2, %c0_i32 : !osl.varying<f32>, i32) -> !osl.varying<f32>, i32 cond {
  ^bb0(%arg0: !osl.varying<f32>, %arg1: i32):
    %4 = osl.cmp lt, %arg1, %c4_i32 : i32, i32 -> i1
    osl.condition %4 : i1, %arg0, %arg1 : !osl.varying<f32>, i32
  } do {
  ^bb0(%arg0: !osl.varying<f32>, %arg1: i32):
    %4 = osl.broadcast %false : i1 -> !osl.varying<i1>
    %5 = osl.broadcast %c0_i32 : i32 -> !osl.varying<i32>
    %6:3 = osl.while(%arg0, %4, %5 : !osl.varying<f32>, !osl.varying<i1>, !osl.varying<i32>) -> !osl.varying<f32>, !osl.varying<i1>, !osl.varying<i32> cond {
    ^bb0(%arg2: !osl.varying<f32>, %arg3: !osl.varying<i1>, %arg4: !osl.varying<i32>):
      %8 = osl.not %arg3 : !osl.varying<i1> -> !osl.varying<i1>
      %9 = osl.cmp lt, %arg4, %c4_i32 : !osl.varying<i32>, i32 -> !osl.varying<i1>
      %10 = osl.and %8, %9 : !osl.varying<i1>, !osl.varying<i1> -> !osl.varying<i1>
      osl.condition %10 : !osl.varying<i1>, %arg2, %arg3, %arg4 : !osl.varying<f32>, !osl.varying<i1>, !osl.varying<i32>
    } do {
    ^bb0(%arg2: !osl.varying<f32>, %arg3: !osl.varying<i1>, %arg4: !osl.varying<i32>):
      %8 = osl.convert %arg4 : !osl.varying<i32> -> !osl.varying<f32>
      %9 = osl.mul %8, %cst_1 : !osl.varying<f32>, f32 -> !osl.varying<f32>
      %10 = osl.cmp gt, %9, %0 : !osl.varying<f32>, !osl.varying<f32> -> !osl.varying<i1>
      %11 = osl.if %10 : !osl.varying<i1> -> !osl.varying<i1> {
        %16 = osl.broadcast %true : i1 -> !osl.varying<i1>
        osl.yield %16 : !osl.varying<i1>
      } else {
        osl.yield %arg3 : !osl.varying<i1>
      }
      %12 = osl.not %11 : !osl.varying<i1> -> !osl.varying<i1>
      %13 = osl.if %12 : !osl.varying<i1> -> !osl.varying<f32> {
        %16 = osl.convert %arg4 : !osl.varying<i32> -> !osl.varying<f32>
        %17 = osl.mul %16, %cst_0 : !osl.varying<f32>, f32 -> !osl.varying<f32>
        %18 = osl.cmp gt, %17, %1 : !osl.varying<f32>, !osl.varying<f32> -> !osl.varying<i1>
        %19 = osl.not %18 : !osl.varying<i1> -> !osl.varying<i1>
        %20 = osl.if %19 : !osl.varying<i1> -> !osl.varying<f32> {
          %21 = osl.add %arg2, %cst : !osl.varying<f32>, f32 -> !osl.varying<f32>
          osl.yield %21 : !osl.varying<f32>
        } else {
          osl.yield %arg2 : !osl.varying<f32>
        }
        osl.yield %20 : !osl.varying<f32>
      } else {
        osl.yield %arg2 : !osl.varying<f32>
      }
      %14 = osl.not %11 : !osl.varying<i1> -> !osl.varying<i1>
      %15 = osl.if %14 : !osl.varying<i1> -> !osl.varying<i32> {
        %16 = osl.add %arg4, %c1_i32 : !osl.varying<i32>, i32 -> !osl.varying<i32>
        osl.yield %16 : !osl.varying<i32>
      } else {
        osl.yield %arg4 : !osl.varying<i32>
      }
      osl.yield %13, %11, %15 : !osl.varying<f32>, !osl.varying<i1>, !osl.varying<i32>
    }
    %7 = osl.add %arg1, %c1_i32 : i32, i32 -> i32
    osl.yield %6#0, %7 : !osl.varying<f32>, i32
  }
  osl.output "f" = %3#0 : !osl.varying<f32>
  return
}

// -----

// return inside a loop of an inlined function: the returned flag leaves
// the loop per lane, and the code after the loop is merged under its
// negation.
// CHECK-LABEL: func.func @return_in_loop
// CHECK: %[[ENTRY:.+]] = osl.batch_mask
// CHECK: %[[LOOP:.+]]:4 = scf.while ({{.*}}%{{.+}} = %[[ENTRY]])
// CHECK:   osl.not %arg0
// CHECK:   osl.any
// CHECK: } do {
// CHECK:   %[[HIT:.+]] = osl.cmp gt
// CHECK:   %[[RET:.+]] = osl.select %[[HIT]], %{{.+}}, %arg0
// CHECK:   %[[STEP:.+]] = osl.not %[[RET]]
// CHECK:   osl.select %[[STEP]]
// CHECK: }
// CHECK: %[[REST:.+]] = osl.not %[[LOOP]]#0
// CHECK: %[[F:.+]] = osl.select %[[REST]], %{{.+}}, %[[LOOP]]#1
// CHECK: osl.output "f" = %[[F]]
func.func @return_in_loop() attributes {osl.shader_type = "shader"} {
  %cst = arith.constant -1.000000e+00 : f32
  %c1_i32 = arith.constant 1 : i32
  %true = arith.constant true
  %cst_0 = arith.constant 1.250000e-01 : f32
  %c8_i32 = arith.constant 8 : i32
  %c0_i32 = arith.constant 0 : i32
  %false = arith.constant false
  %cst_1 = arith.constant 0.000000e+00 : f32
  %0 = osl.global "u" : !osl.varying<f32>
  %1 = osl.broadcast %false : i1 -> !osl.varying<i1>
  %2 = osl.broadcast %cst_1 : f32 -> !osl.varying<f32>
  %3 = osl.broadcast %c0_i32 : i32 -> !osl.varying<i32>
  %4:3 = osl.while(%1, %2, %3 : !osl.varying<i1>, !osl.varying<f32>, !osl.varying<i32>) -> !osl.varying<i1>, !osl.varying<f32>, !osl.varying<i32> cond {
  ^bb0(%arg0: !osl.varying<i1>, %arg1: !osl.varying<f32>, %arg2: !osl.varying<i32>):
    %7 = osl.not %arg0 : !osl.varying<i1> -> !osl.varying<i1>
    %8 = osl.cmp lt, %arg2, %c8_i32 : !osl.varying<i32>, i32 -> !osl.varying<i1>
    %9 = osl.and %7, %8 : !osl.varying<i1>, !osl.varying<i1> -> !osl.varying<i1>
    osl.condition %9 : !osl.varying<i1>, %arg0, %arg1, %arg2 : !osl.varying<i1>, !osl.varying<f32>, !osl.varying<i32>
  } do {
  ^bb0(%arg0: !osl.varying<i1>, %arg1: !osl.varying<f32>, %arg2: !osl.varying<i32>):
    %7 = osl.convert %arg2 : !osl.varying<i32> -> !osl.varying<f32>
    %8 = osl.mul %7, %cst_0 : !osl.varying<f32>, f32 -> !osl.varying<f32>
    %9 = osl.cmp gt, %8, %0 : !osl.varying<f32>, !osl.varying<f32> -> !osl.varying<i1>
    %10:2 = osl.if %9 : !osl.varying<i1> -> !osl.varying<i1>, !osl.varying<f32> {
      %13 = osl.convert %arg2 : !osl.varying<i32> -> !osl.varying<f32>
      %14 = osl.broadcast %true : i1 -> !osl.varying<i1>
      osl.yield %14, %13 : !osl.varying<i1>, !osl.varying<f32>
    } else {
      osl.yield %arg0, %arg1 : !osl.varying<i1>, !osl.varying<f32>
    }
    %11 = osl.not %10#0 : !osl.varying<i1> -> !osl.varying<i1>
    %12 = osl.if %11 : !osl.varying<i1> -> !osl.varying<i32> {
      %13 = osl.add %arg2, %c1_i32 : !osl.varying<i32>, i32 -> !osl.varying<i32>
      osl.yield %13 : !osl.varying<i32>
    } else {
      osl.yield %arg2 : !osl.varying<i32>
    }
    osl.yield %10#0, %10#1, %12 : !osl.varying<i1>, !osl.varying<f32>, !osl.varying<i32>
  }
  %5 = osl.not %4#0 : !osl.varying<i1> -> !osl.varying<i1>
  %6 = osl.if %5 : !osl.varying<i1> -> !osl.varying<f32> {
    %7 = osl.broadcast %cst : f32 -> !osl.varying<f32>
    osl.yield %7 : !osl.varying<f32>
  } else {
    osl.yield %4#1 : !osl.varying<f32>
  }
  osl.output "f" = %6 : !osl.varying<f32>
  return
}

// -----

// exit() under a varying condition: outputs assigned before it keep their
// value; one assigned after it is merged under "not exited".
// CHECK-LABEL: func.func @exit_varying
// CHECK: %[[U:.+]] = osl.global "u"
// CHECK: %[[V:.+]] = osl.global "v"
// CHECK: %[[EXIT:.+]] = osl.cmp gt, %[[V]]
// CHECK: %[[GO:.+]] = osl.not %[[EXIT]]
// CHECK: %[[B:.+]] = osl.select %[[GO]], %[[V]], %{{.+}}
// CHECK: osl.output "a" = %[[U]]
// CHECK: osl.output "b" = %[[B]]
func.func @exit_varying() attributes {osl.shader_type = "shader"} {
  %cst = arith.constant 5.000000e-01 : f32
  %cst_0 = arith.constant 0.000000e+00 : f32
  %0 = osl.global "u" : !osl.varying<f32>
  %1 = osl.global "v" : !osl.varying<f32>
  %2 = osl.cmp gt, %1, %cst : !osl.varying<f32>, f32 -> !osl.varying<i1>
  %3 = osl.not %2 : !osl.varying<i1> -> !osl.varying<i1>
  %4 = osl.if %3 : !osl.varying<i1> -> !osl.varying<f32> {
    osl.yield %1 : !osl.varying<f32>
  } else {
    %5 = osl.broadcast %cst_0 : f32 -> !osl.varying<f32>
    osl.yield %5 : !osl.varying<f32>
  }
  osl.output "a" = %0 : !osl.varying<f32>
  osl.output "b" = %4 : !osl.varying<f32>
  return
}

// -----

// Outputs written in one branch only: lanes that did not write keep the
// output's previous (default) value.
// CHECK-LABEL: func.func @partial_output
// CHECK: %[[U:.+]] = osl.global "u"
// CHECK: %[[V:.+]] = osl.global "v"
// CHECK: %[[C:.+]] = osl.cmp gt, %[[U]]
// CHECK: %[[ADEF:.+]] = osl.broadcast %{{.+}} : f32 -> !osl.varying<f32>
// CHECK: %[[BDEF:.+]] = osl.broadcast %{{.+}} : f32 -> !osl.varying<f32>
// CHECK: %[[A:.+]] = osl.select %[[C]], %[[U]], %[[BDEF]]
// CHECK: %[[B:.+]] = osl.select %[[C]], %[[ADEF]], %[[V]]
// CHECK: osl.output "a" = %[[A]]
// CHECK: osl.output "b" = %[[B]]
func.func @partial_output() attributes {osl.shader_type = "shader"} {
  %cst = arith.constant 5.000000e-01 : f32
  %cst_0 = arith.constant 7.000000e+00 : f32
  %cst_1 = arith.constant 0.000000e+00 : f32
  %0 = osl.global "u" : !osl.varying<f32>
  %1 = osl.global "v" : !osl.varying<f32>
  %2 = osl.cmp gt, %0, %cst : !osl.varying<f32>, f32 -> !osl.varying<i1>
  %3:2 = osl.if %2 : !osl.varying<i1> -> !osl.varying<f32>, !osl.varying<f32> {
    %4 = osl.broadcast %cst_0 : f32 -> !osl.varying<f32>
    osl.yield %0, %4 : !osl.varying<f32>, !osl.varying<f32>
  } else {
    %4 = osl.broadcast %cst_1 : f32 -> !osl.varying<f32>
    osl.yield %4, %1 : !osl.varying<f32>, !osl.varying<f32>
  }
  osl.output "a" = %3#0 : !osl.varying<f32>
  osl.output "b" = %3#1 : !osl.varying<f32>
  return
}

// -----

// An arm holding a loop (or many operations) is skipped when no lane of
// the batch takes it: it runs under scf.if on osl.any of its mask. When
// the other arm only passes values on, the merge happens inside the
// guard, and a skipped arm leaves those values as they were.
// CHECK-LABEL: func.func @one_sided_arm_merges_in_its_guard
// CHECK: %[[ENTRY:.+]] = osl.batch_mask
// CHECK: %[[ARM:.+]] = osl.and %[[ENTRY]], %[[C:.+]] :
// CHECK: %[[ANY:.+]] = osl.any %[[ARM]]
// CHECK: %[[G:.+]] = scf.if %[[ANY]] -> (!osl.varying<f32>) {
// CHECK:   %[[L:.+]]:2 = scf.while
// CHECK:   %[[M:.+]] = osl.select %[[C]], %[[L]]#0, %[[X:.+]] :
// CHECK:   scf.yield %[[M]]
// CHECK: } else {
// CHECK:   scf.yield %[[X]]
// CHECK: }
// CHECK-NOT: osl.select
// CHECK: osl.output "x" = %[[G]]
func.func @one_sided_arm_merges_in_its_guard(%c: !osl.varying<i1>, %n: !osl.varying<f32>, %x: !osl.varying<f32>) {
  %r = osl.if %c : !osl.varying<i1> -> !osl.varying<f32> {
    %l = osl.while (%x : !osl.varying<f32>) -> !osl.varying<f32> cond {
    ^bb0(%v: !osl.varying<f32>):
      %lt = osl.cmp lt, %v, %n : !osl.varying<f32>, !osl.varying<f32> -> !osl.varying<i1>
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

// When both arms compute, a guarded arm yields zeros when it is skipped,
// which the merge after both arms never selects for a live lane.
// CHECK-LABEL: func.func @guarded_arm_beside_another_arm
// CHECK: %[[ANY:.+]] = osl.any
// CHECK: %[[G:.+]] = scf.if %[[ANY]] -> (!osl.varying<f32>) {
// CHECK:   %[[L:.+]]:2 = scf.while
// CHECK:   scf.yield %[[L]]#0
// CHECK: } else {
// CHECK:   %[[Z:.+]] = osl.broadcast %{{.+}} : f32 -> !osl.varying<f32>
// CHECK:   scf.yield %[[Z]]
// CHECK: }
// CHECK: %[[E:.+]] = osl.sin
// CHECK: osl.select %{{.+}}, %[[G]], %[[E]]
func.func @guarded_arm_beside_another_arm(%c: !osl.varying<i1>, %n: !osl.varying<f32>, %x: !osl.varying<f32>) {
  %r = osl.if %c : !osl.varying<i1> -> !osl.varying<f32> {
    %l = osl.while (%x : !osl.varying<f32>) -> !osl.varying<f32> cond {
    ^bb0(%v: !osl.varying<f32>):
      %lt = osl.cmp lt, %v, %n : !osl.varying<f32>, !osl.varying<f32> -> !osl.varying<i1>
      osl.condition %lt : !osl.varying<i1>, %v : !osl.varying<f32>
    } do {
    ^bb0(%v: !osl.varying<f32>):
      %one = arith.constant 1.0 : f32
      %v2 = osl.add %v, %one : !osl.varying<f32>, f32 -> !osl.varying<f32>
      osl.yield %v2 : !osl.varying<f32>
    }
    osl.yield %l : !osl.varying<f32>
  } else {
    %s = osl.sin %x : !osl.varying<f32> -> !osl.varying<f32>
    osl.yield %s : !osl.varying<f32>
  }
  osl.output "x" = %r : !osl.varying<f32>
  return
}

// -----

// In a loop, a one-sided arm of three or more operations is guarded even
// though it is small (`if (d < r) { cover += 1 - d / r; }`): when no lane
// takes it the carried value passes on without waiting for the condition.
// A smaller one (`n += 1`) and one outside any loop stay selects.
// CHECK-LABEL: func.func @small_one_sided_arms
// CHECK: scf.while
// CHECK: } do {
// CHECK:   %[[ANY:.+]] = osl.any
// CHECK:   scf.if %[[ANY]] -> (!osl.varying<f32>) {
// CHECK:     osl.div
// CHECK:     osl.sub
// CHECK:     osl.add
// CHECK:     osl.select
// CHECK:   } else {
// CHECK:   osl.add
// CHECK-NOT: osl.any
// CHECK:   osl.select
// CHECK:   scf.yield
// CHECK: }
// CHECK-NOT: scf.if
// CHECK: osl.output
func.func @small_one_sided_arms(%d: !osl.varying<f32>, %r: f32, %x: !osl.varying<f32>, %n: !osl.varying<f32>) {
  %loop:2 = osl.while (%x, %n : !osl.varying<f32>, !osl.varying<f32>) -> !osl.varying<f32>, !osl.varying<f32> cond {
  ^bb0(%v: !osl.varying<f32>, %k: !osl.varying<f32>):
    %lt = osl.cmp lt, %v, %n : !osl.varying<f32>, !osl.varying<f32> -> !osl.varying<i1>
    osl.condition %lt : !osl.varying<i1>, %v, %k : !osl.varying<f32>, !osl.varying<f32>
  } do {
  ^bb0(%v: !osl.varying<f32>, %k: !osl.varying<f32>):
    %near = osl.cmp lt, %d, %r : !osl.varying<f32>, f32 -> !osl.varying<i1>
    %cover = osl.if %near : !osl.varying<i1> -> !osl.varying<f32> {
      %one = arith.constant 1.0 : f32
      %q = osl.div %d, %r : !osl.varying<f32>, f32 -> !osl.varying<f32>
      %w = osl.sub %one, %q : f32, !osl.varying<f32> -> !osl.varying<f32>
      %s = osl.add %v, %w : !osl.varying<f32>, !osl.varying<f32> -> !osl.varying<f32>
      osl.yield %s : !osl.varying<f32>
    } else {
      osl.yield %v : !osl.varying<f32>
    }
    %k2 = osl.if %near : !osl.varying<i1> -> !osl.varying<f32> {
      %one = arith.constant 1.0 : f32
      %k1 = osl.add %k, %one : !osl.varying<f32>, f32 -> !osl.varying<f32>
      osl.yield %k1 : !osl.varying<f32>
    } else {
      osl.yield %k : !osl.varying<f32>
    }
    osl.yield %cover, %k2 : !osl.varying<f32>, !osl.varying<f32>
  }
  %far = osl.cmp gt, %d, %r : !osl.varying<f32>, f32 -> !osl.varying<i1>
  %out = osl.if %far : !osl.varying<i1> -> !osl.varying<f32> {
    %q = osl.div %d, %r : !osl.varying<f32>, f32 -> !osl.varying<f32>
    %w = osl.sub %loop#0, %q : !osl.varying<f32>, !osl.varying<f32> -> !osl.varying<f32>
    %s = osl.add %loop#1, %w : !osl.varying<f32>, !osl.varying<f32> -> !osl.varying<f32>
    osl.yield %s : !osl.varying<f32>
  } else {
    osl.yield %x : !osl.varying<f32>
  }
  osl.output "x" = %out : !osl.varying<f32>
  return
}

// -----

// With count-lanes, each arm of a varying if and each iteration of a
// varying loop starts by counting its mask's lanes among the batch's
// shading points; without it nothing is counted.
// CHECK-LABEL: func.func @count_lanes_in_masked_blocks
// CHECK-NOT: osl.count_lanes
// COUNT-LABEL: func.func @count_lanes_in_masked_blocks
// COUNT: %[[BATCH:.+]] = osl.batch_mask : !osl.varying<i1>
// COUNT: osl.count_lanes %{{.+}} : !osl.varying<i1>
// COUNT-NEXT: osl.sin
// COUNT-NEXT: %[[ELSE:.+]] = osl.and %[[BATCH]], %{{.+}}
// COUNT-NEXT: osl.count_lanes %[[ELSE]] : !osl.varying<i1>
// COUNT-NEXT: osl.cos
// COUNT: } do {
// COUNT-NEXT: ^bb0(%{{.+}}: !osl.varying<f32>, %[[M:.+]]: !osl.varying<i1>):
// COUNT-NEXT: %[[ITER:.+]] = osl.and %[[BATCH]], %[[M]]
// COUNT-NEXT: osl.count_lanes %[[ITER]] : !osl.varying<i1>
func.func @count_lanes_in_masked_blocks(%c: !osl.varying<i1>, %a: !osl.varying<f32>, %n: !osl.varying<f32>) {
  %r = osl.if %c : !osl.varying<i1> -> !osl.varying<f32> {
    %s = osl.sin %a : !osl.varying<f32> -> !osl.varying<f32>
    osl.yield %s : !osl.varying<f32>
  } else {
    %k = osl.cos %a : !osl.varying<f32> -> !osl.varying<f32>
    osl.yield %k : !osl.varying<f32>
  }
  %w = osl.while (%r : !osl.varying<f32>) -> !osl.varying<f32> cond {
  ^bb0(%v: !osl.varying<f32>):
    %lt = osl.cmp lt, %v, %n : !osl.varying<f32>, !osl.varying<f32> -> !osl.varying<i1>
    osl.condition %lt : !osl.varying<i1>, %v : !osl.varying<f32>
  } do {
  ^bb0(%v: !osl.varying<f32>):
    %one = arith.constant 1.0 : f32
    %v2 = osl.add %v, %one : !osl.varying<f32>, f32 -> !osl.varying<f32>
    osl.yield %v2 : !osl.varying<f32>
  }
  osl.output "x" = %w : !osl.varying<f32>
  return
}

// -----

// A print is a side effect: inside a varying if it prints only for the
// arm's lanes, so it takes the arm's mask; outside, it has none (every
// live lane prints).
// CHECK-LABEL: func.func @print_takes_the_arm_mask
// CHECK: %[[MASK:.+]] = osl.batch_mask
// CHECK: %[[THEN:.+]] = osl.and %[[MASK]], %{{.+}}
// CHECK: osl.print "printf" "sf"(%{{.+}}, %{{.+}}) mask %[[THEN]] : !osl.varying<i1> : i32, !osl.varying<f32>
// CHECK: osl.print "printf" "s"(%{{.+}}) : i32
func.func @print_takes_the_arm_mask(%c: !osl.varying<i1>, %a: !osl.varying<f32>, %fmt: i32) {
  osl.if %c : !osl.varying<i1> {
    osl.print "printf" "sf"(%fmt, %a) : i32, !osl.varying<f32>
    osl.yield
  } else {
    osl.yield
  }
  osl.print "printf" "s"(%fmt) : i32
  return
}

// -----

// An arm with an expensive op (noise) that yields nothing, only prints,
// still goes under its guard, which then ends in an empty scf.yield (a
// shader printing a noise value under a varying if did not verify).
// CHECK-LABEL: func.func @guarded_arm_without_values
// CHECK: %[[ANY:.+]] = osl.any
// CHECK: scf.if %[[ANY]] {
// CHECK:   osl.noise perlin
// CHECK:   osl.print "printf"
// CHECK-NEXT: }
func.func @guarded_arm_without_values(%c: !osl.varying<i1>, %a: !osl.varying<f32>, %fmt: i32) {
  osl.if %c : !osl.varying<i1> {
    %n = osl.noise perlin(%a) : (!osl.varying<f32>) -> !osl.varying<f32>
    osl.print "printf" "sf"(%fmt, %n) : i32, !osl.varying<f32>
    osl.yield
  } else {
    osl.yield
  }
  return
}

// -----

// Messages are side effects too: set and get inside a varying if take the
// arm's mask, so only the arm's points set or ask.
// CHECK-LABEL: func.func @messages_take_the_arm_mask
// CHECK: %[[THEN:.+]] = osl.and %{{.+}}, %{{.+}}
// CHECK: osl.set_message "m" "float" "f"(%{{.+}}) mask %[[THEN]]
// CHECK: osl.get_message "m" "float" "f"(%{{.+}}) mask %[[THEN]]
// CHECK: osl.get_message "m" "float" "f"(%{{.+}}) :
func.func @messages_take_the_arm_mask(%c: !osl.varying<i1>, %a: !osl.varying<f32>) {
  osl.if %c : !osl.varying<i1> {
    osl.set_message "m" "float" "f"(%a) : !osl.varying<f32>
    %f, %v = osl.get_message "m" "float" "f"(%a) : (!osl.varying<f32>) -> (!osl.varying<i32>, !osl.varying<f32>)
    osl.yield
  } else {
    osl.yield
  }
  %f2, %v2 = osl.get_message "m" "float" "f"(%a) : (!osl.varying<f32>) -> (!osl.varying<i32>, !osl.varying<f32>)
  return
}

// -----

// An arm that reports an error (a range check) is cold: its test says so,
// and osl-lower-to-llvm's branch on it says skipping is likely. An arm
// that only prints is not.
// CHECK-LABEL: func.func @error_arm_is_cold
// CHECK: osl.any %{{.+}} {osl.cold_arm} : !osl.varying<i1>
// CHECK: osl.print "renderer_error"
// CHECK: %[[ANY:.+]] = osl.any %{{.+}} : !osl.varying<i1>
// CHECK-NEXT: scf.if %[[ANY]]
// CHECK: osl.print "printf"
func.func @error_arm_is_cold(%c: !osl.varying<i1>, %a: !osl.varying<f32>, %fmt: i32) {
  osl.if %c : !osl.varying<i1> {
    %n = osl.noise perlin(%a) : (!osl.varying<f32>) -> !osl.varying<f32>
    osl.print "renderer_error" "sf"(%fmt, %n) : i32, !osl.varying<f32>
    osl.yield
  } else {
    osl.yield
  }
  osl.if %c : !osl.varying<i1> {
    %n = osl.noise perlin(%a) : (!osl.varying<f32>) -> !osl.varying<f32>
    osl.print "printf" "sf"(%fmt, %n) : i32, !osl.varying<f32>
    osl.yield
  } else {
    osl.yield
  }
  return
}

// -----

// A noise whose kind is chosen per point calls a routine as costly as any
// noise: its arm is guarded, so a batch with no point in the arm skips it
// (noise-generic shaded 2.7x slower without the guard).
// CHECK-LABEL: func.func @noise_by_kind_arm_is_guarded
// CHECK: %[[ANY:.+]] = osl.any
// CHECK: scf.if %[[ANY]] -> (!osl.varying<f32>) {
// CHECK:   osl.noise_by_kind
func.func @noise_by_kind_arm_is_guarded(%c: !osl.varying<i1>, %k: !osl.varying<i32>, %a: !osl.varying<f32>) -> !osl.varying<f32> {
  %r = osl.if %c : !osl.varying<i1> -> !osl.varying<f32> {
    %n = osl.noise_by_kind %k : !osl.varying<i32>(%a) : (!osl.varying<f32>) -> !osl.varying<f32>
    osl.yield %n : !osl.varying<f32>
  } else {
    %z = arith.constant 0.0 : f32
    %zv = osl.broadcast %z : f32 -> !osl.varying<f32>
    osl.yield %zv : !osl.varying<f32>
  }
  return %r : !osl.varying<f32>
}

