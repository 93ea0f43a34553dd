// RUN: osl-opt %s -split-input-file --osl-bind-params | FileCheck %s
// RUN: osl-opt %s -split-input-file --osl-bind-params="values=freq=2.5;Cin=0.1,0.2,0.3" | FileCheck %s --check-prefix=BOUND
// RUN: not osl-opt %s -split-input-file --osl-bind-params="values=nosuch=1" 2>&1 | FileCheck %s --check-prefix=UNKNOWN
// RUN: not osl-opt %s -split-input-file --osl-bind-params="values=freq=abc" 2>&1 | FileCheck %s --check-prefix=NOTNUM

// Without values, each parameter is its default expression.
// CHECK-LABEL: func.func @params
// CHECK-NOT: osl.param
// CHECK: %[[D:.+]] = arith.constant 1.000000e+00 : f32
// CHECK: osl.mul %[[D]], %[[D]]
// BOUND-LABEL: func.func @params
// BOUND-DAG: arith.constant 2.500000e+00 : f32
// BOUND-DAG: arith.constant dense<[1.000000e-01, 2.000000e-01, 3.000000e-01]> : vector<3xf32>
// UNKNOWN: error: shader has no parameter 'nosuch'
// NOTNUM: error: parameter 'freq': 'abc' is not a number
func.func @params() {
  %one = arith.constant 1.0 : f32
  %f = osl.param "freq"(%one) : f32
  %half = arith.constant dense<0.5> : vector<3xf32>
  %c = osl.param "Cin"(%half) : vector<3xf32>
  %sq = osl.mul %f, %f : f32, f32 -> f32
  osl.output "sq" = %sq : f32
  osl.output "c" = %c : vector<3xf32>
  return
}
