//===- IRFingerprint.h - A stable hash of an operation's IR ------*- C++ -*-===//
//
// Library objects are looked up by the IR of their function. Printing that
// IR as a key took as long as lowering it; the fingerprint walks it once and
// hashes what the printer would show (op names, operand numbering, types,
// attributes, block structure), printing each distinct type and attribute
// only once. It is the same in every process, unlike MLIR's own hashes of
// uniqued attributes (their addresses).
//
//===----------------------------------------------------------------------===//
#ifndef OSLCOMPILER_IRFINGERPRINT_H
#define OSLCOMPILER_IRFINGERPRINT_H

#include "mlir/IR/Operation.h"
#include "llvm/ADT/DenseMap.h"

#include <string>

namespace osl {

class IRFingerprint {
public:
  /// 32 hex digits identifying `op` and everything nested in it (not its
  /// location). Types and attributes printed for one call are remembered
  /// for the next, so hash the functions of one module with one object.
  std::string of(mlir::Operation *op);

private:
  uint64_t hashOf(const void *uniqued, llvm::function_ref<void(llvm::raw_ostream &)> print);
  uint64_t hashOf(mlir::Type type);
  uint64_t hashOf(mlir::Attribute attr);

  /// Printed types and attributes (uniqued in their context), hashed.
  llvm::DenseMap<const void *, uint64_t> printed;
};

} // namespace osl

#endif // OSLCOMPILER_IRFINGERPRINT_H
