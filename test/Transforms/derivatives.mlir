// RUN: osl-opt %s -split-input-file --osl-derivatives -verify-diagnostics | FileCheck %s
// RUN: osl-opt %s -split-input-file --osl-derivatives=assume-compiled=true -verify-diagnostics \
// RUN:   | FileCheck %s --check-prefix=COMPILED

// The derivative of a global's row is its derivative row: dudx is row 35
// (u is row 33), so at width 4 it is read 140 floats into the block.
// CHECK-LABEL: func.func @global_row
// CHECK: %[[DU:.+]] = llvm.getelementptr %arg0[140]
// CHECK: %[[D:.+]] = llvm.load %[[DU]]
// CHECK: llvm.intr.masked.store %[[D]]
// CHECK-NOT: osl.lane_deriv
func.func @global_row(%arg0: !llvm.ptr, %arg1: !llvm.ptr, %arg2: i32) {
  %0 = llvm.getelementptr %arg0[132] : (!llvm.ptr) -> !llvm.ptr, f32
  %u = llvm.load %0 {alignment = 4 : i64, osl.global_row = 33 : i64} : !llvm.ptr -> vector<4xf32>
  %d = osl.lane_deriv x %u : vector<4xf32>
  %m = arith.constant dense<true> : vector<4xi1>
  llvm.intr.masked.store %d, %arg1, %m {alignment = 4 : i32} : vector<4xf32>, vector<4xi1> into !llvm.ptr
  return
}

// -----

// A 2D lookup's result row (green, row 24 at width 4: 96 floats in) has
// the derivative d(green)/ds * ds/dy + d(green)/dt * dt/dy: rows 30 and 34
// (the slopes) and 5 and 6 (ds/dy, dt/dy), read from the same block right
// after the result.
// CHECK-LABEL: func.func @texture_result_row
// CHECK: llvm.load %{{.+}} {alignment = 4 : i64, osl.texture_result_row = 24 : i64}
// CHECK-DAG: %[[DS:.+]] = llvm.getelementptr %[[BLOCK:.+]][120]
// CHECK-DAG: %[[DSDY:.+]] = llvm.getelementptr %[[BLOCK]][20]
// CHECK-DAG: %[[DT:.+]] = llvm.getelementptr %[[BLOCK]][136]
// CHECK-DAG: %[[DTDY:.+]] = llvm.getelementptr %[[BLOCK]][24]
// CHECK: arith.addf
// CHECK-NOT: osl.lane_deriv
func.func @texture_result_row(%arg0: !llvm.ptr, %arg1: !llvm.ptr, %arg2: i32) {
  %c = llvm.mlir.constant(148 : i64) : i64
  %block = llvm.alloca %c x i32 {alignment = 64 : i64} : (i64) -> !llvm.ptr
  %0 = llvm.getelementptr %block[96] : (!llvm.ptr) -> !llvm.ptr, f32
  %g = llvm.load %0 {alignment = 4 : i64, osl.texture_result_row = 24 : i64} : !llvm.ptr -> vector<4xf32>
  %d = osl.lane_deriv y %g : vector<4xf32>
  %m = arith.constant dense<true> : vector<4xi1>
  llvm.intr.masked.store %d, %arg1, %m {alignment = 4 : i32} : vector<4xf32>, vector<4xi1> into !llvm.ptr
  return
}

// -----

// Product rule on u * v with respect to y: dudy * v + u * dvdy (rows 36
// and 38); nothing is computed for x, which nobody asks for.
// CHECK-LABEL: func.func @product_rule
// CHECK-DAG: %[[U:.+]] = llvm.load %{{.+}} {alignment = 4 : i64, osl.global_row = 33 : i64}
// CHECK-DAG: %[[V:.+]] = llvm.load %{{.+}} {alignment = 4 : i64, osl.global_row = 34 : i64}
// CHECK-DAG: llvm.getelementptr %arg0[144]
// CHECK-DAG: llvm.getelementptr %arg0[152]
// CHECK: arith.mulf %[[U]], %[[V]]
// CHECK: %[[A:.+]] = arith.mulf %{{.+}}, %[[V]]
// CHECK: %[[B:.+]] = arith.mulf %[[U]], %{{.+}}
// CHECK: %[[S:.+]] = arith.addf %[[A]], %[[B]]
// CHECK: llvm.intr.masked.store %[[S]]
// CHECK-NOT: arith.constant dense<0.0
func.func @product_rule(%arg0: !llvm.ptr, %arg1: !llvm.ptr, %arg2: i32) {
  %0 = llvm.getelementptr %arg0[132] : (!llvm.ptr) -> !llvm.ptr, f32
  %u = llvm.load %0 {alignment = 4 : i64, osl.global_row = 33 : i64} : !llvm.ptr -> vector<4xf32>
  %1 = llvm.getelementptr %arg0[136] : (!llvm.ptr) -> !llvm.ptr, f32
  %v = llvm.load %1 {alignment = 4 : i64, osl.global_row = 34 : i64} : !llvm.ptr -> vector<4xf32>
  %p = arith.mulf %u, %v : vector<4xf32>
  %d = osl.lane_deriv y %p : vector<4xf32>
  %m = arith.constant dense<true> : vector<4xi1>
  llvm.intr.masked.store %d, %arg1, %m {alignment = 4 : i32} : vector<4xf32>, vector<4xi1> into !llvm.ptr
  return
}

