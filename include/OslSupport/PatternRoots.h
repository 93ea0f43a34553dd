//===- PatternRoots.h - Run a pattern set only where it can match ---------===//
//
// The greedy driver visits and folds every op of the IR it is given, even
// when no op is a root of its patterns. In a JIT compile that sweep is a
// real cost for a pass with nothing left to rewrite, so passes check for a
// root first.
//
//===----------------------------------------------------------------------===//
#ifndef OSLSUPPORT_PATTERNROOTS_H
#define OSLSUPPORT_PATTERNROOTS_H

#include "mlir/IR/PatternMatch.h"

namespace mlir::osl {

/// Whether an op nested in `root` is the root of one of `patterns` (or one
/// of them matches any op).
bool hasPatternRoot(Operation *root, RewritePatternSet &patterns);

} // namespace mlir::osl

#endif // OSLSUPPORT_PATTERNROOTS_H
