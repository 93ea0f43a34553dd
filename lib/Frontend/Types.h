//===- Types.h - OSL types as the front end sees them -----------*- C++ -*-===//
//
// The IR only knows f32, i32, i1 and vector<3xf32>; the front end keeps the
// OSL type (point vs vector vs normal vs color, strings, arrays) itself. A
// matrix is 16 f32 values, row-major, held like an array's elements.
//
//===----------------------------------------------------------------------===//
#ifndef OSLFRONTEND_TYPES_H
#define OSLFRONTEND_TYPES_H

#include "mlir/IR/Builders.h"
#include "mlir/IR/Types.h"
#include "llvm/ADT/StringRef.h"

#include <string>

namespace mlir::osl {
enum class TransformKind : uint32_t;
} // namespace mlir::osl

namespace osl::frontend {

struct StructDecl; // Ast.h

enum class BaseType {
  Void,
  Int,
  Float,
  Point,
  Vector,
  Normal,
  Color,
  String,
  Matrix,  // 4x4 floats (RValue::elems, row-major)
  Closure, // closure color: !osl.closure
  Bool,    // internal: the i1 result of a comparison; OSL calls it int
  Struct,  // a user struct (OslType::structDecl)
};

/// An OSL type: a base type, possibly a fixed-size array.
struct OslType {
  BaseType base = BaseType::Void;
  /// -1: not an array; 0: array of unspecified length (function
  /// parameters); N: array of N elements.
  int arrayLen = -1;

  /// The struct, for BaseType::Struct.
  const StructDecl *structDecl = nullptr;

  OslType() = default;
  OslType(BaseType base, int arrayLen = -1) : base(base), arrayLen(arrayLen) {}
  static OslType ofStruct(const StructDecl *decl, int arrayLen = -1) {
    OslType t(BaseType::Struct, arrayLen);
    t.structDecl = decl;
    return t;
  }

  bool isArray() const { return arrayLen >= 0; }
  OslType element() const {
    OslType e = *this;
    e.arrayLen = -1;
    return e;
  }
  /// A struct or an array of structs.
  bool isStructLike() const { return base == BaseType::Struct; }
  bool isTriple() const {
    return !isArray() && (base == BaseType::Point || base == BaseType::Vector ||
                          base == BaseType::Normal || base == BaseType::Color);
  }
  bool isFloat() const { return !isArray() && base == BaseType::Float; }
  bool isInt() const { return !isArray() && base == BaseType::Int; }
  bool isBool() const { return !isArray() && base == BaseType::Bool; }
  bool isMatrix() const { return !isArray() && base == BaseType::Matrix; }
  /// Held as RValue::elems: arrays (not of structs or strings) and matrices.
  bool hasElems() const { return isArray() || isMatrix(); }
  /// int, float or bool (a number).
  bool isScalar() const { return isInt() || isFloat() || isBool(); }
  /// Something the IR holds as one value (number or triple).
  bool isNumeric() const { return isScalar() || isTriple(); }
  bool isString() const { return !isArray() && base == BaseType::String; }
  bool isVoid() const { return base == BaseType::Void; }
  bool isClosure() const { return !isArray() && base == BaseType::Closure; }
  bool operator==(const OslType &o) const {
    return base == o.base && arrayLen == o.arrayLen && structDecl == o.structDecl;
  }
  bool operator!=(const OslType &o) const { return !(*this == o); }

  /// The OSL spelling: "float", "color", "float[4]", "int" for Bool.
  std::string str() const;
};

llvm::StringRef baseTypeName(BaseType base);
/// How osl.transform moves a value of a point-like type.
mlir::osl::TransformKind transformKindOf(BaseType base);
/// The IR type of a non-array numeric type (uniform).
mlir::Type irType(mlir::Builder &b, OslType type);

} // namespace osl::frontend

#endif // OSLFRONTEND_TYPES_H
