// RUN: osl-opt %s -split-input-file --osl-link-group | FileCheck %s
// RUN: osl-opt %s -split-input-file --osl-link-group="lazy=false" | FileCheck %s --check-prefix=EAGER
// RUN: osl-opt %s -split-input-file --osl-link-group="opaque-params=true" | FileCheck %s --check-prefix=OPAQUE

// An upstream layer read only in one arm of an if is inlined in that arm:
// it runs only on the lanes that take it (osl-insert-mask-stack masks it).
// CHECK-LABEL: func.func @root_reads_in_arm
// CHECK: osl.if
// CHECK: osl.global "time"
// CHECK: osl.mul
// CHECK: } else {
// CHECK-NOT: osl.global "time"
// CHECK: osl.output "Cout"
// CHECK-NOT: osl.output
// Not lazy: the layer runs first, at the top level, and keeps its output.
// EAGER-LABEL: func.func @root_reads_in_arm
// EAGER: osl.global "time"
// EAGER: osl.output "up.out"
// EAGER: osl.if
module {
  func.func @up() attributes {osl.layer = "up"} {
    %t = osl.global "time" : !osl.varying<f32>
    %c0 = arith.constant 0.0 : f32
    %o = osl.param "out"(%c0) : f32
    osl.output "out" = %t : !osl.varying<f32>
    return
  }
  func.func @root_reads_in_arm() attributes {osl.layer = "root_reads_in_arm"} {
    %v = osl.global "v" : !osl.varying<f32>
    %half = arith.constant 0.5 : f32
    %in = osl.param "in"(%half) {osl.connect = ["up", "out"]} : f32
    %cond = osl.cmp gt, %v, %half : !osl.varying<f32>, f32 -> !osl.varying<i1>
    %r = osl.if %cond : !osl.varying<i1> -> !osl.varying<f32> {
      %m = osl.mul %in, %half : f32, f32 -> f32
      osl.yield %m : f32
    } else {
      osl.yield %v : !osl.varying<f32>
    }
    osl.output "Cout" = %r : !osl.varying<f32>
    return
  }
}

// -----

// Nobody reads `unused`: it is not inlined at all (lazy), but runs and
// writes its output when every layer runs.
// CHECK-LABEL: func.func @root_without_reads
// CHECK-NOT: osl.global "time"
// CHECK: osl.output "Cout"
// EAGER-LABEL: func.func @root_without_reads
// EAGER: osl.global "time"
// EAGER: osl.output "unused.out"
// EAGER: osl.output "Cout"
module {
  func.func @unused() attributes {osl.layer = "unused"} {
    %t = osl.global "time" : !osl.varying<f32>
    osl.output "out" = %t : !osl.varying<f32>
    return
  }
  func.func @root_without_reads() attributes {osl.layer = "root_without_reads"} {
    %u = osl.global "u" : !osl.varying<f32>
    osl.output "Cout" = %u : !osl.varying<f32>
    return
  }
}

// -----

// A read inside a loop hoists the layer before the loop: once per point.
// CHECK-LABEL: func.func @root_reads_in_loop
// CHECK: osl.global "time"
// CHECK: osl.while
// CHECK-NOT: osl.global "time"
// CHECK: osl.output "Cout"
module {
  func.func @up() attributes {osl.layer = "up"} {
    %t = osl.global "time" : !osl.varying<f32>
    osl.output "out" = %t : !osl.varying<f32>
    return
  }
  func.func @root_reads_in_loop() attributes {osl.layer = "root_reads_in_loop"} {
    %zero = arith.constant 0.0 : f32
    %in = osl.param "in"(%zero) {osl.connect = ["up", "out"]} : f32
    %r = osl.while (%zero : f32) -> f32 cond {
    ^bb0(%x: f32):
      %c = osl.cmp lt, %x, %in : f32, f32 -> i1
      osl.condition %c : i1, %x : f32
    } do {
    ^bb0(%x: f32):
      %one = arith.constant 1.0 : f32
      %n = osl.add %x, %one : f32, f32 -> f32
      osl.yield %n : f32
    }
    osl.output "Cout" = %r : f32
    return
  }
}

// -----

