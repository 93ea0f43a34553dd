//===- OslDialect.td - The osl dialect ---------------------*- tablegen -*-===//
#ifndef OSL_DIALECT_TD
#define OSL_DIALECT_TD

include "mlir/IR/OpBase.td"

def Osl_Dialect : Dialect {
  let name = "osl";
  let summary = "Open Shading Language shaders, uniform and varying";
  let description = [{
    Shaders as the OSL author wrote them: globals, parameters, outputs,
    arithmetic on int/float/triples, and library calls (noise, math,
    geometry, transforms). Every value is uniform (a plain type: f32, i32,
    i1, vector<3xf32> for point/vector/normal/color) or varying
    (`!osl.varying<T>`), one value per shading point of a batch.
  }];
  let cppNamespace = "::mlir::osl";
  let useDefaultTypePrinterParser = 1;
}

class Osl_Op<string mnemonic, list<Trait> traits = []>
    : Op<Osl_Dialect, mnemonic, traits>;

#endif // OSL_DIALECT_TD
