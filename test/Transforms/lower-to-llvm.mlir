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
