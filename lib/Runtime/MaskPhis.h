//===- MaskPhis.h - Loop masks kept as full-width lanes ----------*- C++ -*-===//
//
// A varying loop carries its lane mask around the back edge as a phi of
// <N x i1>. Without AVX-512's mask registers the x86 backend keeps such a
// phi as packed 16-bit lanes, so every iteration narrows the mask after its
// compare and widens it again for each blend: instructions on the loop's
// critical path. Carrying the mask as <N x i32> of 0 / -1 instead lets each
// compare's result feed the blends directly. Only codegen changes: the
// lanes' values are the same.
//
//===----------------------------------------------------------------------===//
#ifndef OSLRUNTIME_MASKPHIS_H
#define OSLRUNTIME_MASKPHIS_H

namespace llvm {
class Function;
} // namespace llvm

namespace osl {

/// When `f` has a phi of <N x i1> (N >= 4): rewrites those phis and the
/// and/or/xor of such masks as <N x i32> lanes of 0 / -1 (other masks
/// sign-extended where they are made), and gives their other users a sign
/// test of the wide value where each original stood. Returns whether
/// anything changed.
bool widenMaskPhis(llvm::Function &f);

} // namespace osl

#endif // OSLRUNTIME_MASKPHIS_H
