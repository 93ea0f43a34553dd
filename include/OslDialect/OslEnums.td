//===- OslEnums.td - osl dialect enumerations --------------*- tablegen -*-===//
//
// Attribute values with a fixed set of cases: the parser rejects any other,
// and code reads them as C++ enums. A shader's own spelling (OSL's noise
// name aliases, "catmull-rom") is mapped to these by the front end; names
// OSL leaves open (spaces, color spaces, files) stay strings.
//
//===----------------------------------------------------------------------===//
#ifndef OSL_ENUMS_TD
#define OSL_ENUMS_TD

include "mlir/IR/EnumAttr.td"

def Osl_CmpPredicate : I32EnumAttr<"CmpPredicate", "the comparison of osl.cmp", [
    I32EnumAttrCase<"eq", 0>, I32EnumAttrCase<"ne", 1>, I32EnumAttrCase<"lt", 2>,
    I32EnumAttrCase<"le", 3>, I32EnumAttrCase<"gt", 4>, I32EnumAttrCase<"ge", 5>,
    // Equal bit patterns: NaNs with one payload agree, 0.0 and -0.0 differ
    // (lane-group filtering: a lane joins a group only with its own value).
    I32EnumAttrCase<"same", 6>]> {
  let cppNamespace = "::mlir::osl";
}

def Osl_DerivAxis : I32EnumAttr<"DerivAxis", "the axis of a derivative (screen x, y; z)", [
    I32EnumAttrCase<"x", 0>, I32EnumAttrCase<"y", 1>, I32EnumAttrCase<"z", 2>]> {
  let cppNamespace = "::mlir::osl";
}

def Osl_NoiseKind : I32EnumAttr<"NoiseKind", "the noise of osl.noise", [
    // "perlin"/"snoise": signed, about [-1, 1]; "uperlin"/"noise": 0.5 * (perlin + 1)
    I32EnumAttrCase<"perlin", 0>, I32EnumAttrCase<"uperlin", 1>,
    // "cell"/"cellnoise": a hash of floor(coords); "hash"/"hashnoise": of the coords' bits
    I32EnumAttrCase<"cell", 2>, I32EnumAttrCase<"hash", 3>,
    I32EnumAttrCase<"simplex", 4>, I32EnumAttrCase<"usimplex", 5>,
    I32EnumAttrCase<"gabor", 6>]> {
  let cppNamespace = "::mlir::osl";
}

def Osl_TransformKind : I32EnumAttr<"TransformKind",
    "what osl.transform moves: a point, a direction, or a normal (by the inverse transpose)", [
    I32EnumAttrCase<"point", 0>, I32EnumAttrCase<"vector", 1>, I32EnumAttrCase<"normal", 2>]> {
  let cppNamespace = "::mlir::osl";
}

def Osl_TextureKind : I32EnumAttr<"TextureKind", "the lookup of osl.texture, named after OSL's function", [
    I32EnumAttrCase<"texture", 0>, I32EnumAttrCase<"texture3d", 1>,
    I32EnumAttrCase<"environment", 2>]> {
  let cppNamespace = "::mlir::osl";
}

def Osl_SplineBasis : I32EnumAttr<"SplineBasis", "the basis of osl.spline (OSL's catmull-rom is catmullrom)", [
    I32EnumAttrCase<"catmullrom", 0>, I32EnumAttrCase<"bezier", 1>,
    I32EnumAttrCase<"bspline", 2>, I32EnumAttrCase<"hermite", 3>,
    I32EnumAttrCase<"linear", 4>, I32EnumAttrCase<"constant", 5>]> {
  let cppNamespace = "::mlir::osl";
}

#endif // OSL_ENUMS_TD
