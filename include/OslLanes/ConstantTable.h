//===- ConstantTable.h - Per-lane reads of constant tables ------*- C++ -*-===//
//
// Library functions that OSL computes from precomputed data (blackbody's
// temperature table, the CIE observer) read it from a constant global: a
// load for a uniform index, a gather for a varying one, so every width reads
// the same bits. Reads are marked kNoDerivativeAttr (LaneMath.h). Runtime
// calls take constant strings (texture file names) the same way.
//
//===----------------------------------------------------------------------===//
#ifndef OSLLANES_CONSTANTTABLE_H
#define OSLLANES_CONSTANTTABLE_H

#include "mlir/Dialect/LLVMIR/LLVMDialect.h"
#include "mlir/IR/Builders.h"

namespace mlir::osl {

/// The internal constant global `symbol` holding `table` in the module
/// that encloses the builder's insertion point, created on first use (later
/// uses must pass the same contents). Get it before building a region
/// whose body reads it: a body under construction has no module yet.
LLVM::GlobalOp getConstantTable(OpBuilder &b, Location loc, StringRef symbol,
                                ArrayRef<float> table);

/// A constant global holding `table` (1-D, f32 or i32) in the enclosing
/// module: one global per distinct table.
LLVM::GlobalOp getConstantTable(OpBuilder &b, Location loc, DenseElementsAttr table);

/// The address of a NUL-terminated constant copy of `value` in the
/// enclosing module (one global per distinct string).
Value constantStringAddress(OpBuilder &b, Location loc, StringRef value);

/// `table[index]` for each lane of `index` (i32 or vector<W x i32>, every
/// lane in range), of the table's element type.
Value lookupConstantTable(OpBuilder &b, Location loc, LLVM::GlobalOp table,
                          Value index);

} // namespace mlir::osl

#endif // OSLLANES_CONSTANTTABLE_H
