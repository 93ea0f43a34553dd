// RUN: osl-opt %s -split-input-file --osl-lane-group-filter | FileCheck %s

// A wrap mode chosen per point: the lookup runs once per group of lanes
// that chose the same mode. The first pending lane leads; its choice is
// the group call's uniform choice and the group its mask; the group leaves
// the pending lanes; results merge per lane.
// CHECK-LABEL: func.func @varying_wrap
// CHECK: %[[PENDING:.+]] = osl.batch_mask : !osl.varying<i1>
// CHECK: scf.while (%[[LEFT:.+]] = %[[PENDING]], %{{.+}} = %{{.+}}, %{{.+}} = %{{.+}}, %{{.+}} = %{{.+}})
// CHECK: %[[ANY:.+]] = osl.any %[[LEFT]]
// CHECK: scf.condition(%[[ANY]])
// CHECK: ^bb0(%[[L:.+]]: !osl.varying<i1>, %[[ACC:.+]]: !osl.varying<vector<3xf32>>, %{{.+}}: !osl.varying<f32>, %{{.+}}: !osl.varying<i32>):
// CHECK: %[[LEAD:.+]] = osl.first_lane %[[WRAP:.+]], %[[L]] : !osl.varying<i32>, !osl.varying<i1> -> i32
// CHECK: %[[B:.+]] = osl.broadcast %[[LEAD]]
// CHECK: %[[SAME:.+]] = osl.cmp eq, %[[WRAP]], %[[B]]
// CHECK: %[[GROUP:.+]] = osl.and %[[L]], %[[SAME]]
// CHECK: %[[R:.+]], %{{.+}}, %{{.+}} = osl.texture texture{{.*}} choices(%{{.+}}, %[[LEAD]], %[[LEAD]], %[[LEAD]], %{{.+}}, %{{.+}}) mask %[[GROUP]]
// CHECK: %[[NOT:.+]] = osl.not %[[SAME]]
// CHECK: %[[REST:.+]] = osl.and %[[L]], %[[NOT]]
// CHECK: osl.select %[[GROUP]], %[[R]], %[[ACC]]
// CHECK: scf.yield %[[REST]]
func.func @varying_wrap() {
  %u = osl.global "u" : !osl.varying<f32>
  %v = osl.global "v" : !osl.varying<f32>
  %one = arith.constant 1.0 : f32
  %zero = arith.constant 0.0 : f32
  %c0 = arith.constant 0 : i32
  %half = arith.constant 0.5 : f32
  %right = osl.cmp gt, %u, %half : !osl.varying<f32>, f32 -> !osl.varying<i1>
  %c1 = arith.constant 1 : i32
  %wrap = osl.select %right, %c1, %c0 : !osl.varying<i1>, i32, i32 -> !osl.varying<i32>
  %r, %a, %err = osl.texture texture(%u, %v) derivs(%zero, %zero, %zero, %zero) options(%zero, %zero, %zero, %one, %one, %one, %zero, %one, %zero, %zero, %zero) channel %c0 subimage %c0 choices(%c0, %wrap, %wrap, %wrap, %c0, %c0) {candidates = [["ramp.tx"], ["black", "clamp"], ["black", "clamp"], ["black", "clamp"], ["smartcubic"], [""]], nchannels = 3 : i32} : (!osl.varying<f32>, !osl.varying<f32>) (f32, f32, f32, f32) (f32, f32, f32, f32, f32, f32, f32, f32, f32, f32, f32) i32, i32(i32, !osl.varying<i32>, !osl.varying<i32>, !osl.varying<i32>, i32, i32) -> !osl.varying<vector<3xf32>>, !osl.varying<f32>, !osl.varying<i32>
  osl.output "C" = %r : !osl.varying<vector<3xf32>>
  return
}

// -----

