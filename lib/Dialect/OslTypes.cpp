//===- OslTypes.cpp - Uniform and varying types ---------------------------===//
#include "OslDialect/OslDialect.h"

using namespace mlir;
using namespace mlir::osl;

static bool isUniformOslType(Type type) {
  return type.isF32() || type.isInteger(32) || type.isInteger(1) ||
         isTriple(type) || isa<ClosureType>(type);
}

bool mlir::osl::isTriple(Type type) {
  auto vec = dyn_cast<VectorType>(type);
  return vec && vec.getRank() == 1 && vec.getDimSize(0) == 3 &&
         !vec.isScalable() && vec.getElementType().isF32();
}

bool mlir::osl::isOslType(Type type) {
  if (auto varying = dyn_cast<VaryingType>(type))
    return isUniformOslType(varying.getElementType());
  return isUniformOslType(type);
}

Type mlir::osl::getUniformType(Type type) {
  if (auto varying = dyn_cast<VaryingType>(type))
    return varying.getElementType();
  return type;
}

bool mlir::osl::isVarying(Type type) { return isa<VaryingType>(type); }

Type mlir::osl::withUniformity(Type uniform, bool varying) {
  uniform = getUniformType(uniform);
  return varying ? VaryingType::get(uniform) : uniform;
}

LogicalResult
VaryingType::verify(function_ref<InFlightDiagnostic()> emitError,
                    Type elementType) {
  if (!isUniformOslType(elementType))
    return emitError() << "varying element must be f32, i32, i1, "
                          "vector<3xf32> or !osl.closure, got "
                       << elementType;
  return success();
}