// -----

// Triples: the derivative of a vector assembled from rows is the vector of
// the rows' derivatives (dPdx for P); constants contribute nothing.
// CHECK-LABEL: func.func @triple
// CHECK: llvm.getelementptr %arg0[108]
// CHECK: %[[DX:.+]] = llvm.load %{{.+}} {alignment = 4 : i64, osl.derivative_row} : !llvm.ptr -> vector<4xf32>
// CHECK: vector.insert
// CHECK: %[[Z:.+]] = arith.constant dense<0.000000e+00> : vector<3x4xf32>
// CHECK: vector.insert %[[DX]], %[[Z]] [0]
func.func @triple(%arg0: !llvm.ptr, %arg1: !llvm.ptr, %arg2: i32) {
  %0 = llvm.getelementptr %arg0[0] : (!llvm.ptr) -> !llvm.ptr, f32
  %px = llvm.load %0 {alignment = 4 : i64, osl.global_row = 0 : i64} : !llvm.ptr -> vector<4xf32>
  %z = arith.constant dense<0.000000e+00> : vector<3x4xf32>
  %p = vector.insert %px, %z [0] : vector<4xf32> into vector<3x4xf32>
  %d = osl.lane_deriv x %p : vector<3x4xf32>
  %r = vector.extract %d[0] : vector<4xf32> from vector<3x4xf32>
  %m = arith.constant dense<true> : vector<4xi1>
  llvm.intr.masked.store %r, %arg1, %m {alignment = 4 : i32} : vector<4xf32>, vector<4xi1> into !llvm.ptr
  return
}

// -----

// OSL's atan2 rule (osl.dual_rule): (y x' - x y') / (x^2 + y^2), the
// negation of the true derivative, which OSL's results follow.
// With y = 1 and x = u that is +dudx / (u^2 + 1).
// CHECK-LABEL: func.func @osl_atan2
// CHECK: %[[DUX:.+]] = llvm.getelementptr %arg0[140]
// CHECK: %[[DU:.+]] = llvm.load %[[DUX]] {alignment = 4 : i64, osl.derivative_row} : !llvm.ptr -> vector<4xf32>
// CHECK: %[[A:.+]] = math.atan2 %[[Y:.+]], %[[X:.+]] {osl.dual_rule = "osl_atan2"}
// CHECK: %[[XX:.+]] = arith.mulf %[[X]], %[[X]]
// CHECK: %[[YY:.+]] = arith.mulf %[[Y]], %[[Y]]
// CHECK: %[[DEN:.+]] = arith.addf %[[XX]], %[[YY]]
// CHECK: %[[NUM:.+]] = arith.mulf %[[Y]], %[[DU]]
// CHECK: %[[D:.+]] = arith.divf %[[NUM]], %[[DEN]]
// CHECK: llvm.intr.masked.store %[[D]]
func.func @osl_atan2(%arg0: !llvm.ptr, %arg1: !llvm.ptr, %arg2: i32) {
  %0 = llvm.getelementptr %arg0[132] : (!llvm.ptr) -> !llvm.ptr, f32
  %u = llvm.load %0 {alignment = 4 : i64, osl.global_row = 33 : i64} : !llvm.ptr -> vector<4xf32>
  %one = arith.constant dense<1.0> : vector<4xf32>
  %a = math.atan2 %one, %u {osl.dual_rule = "osl_atan2"} : vector<4xf32>
  %d = osl.lane_deriv x %a : vector<4xf32>
  %m = arith.constant dense<true> : vector<4xi1>
  llvm.intr.masked.store %d, %arg1, %m {alignment = 4 : i32} : vector<4xf32>, vector<4xi1> into !llvm.ptr
  return
}

