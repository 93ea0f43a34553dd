//===- Types.cpp - OSL types ------------------------------------------------===//
#include "Types.h"
#include "Ast.h"
#include "OslDialect/OslDialect.h"

#include "mlir/IR/BuiltinTypes.h"

using namespace osl::frontend;

llvm::StringRef osl::frontend::baseTypeName(BaseType base) {
  switch (base) {
  case BaseType::Void: return "void";
  case BaseType::Int: return "int";
  case BaseType::Float: return "float";
  case BaseType::Point: return "point";
  case BaseType::Vector: return "vector";
  case BaseType::Normal: return "normal";
  case BaseType::Color: return "color";
  case BaseType::String: return "string";
  case BaseType::Matrix: return "matrix";
  case BaseType::Closure: return "closure color";
  case BaseType::Bool: return "int";
  case BaseType::Struct: return "struct";
  }
  return "?";
}

std::string OslType::str() const {
  std::string s = structDecl ? structDecl->name : baseTypeName(base).str();
  if (arrayLen == 0)
    s += "[]";
  else if (arrayLen > 0)
    s += "[" + std::to_string(arrayLen) + "]";
  return s;
}

mlir::Type osl::frontend::irType(mlir::Builder &b, OslType type) {
  switch (type.base) {
  case BaseType::Int: return b.getI32Type();
  case BaseType::Float: return b.getF32Type();
  case BaseType::Bool: return b.getI1Type();
  case BaseType::Point:
  case BaseType::Vector:
  case BaseType::Normal:
  case BaseType::Color: return mlir::VectorType::get({3}, b.getF32Type());
  case BaseType::Closure: return mlir::osl::ClosureType::get(b.getContext());
  default: return {};
  }
}

mlir::osl::TransformKind osl::frontend::transformKindOf(BaseType base) {
  return base == BaseType::Normal   ? mlir::osl::TransformKind::normal
         : base == BaseType::Vector ? mlir::osl::TransformKind::vector
                                    : mlir::osl::TransformKind::point;
}
