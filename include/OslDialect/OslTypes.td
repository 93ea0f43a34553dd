//===- OslTypes.td - Uniform and varying types -------------*- tablegen -*-===//
#ifndef OSL_TYPES_TD
#define OSL_TYPES_TD

include "OslDialect/OslDialect.td"
include "mlir/IR/AttrTypeBase.td"

def Osl_ClosureType : TypeDef<Osl_Dialect, "Closure"> {
  let mnemonic = "closure";
  let summary = "an OSL closure color: a weighted sum of BSDFs, lights...";
  let description = [{
    `!osl.closure` is a closure color; `!osl.varying<!osl.closure>` one per
    point. Lowered to an i32 handle into the runtime's closure arena
    (OslAbi/Closures.h), 0 being the empty closure.
  }];
}

def Osl_VaryingType : TypeDef<Osl_Dialect, "Varying"> {
  let mnemonic = "varying";
  let summary = "one value per shading point of a batch";
  let description = [{
    `!osl.varying<f32>` holds a value that may differ between the points of
    a batch. Its element is one of the uniform OSL types: f32, i32, i1,
    vector<3xf32> or !osl.closure. Lowered to vector<W x T> (triples: vector<3 x W x f32>).
  }];
  let parameters = (ins "::mlir::Type":$elementType);
  let builders = [TypeBuilderWithInferredContext<(ins "::mlir::Type":$elementType), [{
    return $_get(elementType.getContext(), elementType);
  }]>];
  let assemblyFormat = "`<` $elementType `>`";
  let genVerifyDecl = 1;
}

/// A uniform OSL type or a varying one.
def Osl_Value : Type<CPred<"::mlir::osl::isOslType($_self)">,
    "OSL value (f32, i32, i1, vector<3xf32>, !osl.closure, or !osl.varying of one)">;
/// A closure, uniform or varying.
def Osl_AnyClosure : Type<
    CPred<"::llvm::isa<::mlir::osl::ClosureType>(::mlir::osl::getUniformType($_self))">,
    "!osl.closure or !osl.varying<!osl.closure>">;
/// Boolean (i1), uniform or varying.
def Osl_Bool : Type<
    CPred<"::mlir::osl::getUniformType($_self).isInteger(1) && ::mlir::osl::isOslType($_self)">,
    "i1 or !osl.varying<i1>">;
/// A triple (point, vector, normal, color), uniform or varying.
def Osl_Triple : Type<
    CPred<"::mlir::osl::isTriple(::mlir::osl::getUniformType($_self))">,
    "vector<3xf32> or !osl.varying<vector<3xf32>>">;
/// A float, uniform or varying.
def Osl_Float : Type<
    CPred<"::mlir::osl::getUniformType($_self).isF32()">,
    "f32 or !osl.varying<f32>">;

#endif // OSL_TYPES_TD