// -----

// OSL's dual pow (osl.dual_rule = "osl_pow" on lane::pow's select): where
// the derivative is taken the value becomes x^(y-1) * x (the select's
// plain operand is replaced by it), and the derivative is
// y x^(y-1) x' + x^y ln(x) y' (here x = u, y = 3: only the first term).
// CHECK-LABEL: func.func @osl_pow
// CHECK: %[[DU:.+]] = llvm.load %{{.+}} {alignment = 4 : i64, osl.derivative_row} : !llvm.ptr -> vector<4xf32>
// CHECK: math.powf %[[U:.+]], %{{.+}} : vector<4xf32>
// CHECK: %[[BELOW:.+]] = math.powf %[[U]], %{{.+}} : vector<4xf32>
// CHECK: %[[DUAL:.+]] = arith.mulf %[[BELOW]], %[[U]] : vector<4xf32>
// CHECK: %[[C:.+]] = arith.cmpf false, %[[U]], %[[Y:.+]] : vector<4xf32>
// CHECK: %[[V:.+]] = arith.select %[[C]], %[[DUAL]], %[[DUAL]] {osl.dual_rule = "osl_pow"}
// CHECK: %[[S:.+]] = arith.mulf %[[Y]], %[[BELOW]]
// CHECK: %[[D:.+]] = arith.mulf %[[S]], %[[DU]]
// CHECK: llvm.intr.masked.store %[[V]]
// CHECK: llvm.intr.masked.store %[[D]]
func.func @osl_pow(%arg0: !llvm.ptr, %arg1: !llvm.ptr, %arg2: i32) {
  %0 = llvm.getelementptr %arg0[132] : (!llvm.ptr) -> !llvm.ptr, f32
  %u = llvm.load %0 {alignment = 4 : i64, osl.global_row = 33 : i64} : !llvm.ptr -> vector<4xf32>
  %y = arith.constant dense<3.0> : vector<4xf32>
  %one = arith.constant dense<1.0> : vector<4xf32>
  %plain = math.powf %u, %y : vector<4xf32>
  %ybelow = arith.subf %y, %one : vector<4xf32>
  %below = math.powf %u, %ybelow : vector<4xf32>
  %dual = arith.mulf %below, %u : vector<4xf32>
  %c = arith.cmpf false, %u, %y : vector<4xf32>
  %v = arith.select %c, %dual, %plain {osl.dual_rule = "osl_pow"} : vector<4xi1>, vector<4xf32>
  %d = osl.lane_deriv x %v : vector<4xf32>
  %m = arith.constant dense<true> : vector<4xi1>
  llvm.intr.masked.store %v, %arg1, %m {alignment = 4 : i32} : vector<4xf32>, vector<4xi1> into !llvm.ptr
  %1 = llvm.getelementptr %arg1[4] : (!llvm.ptr) -> !llvm.ptr, f32
  llvm.intr.masked.store %d, %1, %m {alignment = 4 : i32} : vector<4xf32>, vector<4xi1> into !llvm.ptr
  return
}

// -----

// A value carried around a loop carries its derivative too: the loop is
// rebuilt with one more iter_arg, starting at d(init) (dudx, 140 floats in)
// and yielding the derivative of what the body yields (the product rule).
// CHECK-LABEL: func.func @loop_carried_for
// CHECK: %[[DU:.+]] = llvm.load %{{.+}} {alignment = 4 : i64, osl.derivative_row}
// CHECK: %[[R:.+]]:2 = scf.for %{{.+}} iter_args(%[[ACC:.+]] = %{{.+}}, %[[DACC:.+]] = %[[DU]]) -> (vector<4xf32>, vector<4xf32>)
// CHECK:   %[[N:.+]] = arith.mulf %[[ACC]], %[[ACC]]
// CHECK:   %[[A:.+]] = arith.mulf %[[DACC]], %[[ACC]]
// CHECK:   %[[B:.+]] = arith.mulf %[[ACC]], %[[DACC]]
// CHECK:   %[[S:.+]] = arith.addf %[[A]], %[[B]]
// CHECK:   scf.yield %[[N]], %[[S]]
// CHECK: } {osl.primal_counts = array<i64: 1, 1>}
// CHECK: %[[MARKED:.+]] = arith.addf %[[R]]#1, %{{.+}} {osl.no_derivative}
// CHECK: llvm.intr.masked.store %[[MARKED]]
// CHECK-NOT: osl.lane_deriv
func.func @loop_carried_for(%arg0: !llvm.ptr, %arg1: !llvm.ptr, %arg2: i32) {
  %0 = llvm.getelementptr %arg0[132] : (!llvm.ptr) -> !llvm.ptr, f32
  %u = llvm.load %0 {alignment = 4 : i64, osl.global_row = 33 : i64} : !llvm.ptr -> vector<4xf32>
  %c0 = arith.constant 0 : index
  %c4 = arith.constant 4 : index
  %c1 = arith.constant 1 : index
  %r = scf.for %i = %c0 to %c4 step %c1 iter_args(%acc = %u) -> (vector<4xf32>) {
    %n = arith.mulf %acc, %acc : vector<4xf32>
    scf.yield %n : vector<4xf32>
  }
  %d = osl.lane_deriv x %r : vector<4xf32>
  %m = arith.constant dense<true> : vector<4xi1>
  llvm.intr.masked.store %d, %arg1, %m {alignment = 4 : i32} : vector<4xf32>, vector<4xi1> into !llvm.ptr
  return
}

