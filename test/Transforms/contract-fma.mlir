// RUN: osl-opt %s -split-input-file --osl-contract-fma | FileCheck %s

// A product that feeds only an add or a subtract fuses with it.
// CHECK-LABEL: func.func @fuse
// CHECK-SAME: (%[[A:.+]]: vector<8xf32>, %[[B:.+]]: vector<8xf32>, %[[C:.+]]: vector<8xf32>)
// CHECK: %[[F1:.+]] = math.fma %[[A]], %[[B]], %[[C]] : vector<8xf32>
// CHECK: %[[F2:.+]] = math.fma %[[A]], %[[C]], %[[F1]] : vector<8xf32>
// CHECK: %[[NC:.+]] = arith.negf %[[C]] : vector<8xf32>
// CHECK: %[[F3:.+]] = math.fma %[[B]], %[[B]], %[[NC]] : vector<8xf32>
// CHECK: %[[NA:.+]] = arith.negf %[[A]] : vector<8xf32>
// CHECK: math.fma %[[NA]], %[[C]], %[[F3]] : vector<8xf32>
func.func @fuse(%a: vector<8xf32>, %b: vector<8xf32>, %c: vector<8xf32>) -> vector<8xf32> {
  %m1 = arith.mulf %a, %b : vector<8xf32>
  %s1 = arith.addf %m1, %c : vector<8xf32>
  %m2 = arith.mulf %a, %c : vector<8xf32>
  %s2 = arith.addf %s1, %m2 : vector<8xf32>
  %m3 = arith.mulf %b, %b : vector<8xf32>
  %s3 = arith.subf %m3, %c : vector<8xf32>
  %m4 = arith.mulf %a, %c : vector<8xf32>
  %s4 = arith.subf %s3, %m4 : vector<8xf32>
  %r = arith.addf %s4, %s2 : vector<8xf32>
  return %r : vector<8xf32>
}

// -----

// A product used twice stays a product: fusing one use would round it
// differently from the other.
// CHECK-LABEL: func.func @shared_product
// CHECK: %[[M:.+]] = arith.mulf
// CHECK: arith.addf %[[M]]
// CHECK: arith.addf %[[M]]
// CHECK-NOT: math.fma
func.func @shared_product(%a: f32, %b: f32, %c: f32) -> (f32, f32) {
  %m = arith.mulf %a, %b : f32
  %s = arith.addf %m, %c : f32
  %t = arith.addf %m, %a : f32
  return %s, %t : f32, f32
}
