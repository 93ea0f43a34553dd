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