// -----

// A while loop: the derivative goes around through the condition's
// forwarded values and the body's yield (x * 1.5 gives dx * 1.5); the int
// counter carries none.
// CHECK-LABEL: func.func @loop_carried_while
// CHECK: %[[DU:.+]] = llvm.load %{{.+}} {alignment = 4 : i64, osl.derivative_row}
// CHECK: %[[R:.+]]:3 = scf.while (%[[X:.+]] = %{{.+}}, %[[K:.+]] = %{{.+}}, %[[DX:.+]] = %[[DU]]) : (vector<4xf32>, i32, vector<4xf32>) -> (vector<4xf32>, i32, vector<4xf32>)
// CHECK:   scf.condition(%{{.+}}) %[[X]], %[[K]], %[[DX]]
// CHECK: ^bb0(%[[X2:.+]]: vector<4xf32>, %[[K2:.+]]: i32, %[[DX2:.+]]: vector<4xf32>):
// CHECK:   %[[D:.+]] = arith.mulf %[[DX2]], %{{.+}}
// CHECK:   scf.yield %{{.+}}, %{{.+}}, %[[D]]
// CHECK: %[[MARKED:.+]] = arith.addf %[[R]]#2, %{{.+}} {osl.no_derivative}
// CHECK: llvm.intr.masked.store %[[MARKED]]
func.func @loop_carried_while(%arg0: !llvm.ptr, %arg1: !llvm.ptr, %arg2: i32) {
  %0 = llvm.getelementptr %arg0[132] : (!llvm.ptr) -> !llvm.ptr, f32
  %u = llvm.load %0 {alignment = 4 : i64, osl.global_row = 33 : i64} : !llvm.ptr -> vector<4xf32>
  %k0 = arith.constant 0 : i32
  %two = arith.constant dense<2.0> : vector<4xf32>
  %r:2 = scf.while (%x = %u, %k = %k0) : (vector<4xf32>, i32) -> (vector<4xf32>, i32) {
    %lt = arith.cmpf olt, %x, %two : vector<4xf32>
    %any = vector.reduction <or>, %lt : vector<4xi1> into i1
    scf.condition(%any) %x, %k : vector<4xf32>, i32
  } do {
  ^bb0(%x2: vector<4xf32>, %k2: i32):
    %f = arith.constant dense<1.5> : vector<4xf32>
    %n = arith.mulf %x2, %f : vector<4xf32>
    %one = arith.constant 1 : i32
    %k3 = arith.addi %k2, %one : i32
    scf.yield %n, %k3 : vector<4xf32>, i32
  }
  %d = osl.lane_deriv x %r#0 : vector<4xf32>
  %m = arith.constant dense<true> : vector<4xi1>
  llvm.intr.masked.store %d, %arg1, %m {alignment = 4 : i32} : vector<4xf32>, vector<4xi1> into !llvm.ptr
  return
}

// -----

