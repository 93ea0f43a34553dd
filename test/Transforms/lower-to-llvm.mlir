// RUN: osl-opt %s -split-input-file --osl-lower-to-llvm | FileCheck %s

// sin on 16 lanes becomes a polynomial in vector registers, never 16
// calls to sinf.
// CHECK-LABEL: llvm.func @sin_is_a_polynomial
// CHECK-NOT: llvm.call
// CHECK-NOT: math.sin
// CHECK: llvm.fmul %{{.+}}, %{{.+}} : vector<16xf32>
func.func @sin_is_a_polynomial(%x: vector<16xf32>) -> vector<16xf32> {
  %s = math.sin %x : vector<16xf32>
  return %s : vector<16xf32>
}

// -----

// pow expands into exp and log approximations, also without calls.
// CHECK-LABEL: llvm.func @pow_is_inline
// CHECK-NOT: llvm.call
// CHECK-NOT: math.
func.func @pow_is_inline(%x: vector<8xf32>, %y: vector<8xf32>) -> vector<8xf32> {
  %p = math.powf %x, %y : vector<8xf32>
  return %p : vector<8xf32>
}

// -----

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
