// RUN: osl-opt %s -split-input-file -verify-diagnostics --osl-link-group

module {
  func.func @root() attributes {osl.layer = "root"} {
    %zero = arith.constant 0.0 : f32
    // expected-error @+1 {{input 'in' of layer 'root' is connected to unknown layer 'nosuch'}}
    %in = osl.param "in"(%zero) {osl.connect = ["nosuch", "out"]} : f32
    osl.output "Cout" = %in : f32
    return
  }
}

// -----

module {
  func.func @first() attributes {osl.layer = "first"} {
    %zero = arith.constant 0.0 : f32
    // expected-error @+1 {{connecting layer 'second' to layer 'first' would make a cycle}}
    %in = osl.param "in"(%zero) {osl.connect = ["second", "out"]} : f32
    osl.output "out" = %in : f32
    return
  }
  func.func @second() attributes {osl.layer = "second"} {
    %zero = arith.constant 0.0 : f32
    osl.output "out" = %zero : f32
    return
  }
}

// -----

module {
  func.func @up() attributes {osl.layer = "up"} {
    %zero = arith.constant dense<0.0> : vector<3xf32>
    osl.output "out" = %zero : vector<3xf32>
    return
  }
  func.func @root() attributes {osl.layer = "root"} {
    %c = arith.constant 0.0 : f32
    // expected-error @+1 {{cannot connect output 'up.out' (color/point/vector/normal) to input 'root.f' (float)}}
    %in = osl.param "f"(%c) {osl.connect = ["up", "out"]} : f32
    osl.output "Cout" = %in : f32
    return
  }
}

// -----

module {
  func.func @up() attributes {osl.layer = "up"} {
    %zero = arith.constant 0.0 : f32
    osl.output "out" = %zero : f32
    return
  }
  func.func @root() attributes {osl.layer = "root"} {
    %zero = arith.constant 0.0 : f32
    // expected-error @+1 {{layer 'up' has no output 'nosuch' (connected to input 'in' of layer 'root')}}
    %in = osl.param "in"(%zero) {osl.connect = ["up", "nosuch"]} : f32
    osl.output "Cout" = %in : f32
    return
  }
}