// Both Dx and Dy of a value a loop computes under a branch (a `break`'s
// flag): the loop is rebuilt once per axis, and the second rebuild must not
// differentiate the derivative the first added to the branch (that led back
// to the loop being rebuilt, forever).
// CHECK-LABEL: func.func @both_axes_through_branch
// CHECK: %[[R:.+]]:4 = scf.while
// CHECK: scf.if %{{.+}} -> (vector<4xf32>, vector<4xf32>, vector<4xf32>)
// CHECK: arith.addf %[[R]]#2
// CHECK: arith.addf %[[R]]#3
func.func @both_axes_through_branch(%arg0: !llvm.ptr, %arg1: !llvm.ptr, %arg2: i32) {
  %0 = llvm.getelementptr %arg0[132] : (!llvm.ptr) -> !llvm.ptr, f32
  %u = llvm.load %0 {alignment = 4 : i64, osl.global_row = 33 : i64} : !llvm.ptr -> vector<4xf32>
  %k0 = arith.constant 0 : i32
  %one = arith.constant 1 : i32
  %three = arith.constant 3 : i32
  %r:2 = scf.while (%x = %u, %k = %k0) : (vector<4xf32>, i32) -> (vector<4xf32>, i32) {
    %go = arith.cmpi slt, %k, %three : i32
    scf.condition(%go) %x, %k : vector<4xf32>, i32
  } do {
  ^bb0(%x2: vector<4xf32>, %k2: i32):
    %early = arith.cmpi sgt, %k2, %one : i32
    %n = scf.if %early -> (vector<4xf32>) {
      scf.yield %x2 : vector<4xf32>
    } else {
      %f = arith.constant dense<2.0> : vector<4xf32>
      %twice = arith.mulf %x2, %f : vector<4xf32>
      scf.yield %twice : vector<4xf32>
    }
    %k3 = arith.addi %k2, %one : i32
    scf.yield %n, %k3 : vector<4xf32>, i32
  }
  %dx = osl.lane_deriv x %r#0 : vector<4xf32>
  %dy = osl.lane_deriv y %r#0 : vector<4xf32>
  %m = arith.constant dense<true> : vector<4xi1>
  llvm.intr.masked.store %dx, %arg1, %m {alignment = 4 : i32} : vector<4xf32>, vector<4xi1> into !llvm.ptr
  llvm.intr.masked.store %dy, %arg1, %m {alignment = 4 : i32} : vector<4xf32>, vector<4xi1> into !llvm.ptr
  return
}

// -----

// A uniform (scalar) value carried around a loop, like an fbm's frequency,
// meets the varying u through a broadcast: the same at every point, so its
// derivative is 0 and d(u * freq)/dx is dudx * freq (row 35: 140 floats in).
// CHECK-LABEL: func.func @uniform_loop_carried
// CHECK: %[[ROW:.+]] = llvm.getelementptr %arg0[140]
// CHECK: %[[DU:.+]] = llvm.load %[[ROW]]
// CHECK: scf.for %{{.+}} iter_args(%[[F:.+]] = %{{.+}}) -> (f32)
// CHECK: %[[B:.+]] = vector.broadcast %[[F]] : f32 to vector<4xf32>
// CHECK: %[[D:.+]] = arith.mulf %[[DU]], %[[B]] {{.*}}: vector<4xf32>
// CHECK: llvm.intr.masked.store %[[D]]
// CHECK-NOT: osl.lane_deriv
func.func @uniform_loop_carried(%arg0: !llvm.ptr, %arg1: !llvm.ptr, %arg2: i32) {
  %0 = llvm.getelementptr %arg0[132] : (!llvm.ptr) -> !llvm.ptr, f32
  %u = llvm.load %0 {alignment = 4 : i64, osl.global_row = 33 : i64} : !llvm.ptr -> vector<4xf32>
  %c0 = arith.constant 0 : index
  %c4 = arith.constant 4 : index
  %c1 = arith.constant 1 : index
  %one = arith.constant 1.0 : f32
  %two = arith.constant 2.0 : f32
  %r = scf.for %i = %c0 to %c4 step %c1 iter_args(%freq = %one) -> (f32) {
    %b = vector.broadcast %freq : f32 to vector<4xf32>
    %p = arith.mulf %u, %b : vector<4xf32>
    %d = osl.lane_deriv x %p : vector<4xf32>
    %m = arith.constant dense<true> : vector<4xi1>
    llvm.intr.masked.store %d, %arg1, %m {alignment = 4 : i32} : vector<4xf32>, vector<4xi1> into !llvm.ptr
    %next = arith.mulf %freq, %two : f32
    scf.yield %next : f32
  }
  return
}

// -----

