//===- ConstantTable.h - Per-lane reads of constant tables ------*- C++ -*-===//
//
// Library functions that OSL computes from precomputed data (blackbody's
// temperature table, the CIE observer) read it from a constant global: a
// load for a uniform index, a gather for a varying one, so every width reads
// the same bits.
//
//===----------------------------------------------------------------------===//
#ifndef OSLTRANSFORMS_CONSTANTTABLE_H
#define OSLTRANSFORMS_CONSTANTTABLE_H

#include "mlir/Dialect/LLVMIR/LLVMDialect.h"
#include "mlir/IR/Builders.h"

namespace mlir::osl {

/// Marks loads from constant tables, so osl-derivatives knows they are not
/// shader globals: their values have no derivative.
inline constexpr const char *kConstantTableAttr = "osl.constant_table";

/// The internal constant global `symbol` holding `table` in the module
/// that encloses the builder's insertion point, created on first use (later
/// uses must pass the same contents). Get it before building a region
/// whose body reads it: a body under construction has no module yet.
LLVM::GlobalOp getConstantTable(OpBuilder &b, Location loc, StringRef symbol,
                                ArrayRef<float> table);

/// `table[index]` for each lane of `index` (i32 or vector<W x i32>, every
/// lane in range).
Value lookupConstantTable(OpBuilder &b, Location loc, LLVM::GlobalOp table,
                          Value index);

} // namespace mlir::osl

#endif // OSLTRANSFORMS_CONSTANTTABLE_H
