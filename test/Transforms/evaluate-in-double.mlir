// RUN: osl-opt %s -split-input-file --osl-evaluate-in-double | FileCheck %s

// Arithmetic, constants and comparisons become f64; the loaded input is
// extended once and the output rounded once when stored.
// CHECK-LABEL: func.func @arithmetic_in_double
// CHECK: %[[X:.+]] = llvm.load %{{.+}} : !llvm.ptr -> vector<4xf32>
// CHECK: %[[W:.+]] = arith.extf %[[X]] : vector<4xf32> to vector<4xf64>
// CHECK: %[[M:.+]] = arith.mulf %[[W]], %[[W]] : vector<4xf64>
// CHECK: arith.addf %[[M]], %{{.+}} : vector<4xf64>
// CHECK: arith.cmpf olt, %{{.+}}, %{{.+}} : vector<4xf64>
// CHECK: arith.select %{{.+}}, %{{.+}}, %{{.+}} : vector<4xi1>, vector<4xf64>
// CHECK: %[[R:.+]] = arith.truncf %{{.+}} : vector<4xf64> to vector<4xf32>
// CHECK: llvm.store %[[R]], %{{.+}} : vector<4xf32>, !llvm.ptr
func.func @arithmetic_in_double(%in: !llvm.ptr, %out: !llvm.ptr) {
  %x = llvm.load %in : !llvm.ptr -> vector<4xf32>
  %c = arith.constant dense<0.1> : vector<4xf32>
  %m = arith.mulf %x, %x : vector<4xf32>
  %s = arith.addf %m, %c : vector<4xf32>
  %lt = arith.cmpf olt, %s, %c : vector<4xf32>
  %r = arith.select %lt, %c, %s : vector<4xi1>, vector<4xf32>
  llvm.store %r, %out : vector<4xf32>, !llvm.ptr
  return
}

// -----

// precise's rounding of a libm result (extf -> call -> truncf) vanishes:
// the double result flows on; a loop-carried float becomes f64.
// CHECK-LABEL: func.func @libm_and_loops
// CHECK: %[[S:.+]] = call @sin(%{{.+}}) : (f64) -> f64
// CHECK-NOT: arith.truncf %[[S]]
// CHECK: scf.while (%{{.+}} = %[[S]]) : (f64) -> f64
// CHECK: arith.mulf %{{.+}}, %{{.+}} : f64
func.func private @sin(f64) -> f64
func.func @libm_and_loops(%x: f32, %n: i1) -> f32 {
  %e = arith.extf %x : f32 to f64
  %s = call @sin(%e) : (f64) -> f64
  %t = arith.truncf %s : f64 to f32
  %r = scf.while (%v = %t) : (f32) -> f32 {
    scf.condition(%n) %v : f32
  } do {
  ^bb0(%v: f32):
    %w = arith.mulf %v, %v : f32
    scf.yield %w : f32
  }
  return %r : f32
}

// -----

// A float reinterpreted as bits is the f32 the shader would have had.
// CHECK-LABEL: func.func @bitcast_sees_f32
// CHECK: %[[A:.+]] = arith.addf %{{.+}}, %{{.+}} : f64
// CHECK: %[[F:.+]] = arith.truncf %[[A]] : f64 to f32
// CHECK: arith.bitcast %[[F]] : f32 to i32
func.func @bitcast_sees_f32(%x: f32) -> i32 {
  %a = arith.addf %x, %x : f32
  %b = arith.bitcast %a : f32 to i32
  return %b : i32
}

// -----

// A pick of float lanes carries its elements' doubles, as the select it
// stands for would: no rounding to f32 around it.
// CHECK-LABEL: func.func @pick_in_double
// CHECK: %[[A:.+]] = arith.mulf %{{.+}}, %{{.+}} : vector<4xf64>
// CHECK: %[[P:.+]] = osl.lane_pick %{{.+}}, [%{{.+}}, %[[A]]] : vector<4xi32>, [vector<4xf64>, vector<4xf64>] -> vector<4xf64>
// CHECK: arith.addf %[[P]], %{{.+}} : vector<4xf64>
// CHECK-NOT: arith.truncf %[[P]]
func.func @pick_in_double(%in: !llvm.ptr, %out: !llvm.ptr, %i: vector<4xi32>) {
  %x = llvm.load %in : !llvm.ptr -> vector<4xf32>
  %a = arith.mulf %x, %x : vector<4xf32>
  %p = osl.lane_pick %i, [%x, %a] : vector<4xi32>, [vector<4xf32>, vector<4xf32>] -> vector<4xf32>
  %s = arith.addf %p, %x : vector<4xf32>
  llvm.store %s, %out : vector<4xf32>, !llvm.ptr
  return
}
