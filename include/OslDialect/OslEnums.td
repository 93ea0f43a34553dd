//===- OslEnums.td - osl dialect enumerations --------------*- tablegen -*-===//
//
// Attribute values with a fixed set of cases: the parser rejects any other,
// and code reads them as C++ enums. (Names chosen by the shader, such as
// noise and space names, stay strings.)
//
//===----------------------------------------------------------------------===//
#ifndef OSL_ENUMS_TD
#define OSL_ENUMS_TD

include "mlir/IR/EnumAttr.td"

def Osl_CmpPredicate : I32EnumAttr<"CmpPredicate", "the comparison of osl.cmp", [
    I32EnumAttrCase<"eq", 0>, I32EnumAttrCase<"ne", 1>, I32EnumAttrCase<"lt", 2>,
    I32EnumAttrCase<"le", 3>, I32EnumAttrCase<"gt", 4>, I32EnumAttrCase<"ge", 5>]> {
  let cppNamespace = "::mlir::osl";
}

def Osl_DerivAxis : I32EnumAttr<"DerivAxis", "the axis of a derivative (screen x, y; z)", [
    I32EnumAttrCase<"x", 0>, I32EnumAttrCase<"y", 1>, I32EnumAttrCase<"z", 2>]> {
  let cppNamespace = "::mlir::osl";
}

#endif // OSL_ENUMS_TD
