// RUN: osl-opt %s -split-input-file --osl-lower-to-llvm | FileCheck %s

// Structured loops become branches; an OR reduction is an LLVM intrinsic.
// CHECK-LABEL: llvm.func @loop_until_no_lane_active
// CHECK: llvm.intr.vector.reduce.or
// CHECK: llvm.cond_br
func.func @loop_until_no_lane_active(%m: vector<4xi1>) -> vector<4xi1> {
  %r = scf.while (%x = %m) : (vector<4xi1>) -> vector<4xi1> {
    %any = vector.reduction <or>, %x : vector<4xi1> into i1
    scf.condition(%any) %x : vector<4xi1>
  } do {
  ^bb0(%x: vector<4xi1>):
    %f = arith.constant dense<false> : vector<4xi1>
    scf.yield %f : vector<4xi1>
  }
  return %r : vector<4xi1>
}

// -----

// Triples of W lanes (vector<3xWxf32>) lower to arrays of 1-D vectors.
// A branch on whether any lane takes an arm (osl-insert-mask-stack's
// guard) says skipping is likely, so that LLVM keeps it a branch; a
// loop's branch on the same kind of test has no weights.
// CHECK-LABEL: llvm.func @lane_guard_weights
// CHECK: llvm.cond_br %{{.+}} weights([1, 1000]), ^bb1, ^bb2
// CHECK: llvm.cond_br %{{[0-9]+}}, ^
// CHECK-NOT: weights
func.func @lane_guard_weights(%m: vector<4xi1>, %x: vector<4xf32>) -> vector<4xf32> {
  %any = vector.reduction <or>, %m : vector<4xi1> into i1
  %g = scf.if %any -> vector<4xf32> {
    %s = arith.addf %x, %x : vector<4xf32>
    scf.yield %s : vector<4xf32>
  } else {
    scf.yield %x : vector<4xf32>
  }
  %r = scf.while (%y = %m) : (vector<4xi1>) -> vector<4xi1> {
    %more = vector.reduction <or>, %y : vector<4xi1> into i1
    scf.condition(%more) %y : vector<4xi1>
  } do {
  ^bb0(%y: vector<4xi1>):
    %f = arith.constant dense<false> : vector<4xi1>
    scf.yield %f : vector<4xi1>
  }
  return %g : vector<4xf32>
}

// -----

// A cold arm's guard (osl.cold_arm on its test: the arm reports an error)
// says skipping is likely whatever the arm's size; a large arm's that is
// not cold has no weights.
// CHECK-LABEL: llvm.func @cold_arm_weights
// CHECK: llvm.cond_br %{{.+}} weights([1, 1000])
// CHECK: llvm.call @report
// CHECK: llvm.cond_br %{{[0-9]+}}, ^
// CHECK-NOT: weights
// CHECK: llvm.call @work
func.func private @report(vector<4xf32>)
func.func private @work(vector<4xf32>)
func.func @cold_arm_weights(%m: vector<4xi1>, %x: vector<4xf32>) {
  %cold = vector.reduction <or>, %m {osl.cold_arm} : vector<4xi1> into i1
  scf.if %cold {
    func.call @report(%x) : (vector<4xf32>) -> ()
  }
  %any = vector.reduction <or>, %m : vector<4xi1> into i1
  scf.if %any {
    func.call @work(%x) : (vector<4xf32>) -> ()
  }
  return
}

// -----

// CHECK-LABEL: llvm.func @triple_rows
// CHECK: llvm.extractvalue %{{.+}}[1] : !llvm.array<3 x vector<8xf32>>
func.func @triple_rows(%t: vector<3x8xf32>) -> vector<8xf32> {
  %y = vector.extract %t[1] : vector<8xf32> from vector<3x8xf32>
  return %y : vector<8xf32>
}

// -----