// A value chosen by a uniform branch: the branch is rebuilt to also yield
// the derivative of what each arm yields (marked as a derivative through
// + -0, which folds away later, since the branch itself stays
// differentiable).
// CHECK-LABEL: func.func @uniform_branch
// CHECK: %[[R:.+]]:2 = scf.if %arg3 -> (vector<4xf32>, vector<4xf32>) {
// CHECK:   %[[T:.+]] = arith.mulf %[[U:.+]], %{{.+}}
// CHECK:   %[[D:.+]] = arith.mulf %{{.+}}, %{{.+}}
// CHECK:   scf.yield %[[T]], %[[D]]
// CHECK: } else {
// CHECK:   %[[Z:.+]] = arith.constant dense<0.000000e+00>
// CHECK:   scf.yield %{{.+}}, %[[Z]]
// CHECK: %[[MARKED:.+]] = arith.addf %[[R]]#1, %{{.+}} {osl.no_derivative}
// CHECK: llvm.intr.masked.store %[[MARKED]]
func.func @uniform_branch(%arg0: !llvm.ptr, %arg1: !llvm.ptr, %arg2: i32, %arg3: i1) {
  %0 = llvm.getelementptr %arg0[132] : (!llvm.ptr) -> !llvm.ptr, f32
  %u = llvm.load %0 {alignment = 4 : i64, osl.global_row = 33 : i64} : !llvm.ptr -> vector<4xf32>
  %r = scf.if %arg3 -> (vector<4xf32>) {
    %two = arith.constant dense<2.0> : vector<4xf32>
    %t = arith.mulf %u, %two : vector<4xf32>
    scf.yield %t : vector<4xf32>
  } else {
    %c = arith.constant dense<1.0> : vector<4xf32>
    scf.yield %c : vector<4xf32>
  }
  %d = osl.lane_deriv x %r : vector<4xf32>
  %m = arith.constant dense<true> : vector<4xi1>
  llvm.intr.masked.store %d, %arg1, %m {alignment = 4 : i32} : vector<4xf32>, vector<4xi1> into !llvm.ptr
  return
}

// -----

// A derivative has none of its own: the outer request, resolved first,
// sees the inner one still there and gives 0.
// CHECK-LABEL: func.func @derivative_of_derivative
// CHECK: %[[ZERO:.+]] = arith.constant {{.*}}dense<0.000000e+00> : vector<4xf32>
// CHECK: llvm.intr.masked.store %[[ZERO]]
// CHECK-NOT: osl.lane_deriv
func.func @derivative_of_derivative(%arg0: !llvm.ptr, %arg1: !llvm.ptr, %arg2: i32) {
  %0 = llvm.getelementptr %arg0[132] : (!llvm.ptr) -> !llvm.ptr, f32
  %u = llvm.load %0 {alignment = 4 : i64, osl.global_row = 33 : i64} : !llvm.ptr -> vector<4xf32>
  %sq = arith.mulf %u, %u : vector<4xf32>
  %d = osl.lane_deriv x %sq : vector<4xf32>
  %dd = osl.lane_deriv y %d : vector<4xf32>
  %m = arith.constant dense<true> : vector<4xi1>
  llvm.intr.masked.store %dd, %arg1, %m {alignment = 4 : i32} : vector<4xf32>, vector<4xi1> into !llvm.ptr
  return
}

// -----

// A call of a library function built from a recipe that its site may
// inline (no osl.keep_call): its code is copied in place of the call a
// derivative needs, and the chain rule goes through it (here u + u, so
// d/dx is dudx + dudx); the other call stays.
// CHECK-LABEL: func.func @library_call_inlined
// CHECK: %[[DU:.+]] = llvm.getelementptr %arg0[140]
// CHECK: %[[D:.+]] = llvm.load %[[DU]]
// CHECK: %[[U:.+]] = llvm.load
// CHECK: call @osl.lib.noise_perlin.1(%[[U]])
// CHECK-NOT: call
// CHECK: arith.addf %[[U]], %[[U]]
// CHECK: arith.addf %[[D]], %[[D]]
// CHECK-NOT: osl.lane_deriv
func.func @library_call_inlined(%arg0: !llvm.ptr, %arg1: !llvm.ptr, %arg2: i32) {
  %0 = llvm.getelementptr %arg0[132] : (!llvm.ptr) -> !llvm.ptr, f32
  %u = llvm.load %0 {alignment = 4 : i64, osl.global_row = 33 : i64} : !llvm.ptr -> vector<4xf32>
  %kept = call @osl.lib.noise_perlin.1(%u) : (vector<4xf32>) -> vector<4xf32>
  %twice = call @osl.lib.noise_perlin.1(%u) : (vector<4xf32>) -> vector<4xf32>
  %d = osl.lane_deriv x %twice : vector<4xf32>
  %sum = arith.addf %d, %kept : vector<4xf32>
  %m = arith.constant dense<true> : vector<4xi1>
  llvm.intr.masked.store %sum, %arg1, %m {alignment = 4 : i32} : vector<4xf32>, vector<4xi1> into !llvm.ptr
  return
}
func.func private @osl.lib.noise_perlin.1(%x: vector<4xf32>) -> vector<4xf32>
    attributes {osl.library_recipe = "twice"} {
  %t = arith.addf %x, %x : vector<4xf32>
  return %t : vector<4xf32>
}