// Two layers read `up`: it is inlined once, before the first read, and
// its own input (from `base`, further up) is inlined before its first use.
// CHECK-LABEL: func.func @root_two_readers
// CHECK: osl.global "time"
// CHECK-NEXT: osl.global "u"
// CHECK-NOT: osl.global
// CHECK: osl.output "Cout"
module {
  func.func @base() attributes {osl.layer = "base"} {
    %u = osl.global "u" : !osl.varying<f32>
    osl.output "out" = %u : !osl.varying<f32>
    return
  }
  func.func @up() attributes {osl.layer = "up"} {
    %zero = arith.constant 0.0 : f32
    %in = osl.param "in"(%zero) {osl.connect = ["base", "out"]} : f32
    %t = osl.global "time" : !osl.varying<f32>
    %s = osl.add %t, %in : !osl.varying<f32>, f32 -> !osl.varying<f32>
    osl.output "out" = %s : !osl.varying<f32>
    return
  }
  func.func @mid() attributes {osl.layer = "mid"} {
    %zero = arith.constant 0.0 : f32
    %in = osl.param "in"(%zero) {osl.connect = ["up", "out"]} : f32
    %two = arith.constant 2.0 : f32
    %m = osl.mul %in, %two : f32, f32 -> f32
    osl.output "out" = %m : f32
    return
  }
  func.func @root_two_readers() attributes {osl.layer = "root_two_readers"} {
    %zero = arith.constant 0.0 : f32
    %a = osl.param "a"(%zero) {osl.connect = ["up", "out"]} : f32
    %b = osl.param "b"(%zero) {osl.connect = ["mid", "out"]} : f32
    %s = osl.add %a, %b : f32, f32 -> f32
    osl.output "Cout" = %s : f32
    return
  }
}

// -----

// Entries run at the top level; the group's requested outputs are the only
// ones kept ("layer.name" for a layer other than the root).
// CHECK-LABEL: func.func @root_with_entries
// CHECK: osl.output "side.extra"
// CHECK-NOT: osl.output "side.other"
// CHECK: osl.output "Cout"
// CHECK-NOT: osl.output
module attributes {osl.group_outputs = ["Cout", "side.extra"]} {
  func.func @side() attributes {osl.layer = "side", osl.entry} {
    %u = osl.global "u" : !osl.varying<f32>
    osl.output "extra" = %u : !osl.varying<f32>
    osl.output "other" = %u : !osl.varying<f32>
    return
  }
  func.func @root_with_entries() attributes {osl.layer = "root_with_entries", osl.entry} {
    %v = osl.global "v" : !osl.varying<f32>
    osl.output "Cout" = %v : !osl.varying<f32>
    osl.output "Cunused" = %v : !osl.varying<f32>
    return
  }
}

// -----

// Unspecialised parameters are loads from writable globals; a userdata
// (lockgeom=0) parameter is one even when specialising. A parameter whose
// default is computed per point is no instance value and stays.
// CHECK: llvm.mlir.global external @osl_param.root_params.height
// CHECK-NOT: llvm.mlir.global
// CHECK-LABEL: func.func @root_params
// CHECK: osl.param "freq"
// CHECK: llvm.load
// CHECK-NOT: llvm.load
// OPAQUE-DAG: llvm.mlir.global external @osl_param.root_params.freq(2.000000e+00 : f32)
// OPAQUE-DAG: llvm.mlir.global external @osl_param.root_params.height
// OPAQUE-LABEL: func.func @root_params
// OPAQUE-NOT: osl.param "freq"
// OPAQUE-NOT: osl.param "height"
// OPAQUE: osl.param "fromu"
module {
  func.func @root_params() attributes {osl.layer = "root_params"} {
    %c2 = arith.constant 2.0 : f32
    %freq = osl.param "freq"(%c2) : f32
    %c3 = arith.constant 3.0 : f32
    %height = osl.param "height"(%c3) {userdata} : f32
    %u = osl.global "u" : !osl.varying<f32>
    %fromu = osl.param "fromu"(%u) : !osl.varying<f32>
    %a = osl.mul %freq, %height : f32, f32 -> f32
    %b = osl.mul %a, %fromu : f32, !osl.varying<f32> -> !osl.varying<f32>
    osl.output "Cout" = %b : !osl.varying<f32>
    return
  }
}

// -----