// (x << k) | (x >> (32 - k)) is a rotate: one funnel shift. Shifts that do
// not add up to the width stay as they are.
// CHECK-LABEL: llvm.func @rotates
// CHECK: %[[K:.+]] = llvm.mlir.constant(dense<14> : vector<4xi32>) : vector<4xi32>
// CHECK: %[[HI:.+]] = llvm.shl %[[X:.+]], %[[K]]
// CHECK: %[[ROT:.+]] = llvm.intr.fshl(%[[X]], %[[X]], %[[K]]) : (vector<4xi32>, vector<4xi32>, vector<4xi32>) -> vector<4xi32>
// CHECK: %[[LO:.+]] = llvm.lshr %[[X]]
// CHECK: %[[NOT:.+]] = llvm.or %[[HI]], %[[LO]]
// CHECK: llvm.insertvalue %[[ROT]]
// CHECK: llvm.insertvalue %[[NOT]]
func.func @rotates(%x: vector<4xi32>) -> (vector<4xi32>, vector<4xi32>) {
  %k = arith.constant dense<14> : vector<4xi32>
  %rest = arith.constant dense<18> : vector<4xi32>
  %three = arith.constant dense<3> : vector<4xi32>
  %hi = arith.shli %x, %k : vector<4xi32>
  %lo = arith.shrui %x, %rest : vector<4xi32>
  %rot = arith.ori %lo, %hi : vector<4xi32>
  %lo3 = arith.shrui %x, %three : vector<4xi32>
  %not = arith.ori %hi, %lo3 : vector<4xi32>
  return %rot, %not : vector<4xi32>, vector<4xi32>
}

// -----

// A fence is llvm.arithmetic.fence between bitcasts to f32 and back, for
// W lanes and for a scalar alike.
// CHECK-LABEL: llvm.func @codegen_fences
// CHECK: %[[F:.+]] = llvm.bitcast %{{.+}} : vector<4xi32> to vector<4xf32>
// CHECK: %[[G:.+]] = llvm.call_intrinsic "llvm.arithmetic.fence"(%[[F]]) : (vector<4xf32>) -> vector<4xf32>
// CHECK: llvm.bitcast %[[G]] : vector<4xf32> to vector<4xi32>
// CHECK: %[[S:.+]] = llvm.bitcast %{{.+}} : i32 to f32
// CHECK: %[[T:.+]] = llvm.call_intrinsic "llvm.arithmetic.fence"(%[[S]]) : (f32) -> f32
// CHECK: llvm.bitcast %[[T]] : f32 to i32
// CHECK-NOT: osl.codegen_fence
func.func @codegen_fences(%x: vector<4xi32>, %n: i32) -> (vector<4xi32>, i32) {
  %a = osl.codegen_fence %x : vector<4xi32>
  %b = osl.codegen_fence %n : i32
  return %a, %b : vector<4xi32>, i32
}

// -----

// Lanes dividing by ints not known to be one constant divide in double
// precision (an exact quotient, truncated by the conversion back); a
// remainder is n - q*d. A constant divisor stays an sdiv, and a scalar's
// too: LLVM multiplies by constants, and one idiv serves a scalar. 64-bit
// lanes stay: a double does not hold every such int.
// CHECK-LABEL: llvm.func @divide_lanes
// CHECK-DAG: %[[N:.+]] = llvm.sitofp %[[NUM:[^ ]+]] : vector<8xi32> to vector<8xf64>
// CHECK-DAG: %[[D:.+]] = llvm.sitofp %[[DEN:[^ ]+]] : vector<8xi32> to vector<8xf64>
// CHECK: %[[Q:.+]] = llvm.fdiv %[[N]], %[[D]] : vector<8xf64>
// CHECK: %[[QI:.+]] = llvm.fptosi %[[Q]] : vector<8xf64> to vector<8xi32>
// CHECK-NOT: llvm.srem
// CHECK: llvm.fdiv {{.*}} : vector<8xf64>
// CHECK: %[[R:.+]] = llvm.fptosi {{.*}} : vector<8xf64> to vector<8xi32>
// CHECK: %[[P:.+]] = llvm.mul %[[R]], %[[DEN]]
// CHECK: llvm.sub %[[NUM]], %[[P]]
// CHECK: llvm.sdiv {{.*}} : vector<8xi32>
// CHECK: llvm.sdiv {{.*}} : i32
// CHECK: llvm.sdiv {{.*}} : vector<4xi64>
// CHECK: llvm.return
func.func @divide_lanes(%n: vector<8xi32>, %d: vector<8xi32>, %s: i32, %t: i32,
                        %wide: vector<4xi64>, %wideDen: vector<4xi64>)
    -> (vector<8xi32>, vector<8xi32>, vector<8xi32>, i32, vector<4xi64>) {
  %three = arith.constant dense<3> : vector<8xi32>
  %q = arith.divsi %n, %d : vector<8xi32>
  %r = arith.remsi %n, %d : vector<8xi32>
  %k = arith.divsi %n, %three : vector<8xi32>
  %one = arith.divsi %s, %t : i32
  %w = arith.divsi %wide, %wideDen : vector<4xi64>
  return %q, %r, %k, %one, %w : vector<8xi32>, vector<8xi32>, vector<8xi32>, i32, vector<4xi64>
}