// Two options chosen per point (file and interp): a lane joins the group
// only when both of its choices equal the lead's.
// CHECK-LABEL: func.func @varying_file_and_interp
// CHECK: %[[LF:.+]] = osl.first_lane %[[FILE:[^,]+]], %[[L:[^ ]+]]
// CHECK: %[[EQF:.+]] = osl.cmp eq, %[[FILE]]
// CHECK: %[[LI:.+]] = osl.first_lane %[[INTERP:[^,]+]], %[[L]]
// CHECK: %[[EQI:.+]] = osl.cmp eq, %[[INTERP]]
// CHECK: %[[SAME:.+]] = osl.and %[[EQF]], %[[EQI]]
// CHECK: choices(%[[LF]], %{{.+}}, %{{.+}}, %{{.+}}, %[[LI]], %{{.+}})
func.func @varying_file_and_interp() {
  %u = osl.global "u" : !osl.varying<f32>
  %v = osl.global "v" : !osl.varying<f32>
  %one = arith.constant 1.0 : f32
  %zero = arith.constant 0.0 : f32
  %c0 = arith.constant 0 : i32
  %c1 = arith.constant 1 : i32
  %half = arith.constant 0.5 : f32
  %right = osl.cmp gt, %u, %half : !osl.varying<f32>, f32 -> !osl.varying<i1>
  %top = osl.cmp gt, %v, %half : !osl.varying<f32>, f32 -> !osl.varying<i1>
  %file = osl.select %right, %c1, %c0 : !osl.varying<i1>, i32, i32 -> !osl.varying<i32>
  %interp = osl.select %top, %c1, %c0 : !osl.varying<i1>, i32, i32 -> !osl.varying<i32>
  %r, %a, %err = osl.texture texture(%u, %v) derivs(%zero, %zero, %zero, %zero) options(%zero, %zero, %zero, %one, %one, %one, %zero, %one, %zero, %zero, %zero) channel %c0 subimage %c0 choices(%file, %c0, %c0, %c0, %interp, %c0) {candidates = [["a.tx", "b.tx"], ["default"], ["default"], ["default"], ["closest", "linear"], [""]], nchannels = 1 : i32} : (!osl.varying<f32>, !osl.varying<f32>) (f32, f32, f32, f32) (f32, f32, f32, f32, f32, f32, f32, f32, f32, f32, f32) i32, i32(!osl.varying<i32>, i32, i32, i32, !osl.varying<i32>, i32) -> !osl.varying<f32>, !osl.varying<f32>, !osl.varying<i32>
  osl.output "f" = %r : !osl.varying<f32>
  return
}

// -----

// Uniform choices: one call, no loop.
// CHECK-LABEL: func.func @uniform_options
// CHECK-NOT: scf.while
// CHECK: osl.texture texture3d
// CHECK-NOT: mask
func.func @uniform_options() {
  %P = osl.global "P" : !osl.varying<vector<3xf32>>
  %x = osl.extract %P[0] : !osl.varying<vector<3xf32>> -> !osl.varying<f32>
  %one = arith.constant 1.0 : f32
  %zero = arith.constant 0.0 : f32
  %c0 = arith.constant 0 : i32
  %r, %a, %err = osl.texture texture3d(%x, %x, %x) derivs(%zero, %zero, %zero, %zero, %zero, %zero, %zero, %zero, %zero) options(%zero, %zero, %zero, %one, %one, %one, %zero, %one, %zero, %zero, %zero) channel %c0 subimage %c0 choices(%c0, %c0, %c0, %c0, %c0, %c0) {candidates = [["v.vdb"], ["clamp"], ["clamp"], ["clamp"], ["smartcubic"], ["density"]], nchannels = 1 : i32} : (!osl.varying<f32>, !osl.varying<f32>, !osl.varying<f32>) (f32, f32, f32, f32, f32, f32, f32, f32, f32) (f32, f32, f32, f32, f32, f32, f32, f32, f32, f32, f32) i32, i32(i32, i32, i32, i32, i32, i32) -> !osl.varying<f32>, !osl.varying<f32>, !osl.varying<i32>
  osl.output "f" = %r : !osl.varying<f32>
  return
}
