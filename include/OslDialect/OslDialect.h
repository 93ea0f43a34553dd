//===- OslDialect.h - The osl dialect ---------------------------*- C++ -*-===//
#ifndef OSLDIALECT_OSLDIALECT_H
#define OSLDIALECT_OSLDIALECT_H

#include "mlir/Bytecode/BytecodeOpInterface.h"
#include "mlir/IR/Builders.h"
#include "mlir/IR/BuiltinTypes.h"
#include "mlir/IR/Dialect.h"
#include "mlir/IR/OpDefinition.h"
#include "mlir/IR/OpImplementation.h"
#include "mlir/Interfaces/ControlFlowInterfaces.h"
#include "mlir/Interfaces/SideEffectInterfaces.h"

namespace mlir::osl {

/// What a lane-wise op accepts; its verifier and result-type inference
/// follow from it.
enum class LaneKind {
  Numeric,       // same-typed f32, i32 or triple operands; result alike
  Float,         // f32 or triple; result alike
  Int,           // i32; result i32
  Bool,          // i1; result i1
  Triple,        // triples; result triple
  TripleToFloat, // triples; result f32
  Compare,       // same-typed f32/i32/triple; result i1
  Select,        // i1 condition, two same-typed values; result alike
  Construct,     // three f32; result triple
};

/// True for f32, i32, i1, vector<3xf32> and !osl.varying of one of them.
bool isOslType(Type type);
/// True for vector<3xf32> (point, vector, normal, color).
bool isTriple(Type type);
/// The element of a varying type; a uniform type itself.
Type getUniformType(Type type);
bool isVarying(Type type);
/// `uniform` made varying (or left uniform) as asked.
Type withUniformity(Type uniform, bool varying);
/// The zero of an osl value type (varying: broadcast): 0, the zero triple,
/// false, or the empty closure.
Value buildZero(OpBuilder &b, Location loc, Type type);
/// Marks an osl.mul that computes inside a library routine (a matrix
/// inverse, a determinant) rather than a product the shader writes: OSL
/// runs those in C++, so x * 0 keeps IEEE's sign there (-0 for a negative
/// x), while its optimizer folds a shader's x * 0 to 0.
constexpr llvm::StringLiteral kIeeeProductAttr = "osl.ieee_product";
/// Marks an osl.any that tests whether any lane takes an arm reporting an
/// error (a range check, error()): the arm is cold, and its branch says so
/// to LLVM (osl-insert-mask-stack sets it; the OR reduction osl.any
/// becomes keeps it for osl-lower-to-llvm).
constexpr llvm::StringLiteral kColdArmAttr = "osl.cold_arm";
/// The result type of a lane-wise op of this kind over these operands.
Type inferLaneResultType(LaneKind kind, ValueRange operands);
LogicalResult verifyLaneOp(Operation *op, LaneKind kind);
} // namespace mlir::osl

#include "OslDialect/OslOpsDialect.h.inc"
#include "OslDialect/OslEnums.h.inc"

namespace mlir::osl {
/// The noise an OSL noise name selects ("snoise" is perlin, "noise"
/// uperlin, "cellnoise" cell, "hashnoise" hash), or none.
std::optional<NoiseKind> noiseKindFromName(llvm::StringRef name);
/// The basis an OSL basis name selects ("catmull-rom" is catmullrom).
std::optional<SplineBasis> splineBasisFromName(llvm::StringRef name);
/// OSL's name of a basis, for messages.
llvm::StringRef splineBasisName(SplineBasis basis);
} // namespace mlir::osl

#define GET_TYPEDEF_CLASSES
#include "OslDialect/OslOpsTypes.h.inc"

#define GET_OP_CLASSES
#include "OslDialect/OslOps.h.inc"

#endif // OSLDIALECT_OSLDIALECT_H