// -----

// A call its site keeps (too big to inline) is differentiated by a call of
// the routine's dual: its code and derivatives along x and y, given the
// argument's tangents (dudx made here, dudy asked for and made by the y
// axis), built from the routine's code (here u * u: 2 u u').
// CHECK-LABEL: func.func @library_call_dual
// CHECK-DAG: %[[DUDX:.+]] = llvm.load %{{.+}} {{.*}}osl.derivative_row{{.*}} -> vector<4xf32>
// CHECK-DAG: %[[DUDY:.+]] = llvm.load %{{.+}} {{.*}}osl.derivative_row{{.*}} -> vector<4xf32>
// CHECK: %[[R:.+]]:3 = call @[[D:osl\.lib\.noise_perlin_dual\.[0-9a-f]+]](%{{.+}}, %[[DUDX]], %[[DUDY]]) {osl.keep_call
// CHECK-NOT: call
// CHECK: arith.addf %[[R]]#1, %[[R]]#2
// CHECK-NOT: osl.lane_deriv
// CHECK: func.func private @[[D]](%[[X:.+]]: vector<4xf32>, %[[TX:.+]]: vector<4xf32>, %[[TY:.+]]: vector<4xf32>) -> (vector<4xf32>, vector<4xf32>, vector<4xf32>)
// CHECK-SAME: osl.library_recipe = "square dual x y"
// CHECK: %[[M:.+]] = arith.mulf %[[X]], %[[X]]
// CHECK-DAG: arith.mulf %[[TX]], %[[X]]
// CHECK-DAG: arith.mulf %[[TY]], %[[X]]
// CHECK: return %[[M]],
// COMPILED-LABEL: func.func @library_call_dual
// COMPILED: call @osl.lib.noise_perlin_dual.{{[0-9a-f]+}}(
// COMPILED: func.func private @osl.lib.noise_perlin_dual.{{[0-9a-f]+}}(vector<4xf32>, vector<4xf32>, vector<4xf32>) -> (vector<4xf32>, vector<4xf32>, vector<4xf32>)
func.func @library_call_dual(%arg0: !llvm.ptr, %arg1: !llvm.ptr, %arg2: i32) {
  %0 = llvm.getelementptr %arg0[132] : (!llvm.ptr) -> !llvm.ptr, f32
  %u = llvm.load %0 {alignment = 4 : i64, osl.global_row = 33 : i64} : !llvm.ptr -> vector<4xf32>
  %n = call @osl.lib.noise_perlin.3(%u) {osl.keep_call} : (vector<4xf32>) -> vector<4xf32>
  %dx = osl.lane_deriv x %n : vector<4xf32>
  %dy = osl.lane_deriv y %n : vector<4xf32>
  %sum = arith.addf %dx, %dy : vector<4xf32>
  %m = arith.constant dense<true> : vector<4xi1>
  llvm.intr.masked.store %sum, %arg1, %m {alignment = 4 : i32} : vector<4xf32>, vector<4xi1> into !llvm.ptr
  return
}
func.func private @osl.lib.noise_perlin.3(%x: vector<4xf32>) -> vector<4xf32>
    attributes {osl.library_recipe = "square"} {
  %t = arith.mulf %x, %x : vector<4xf32>
  return %t : vector<4xf32>
}

// -----