// -----

// osl.lane_pick: the elements go to a stack block in the entry block, each
// stored right after its definition (not kept live until the read), and a
// per-lane index gathers lane l of element i[l] (i[l] * 4 + l); a second
// pick of the same list shares the block and a uniform index loads.
// CHECK-LABEL: llvm.func @pick_from_memory
// CHECK: %[[BLOCK:.+]] = llvm.alloca %{{.+}} x !llvm.array<3 x vector<4xf32>>
// CHECK-NOT: llvm.alloca
// CHECK: %[[SLOT0:.+]] = llvm.getelementptr %[[BLOCK]][0, 0]
// CHECK: llvm.store %arg0, %[[SLOT0]]
// CHECK: %[[X:.+]] = llvm.fmul %arg0, %arg0
// CHECK-NEXT: %[[SLOT1:.+]] = llvm.getelementptr %[[BLOCK]][0, 1]
// CHECK-NEXT: llvm.store %[[X]], %[[SLOT1]]
// CHECK: llvm.getelementptr %[[BLOCK]][0, 2]
// CHECK: %[[LANES:.+]] = llvm.mlir.constant(dense<[0, 1, 2, 3]> : vector<4xi32>)
// CHECK: %[[STRIDE:.+]] = llvm.mlir.constant(dense<4> : vector<4xi32>)
// CHECK: %[[ROW:.+]] = llvm.mul %arg1, %[[STRIDE]]
// CHECK: %[[AT:.+]] = llvm.add %[[ROW]], %[[LANES]]
// CHECK: %[[ADDRS:.+]] = llvm.getelementptr %[[BLOCK]][%[[AT]]] : (!llvm.ptr, vector<4xi32>) -> !llvm.vec<4 x ptr>, f32
// CHECK: llvm.intr.masked.gather %[[ADDRS]]
// CHECK: %[[ONE:.+]] = llvm.getelementptr %[[BLOCK]][0, %arg2]
// CHECK: llvm.load %[[ONE]] : !llvm.ptr -> vector<4xf32>
// CHECK-NOT: llvm.select
func.func @pick_from_memory(%a: vector<4xf32>, %i: vector<4xi32>, %j: i32) -> vector<4xf32> {
  %x = arith.mulf %a, %a : vector<4xf32>
  %y = arith.addf %x, %a : vector<4xf32>
  %p = osl.lane_pick %i, [%a, %x, %y] : vector<4xi32>, [vector<4xf32>, vector<4xf32>, vector<4xf32>] -> vector<4xf32>
  %q = osl.lane_pick %j, [%a, %x, %y] : i32, [vector<4xf32>, vector<4xf32>, vector<4xf32>] -> vector<4xf32>
  %r = arith.addf %p, %q : vector<4xf32>
  return %r : vector<4xf32>
}

// -----

// A pick in a loop that redefines its elements each trip selects over
// them from the last element down, rather than storing them every trip.
// CHECK-LABEL: llvm.func @pick_in_loop_selects
// CHECK-NOT: llvm.alloca
// CHECK: llvm.icmp "sle" %{{.+}}, %{{.+}} : vector<4xi32>
// CHECK: llvm.select
// CHECK: llvm.icmp "sle"
// CHECK: llvm.select
// CHECK-NOT: llvm.intr.masked.gather
func.func @pick_in_loop_selects(%a: vector<4xf32>, %i: vector<4xi32>, %n: i32) -> vector<4xf32> {
  %c0 = arith.constant 0 : i32
  %c1 = arith.constant 1 : i32
  %r:2 = scf.while (%k = %c0, %x = %a) : (i32, vector<4xf32>) -> (i32, vector<4xf32>) {
    %go = arith.cmpi slt, %k, %n : i32
    scf.condition(%go) %k, %x : i32, vector<4xf32>
  } do {
  ^bb0(%k: i32, %x: vector<4xf32>):
    %y = arith.mulf %x, %x : vector<4xf32>
    %p = osl.lane_pick %i, [%a, %x, %y] : vector<4xi32>, [vector<4xf32>, vector<4xf32>, vector<4xf32>] -> vector<4xf32>
    %k1 = arith.addi %k, %c1 : i32
    scf.yield %k1, %p : i32, vector<4xf32>
  }
  return %r#1 : vector<4xf32>
}