// Reads in two sibling ifs: one copy, before the first, so that no lane
// runs the layer twice (a lane that takes neither arm runs it too).
// CHECK-LABEL: func.func @root_reads_in_two_ifs
// CHECK: osl.global "time"
// CHECK: osl.if
// CHECK-NOT: osl.global "time"
// CHECK: osl.if
// CHECK-NOT: osl.global "time"
// CHECK: osl.output "Cout"
module {
  func.func @up() attributes {osl.layer = "up"} {
    %t = osl.global "time" : !osl.varying<f32>
    osl.output "out" = %t : !osl.varying<f32>
    return
  }
  func.func @root_reads_in_two_ifs() attributes {osl.layer = "root_reads_in_two_ifs"} {
    %u = osl.global "u" : !osl.varying<f32>
    %half = arith.constant 0.5 : f32
    %in = osl.param "in"(%half) {osl.connect = ["up", "out"]} : f32
    %c1 = osl.cmp gt, %u, %half : !osl.varying<f32>, f32 -> !osl.varying<i1>
    %a = osl.if %c1 : !osl.varying<i1> -> !osl.varying<f32> {
      osl.yield %in : f32
    } else {
      osl.yield %u : !osl.varying<f32>
    }
    %c2 = osl.cmp lt, %a, %half : !osl.varying<f32>, f32 -> !osl.varying<i1>
    %b = osl.if %c2 : !osl.varying<i1> -> !osl.varying<f32> {
      %m = osl.mul %in, %a : f32, !osl.varying<f32> -> !osl.varying<f32>
      osl.yield %m : !osl.varying<f32>
    } else {
      osl.yield %a : !osl.varying<f32>
    }
    osl.output "Cout" = %b : !osl.varying<f32>
    return
  }
}

// -----

// Layers share their globals: a read of P after a layer that assigned it
// (an entry, run first) takes that layer's value; a read before it, and the
// layer's own read, the renderer's. A uniform value is broadcast.
// CHECK-LABEL: func.func @root_reads_displaced_P
// CHECK: %[[P:.*]] = osl.global "P" {osl.from_layer = "displace"}
// CHECK: %[[MOVED:.*]] = osl.add %[[P]]
// CHECK-NOT: osl.set_global
// CHECK: %[[ZERO:.*]] = osl.broadcast %{{.*}} {osl.from_layer = "displace"} : f32 -> !osl.varying<f32>
// CHECK: osl.output "displace.h"
// CHECK-NOT: osl.global "P"
// CHECK: osl.output "moved" = %[[MOVED]]
// CHECK: osl.output "zero" = %[[ZERO]]
// EAGER-LABEL: func.func @root_reads_displaced_P
// EAGER: %[[MOVED:.*]] = osl.add
// EAGER-NOT: osl.set_global
// EAGER: osl.output "moved" = %[[MOVED]]
module {
  func.func @displace() attributes {osl.layer = "displace", osl.entry} {
    %p = osl.global "P" : !osl.varying<vector<3xf32>>
    %d = arith.constant dense<[0.5, 0.0, 0.0]> : vector<3xf32>
    %moved = osl.add %p, %d : !osl.varying<vector<3xf32>>, vector<3xf32> -> !osl.varying<vector<3xf32>>
    osl.set_global "P" = %moved : !osl.varying<vector<3xf32>>
    %zero = arith.constant 0.0 : f32
    osl.set_global "u" = %zero : f32
    osl.output "h" = %zero : f32
    return
  }
  func.func @root_reads_displaced_P() attributes {osl.layer = "root_reads_displaced_P", osl.entry} {
    %p = osl.global "P" : !osl.varying<vector<3xf32>>
    %u = osl.global "u" : !osl.varying<f32>
    osl.output "moved" = %p : !osl.varying<vector<3xf32>>
    osl.output "zero" = %u : !osl.varying<f32>
    return
  }
}

// -----

// A shader alone: nothing reads what it leaves in P.
// CHECK-LABEL: func.func @alone_writes_P
// CHECK-NOT: osl.set_global
// CHECK: return
module {
  func.func @alone_writes_P() {
    %p = osl.global "P" : !osl.varying<vector<3xf32>>
    osl.set_global "P" = %p : !osl.varying<vector<3xf32>>
    return
  }
}