// A routine compiled before is only declared: there is no code to copy in
// place (osl-convert-to-vector builds every routine a derivative depends
// on, so this is the compiler's error, not the shader's).
func.func @library_declaration(%arg0: !llvm.ptr, %arg1: !llvm.ptr, %arg2: i32) {
  %0 = llvm.getelementptr %arg0[132] : (!llvm.ptr) -> !llvm.ptr, f32
  %u = llvm.load %0 {alignment = 4 : i64, osl.global_row = 33 : i64} : !llvm.ptr -> vector<4xf32>
  %n = call @osl.lib.noise_perlin.2(%u) : (vector<4xf32>) -> vector<4xf32>
  // expected-error @+1 {{cannot take the derivative through a library routine whose code was not built yet}}
  %d = osl.lane_deriv x %n : vector<4xf32>
  %m = arith.constant dense<true> : vector<4xi1>
  llvm.intr.masked.store %d, %arg1, %m {alignment = 4 : i32} : vector<4xf32>, vector<4xi1> into !llvm.ptr
  return
}
func.func private @osl.lib.noise_perlin.2(vector<4xf32>) -> vector<4xf32>
    attributes {osl.library_recipe = "declared"}

// -----

// OSL's dual division: (x' - (x/y) y') times 1/y, and 1/y is 0 where it is
// not finite (rounded as OSL rounds it: normalize's derivative is then
// OSL's to the last bit). With x = 1 and y = u: -(q dudx) * (1/u).
// CHECK-LABEL: func.func @dual_division
// CHECK: %[[DU:.+]] = llvm.load %{{.+}} {alignment = 4 : i64, osl.derivative_row} : !llvm.ptr -> vector<4xf32>
// CHECK: %[[Q:.+]] = arith.divf %[[ONE:.+]], %[[U:.+]] : vector<4xf32>
// CHECK: %[[QDU:.+]] = arith.mulf %[[Q]], %[[DU]]
// CHECK: %[[NUM:.+]] = arith.negf %[[QDU]]
// CHECK: %[[INV:.+]] = arith.divf %{{.+}}, %[[U]]
// CHECK: %[[ABS:.+]] = math.absf %[[INV]]
// CHECK: %[[FINITE:.+]] = arith.cmpf olt, %[[ABS]], %{{.+}}
// CHECK: %[[SAFE:.+]] = arith.select %[[FINITE]], %[[INV]], %{{.+}}
// CHECK: %[[D:.+]] = arith.mulf %[[SAFE]], %[[NUM]]
// CHECK: llvm.intr.masked.store %[[D]]
func.func @dual_division(%arg0: !llvm.ptr, %arg1: !llvm.ptr, %arg2: i32) {
  %0 = llvm.getelementptr %arg0[132] : (!llvm.ptr) -> !llvm.ptr, f32
  %u = llvm.load %0 {alignment = 4 : i64, osl.global_row = 33 : i64} : !llvm.ptr -> vector<4xf32>
  %one = arith.constant dense<1.0> : vector<4xf32>
  %q = arith.divf %one, %u : vector<4xf32>
  %d = osl.lane_deriv x %q : vector<4xf32>
  %m = arith.constant dense<true> : vector<4xi1>
  llvm.intr.masked.store %d, %arg1, %m {alignment = 4 : i32} : vector<4xf32>, vector<4xi1> into !llvm.ptr
  return
}

// -----

// A picked element's derivative is the same pick of the elements'
// derivatives: dudx (row 35) for u, 0 for a constant.
// CHECK-LABEL: func.func @lane_pick
// CHECK: %[[DU:.+]] = llvm.load %{{.+}} {alignment = 4 : i64, osl.derivative_row}
// CHECK: osl.lane_pick %[[I:[^,]+]], [%{{.+}}, %{{.+}}] :
// CHECK: %[[ZERO:.+]] = arith.constant dense<0.000000e+00> : vector<4xf32>
// CHECK: %[[D:.+]] = osl.lane_pick %[[I]], [%[[DU]], %[[ZERO]]]
// CHECK: llvm.intr.masked.store %[[D]]
// CHECK-NOT: osl.lane_deriv
func.func @lane_pick(%arg0: !llvm.ptr, %arg1: !llvm.ptr, %arg2: i32, %i: vector<4xi32>) {
  %0 = llvm.getelementptr %arg0[132] : (!llvm.ptr) -> !llvm.ptr, f32
  %u = llvm.load %0 {alignment = 4 : i64, osl.global_row = 33 : i64} : !llvm.ptr -> vector<4xf32>
  %c = arith.constant dense<2.0> : vector<4xf32>
  %p = osl.lane_pick %i, [%u, %c] : vector<4xi32>, [vector<4xf32>, vector<4xf32>] -> vector<4xf32>
  %d = osl.lane_deriv x %p : vector<4xf32>
  %m = arith.constant dense<true> : vector<4xi1>
  llvm.intr.masked.store %d, %arg1, %m {alignment = 4 : i32} : vector<4xf32>, vector<4xi1> into !llvm.ptr
  return
}
