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
// CHECK: %[[SAME:.+]] = osl.cmp same, %[[WRAP]], %[[B]]
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
// CHECK: %[[EQF:.+]] = osl.cmp same, %[[FILE]]
// CHECK: %[[LI:.+]] = osl.first_lane %[[INTERP:[^,]+]], %[[L]]
// CHECK: %[[EQI:.+]] = osl.cmp same, %[[INTERP]]
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

// -----

// Gabor noise with a bandwidth and a direction chosen per point: the noise
// (pure, no mask) runs once per group of lanes whose options have the same
// bits, with the lead's options as uniform operands; the coordinates stay
// varying and the group keeps its lanes' values.
// CHECK-LABEL: func.func @varying_gabor_options
// CHECK: %[[PENDING:.+]] = osl.batch_mask : !osl.varying<i1>
// CHECK: scf.while (%[[LEFT:.+]] = %[[PENDING]], %{{.+}} = %{{.+}})
// CHECK: ^bb0(%[[L:.+]]: !osl.varying<i1>, %[[ACC:.+]]: !osl.varying<f32>):
// CHECK: %[[LD:.+]] = osl.first_lane %[[DIR:[^,]+]], %[[L]] : !osl.varying<vector<3xf32>>, !osl.varying<i1> -> vector<3xf32>
// CHECK: %[[SD:.+]] = osl.cmp same, %[[DIR]]
// CHECK: %[[LB:.+]] = osl.first_lane %[[BW:[^,]+]], %[[L]] : !osl.varying<f32>, !osl.varying<i1> -> f32
// CHECK: %[[SB:.+]] = osl.cmp same, %[[BW]]
// CHECK: %[[SAME:.+]] = osl.and %[[SD]], %[[SB]]
// CHECK: %[[GROUP:.+]] = osl.and %[[L]], %[[SAME]]
// CHECK: %[[N:.+]] = osl.noise gabor(%[[P:.+]]) direction(%[[LD]] : vector<3xf32>) bandwidth(%[[LB]] : f32) : (!osl.varying<vector<3xf32>>) -> !osl.varying<f32>
// CHECK: osl.select %[[GROUP]], %[[N]], %[[ACC]]
// CHECK: scf.yield
func.func @varying_gabor_options() {
  %p = osl.global "P" : !osl.varying<vector<3xf32>>
  %u = osl.global "u" : !osl.varying<f32>
  %half = arith.constant 0.5 : f32
  %right = osl.cmp gt, %u, %half : !osl.varying<f32>, f32 -> !osl.varying<i1>
  %two = arith.constant 2.0 : f32
  %four = arith.constant 4.0 : f32
  %bw = osl.select %right, %two, %four : !osl.varying<i1>, f32, f32 -> !osl.varying<f32>
  %x = arith.constant dense<[1.0, 0.0, 0.0]> : vector<3xf32>
  %y = arith.constant dense<[0.0, 1.0, 0.0]> : vector<3xf32>
  %dir = osl.select %right, %x, %y : !osl.varying<i1>, vector<3xf32>, vector<3xf32> -> !osl.varying<vector<3xf32>>
  %n = osl.noise gabor(%p) direction(%dir : !osl.varying<vector<3xf32>>) bandwidth(%bw : !osl.varying<f32>) : (!osl.varying<vector<3xf32>>) -> !osl.varying<f32>
  osl.output "f" = %n : !osl.varying<f32>
  return
}

// -----

// Uniform Gabor options: one noise, no loop.
// CHECK-LABEL: func.func @uniform_gabor_options
// CHECK-NOT: scf.while
// CHECK: osl.noise gabor
func.func @uniform_gabor_options(%bw: f32) {
  %p = osl.global "P" : !osl.varying<vector<3xf32>>
  %n = osl.noise gabor(%p) bandwidth(%bw : f32) : (!osl.varying<vector<3xf32>>) -> !osl.varying<f32>
  osl.output "f" = %n : !osl.varying<f32>
  return
}
