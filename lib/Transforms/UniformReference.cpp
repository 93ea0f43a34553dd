//===- UniformReference.cpp - One point at a time, without masks ----------===//
//
// Reference mode: every value becomes uniform, so osl-insert-mask-stack
// turns all control flow into ordinary branches and loops, and at width 1
// the kernel shades one point per call. The differential tester checks the
// masked vector kernels against this.
//
//===----------------------------------------------------------------------===//
#include "OslDialect/OslDialect.h"
#include "OslTransforms/Passes.h"

namespace mlir::osl {
#define GEN_PASS_DEF_UNIFORMREFERENCE
#include "OslTransforms/Passes.h.inc"
} // namespace mlir::osl

using namespace mlir;
using namespace mlir::osl;

namespace {

void makeUniform(Value v) {
  if (isVarying(v.getType()))
    v.setType(getUniformType(v.getType()));
}

struct UniformReferencePass
    : public mlir::osl::impl::UniformReferenceBase<UniformReferencePass> {
  void runOnOperation() override {
    // Tells the verifier that uniform globals are intended.
    getOperation()->setAttr("osl.reference", UnitAttr::get(&getContext()));
    SmallVector<BroadcastOp> broadcasts;
    getOperation().walk([&](Operation *op) {
      for (Region &region : op->getRegions())
        for (Block &block : region)
          for (BlockArgument arg : block.getArguments())
            makeUniform(arg);
      for (Value result : op->getResults())
        makeUniform(result);
      if (auto b = dyn_cast<BroadcastOp>(op))
        broadcasts.push_back(b);
    });
    for (BroadcastOp b : broadcasts) {
      b.getResult().replaceAllUsesWith(b.getValue());
      b.erase();
    }
  }
};

} // namespace
