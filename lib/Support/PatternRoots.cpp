//===- PatternRoots.cpp - Run a pattern set only where it can match -------===//
#include "OslSupport/PatternRoots.h"

#include "llvm/ADT/DenseSet.h"

namespace mlir::osl {

bool hasPatternRoot(Operation *root, RewritePatternSet &patterns) {
  llvm::SmallDenseSet<OperationName> names;
  for (const std::unique_ptr<RewritePattern> &pattern : patterns.getNativePatterns()) {
    std::optional<OperationName> name = pattern->getRootKind();
    if (!name)
      return true; // matches any op (or by interface or trait)
    names.insert(*name);
  }
  return root
      ->walk([&](Operation *op) {
        return names.contains(op->getName()) ? WalkResult::interrupt()
                                             : WalkResult::advance();
      })
      .wasInterrupted();
}

} // namespace mlir::osl
