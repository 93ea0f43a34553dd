//===- VaryingPropagation.cpp - Infer varying values ----------------------===//
//
// A monotone fixed point: types only ever move from uniform to varying, so
// repeated sweeps over the function terminate. Data dependence makes a
// result varying when an operand is; control dependence makes the results
// of an osl.if with a varying condition, and every value carried by an
// osl.while with a varying condition, varying.
//
//===----------------------------------------------------------------------===//
#include "OslDialect/OslDialect.h"
#include "OslTransforms/Passes.h"
#include "VaryingTypes.h"

#include "mlir/IR/Builders.h"

namespace mlir::osl {
#define GEN_PASS_DEF_VARYINGPROPAGATION
#include "OslTransforms/Passes.h.inc"
} // namespace mlir::osl

using namespace mlir;
using namespace mlir::osl;

namespace {

bool isVaryingValue(Value v) { return isVarying(v.getType()); }

bool propagateIf(IfOp op) {
  bool changed = false;
  auto thenYield = cast<YieldOp>(op.getThenRegion().front().getTerminator());
  auto elseYield = cast<YieldOp>(op.getElseRegion().front().getTerminator());
  bool divergent = isVaryingValue(op.getCondition());
  for (auto [i, result] : llvm::enumerate(op.getResults()))
    if (divergent || isVaryingValue(thenYield.getValues()[i]) ||
        isVaryingValue(elseYield.getValues()[i]))
      changed |= makeVarying(result);
  return changed;
}

bool propagateWhile(WhileOp op) {
  bool changed = false;
  Block &before = op.getBefore().front();
  Block &after = op.getAfter().front();
  auto cond = cast<ConditionOp>(before.getTerminator());
  auto yield = cast<YieldOp>(after.getTerminator());
  // Lanes leave a loop with a varying condition at different iterations,
  // so every carried value differs between lanes after that.
  bool divergent = isVaryingValue(cond.getCondition());
  for (auto [i, arg] : llvm::enumerate(before.getArguments()))
    if (divergent || isVaryingValue(op.getInits()[i]) ||
        isVaryingValue(yield.getValues()[i]))
      changed |= makeVarying(arg);
  for (auto [i, forwarded] : llvm::enumerate(cond.getArgs()))
    if (divergent || isVaryingValue(forwarded)) {
      changed |= makeVarying(after.getArgument(i));
      changed |= makeVarying(op.getResult(i));
    }
  return changed;
}

/// Inserts osl.broadcast where a uniform value reaches a varying slot.
void broadcastInto(OpOperand &use, Type slot) {
  Value v = use.get();
  if (!isVarying(slot) || isVarying(v.getType()))
    return;
  OpBuilder b(use.getOwner());
  use.set(b.create<BroadcastOp>(use.getOwner()->getLoc(), slot, v));
}

void insertBroadcasts(func::FuncOp func) {
  func.walk([](Operation *op) {
    if (auto yield = dyn_cast<YieldOp>(op)) {
      Operation *parent = op->getParentOp();
      TypeRange slots = isa<IfOp>(parent)
                            ? TypeRange(parent->getResultTypes())
                            : TypeRange(cast<WhileOp>(parent)
                                            .getBefore()
                                            .front()
                                            .getArgumentTypes());
      for (auto [use, slot] : llvm::zip(op->getOpOperands(), slots))
        broadcastInto(use, slot);
    } else if (auto cond = dyn_cast<ConditionOp>(op)) {
      auto loop = cast<WhileOp>(op->getParentOp());
      for (auto [use, slot] : llvm::zip(cond.getArgsMutable(),
                                        loop.getResultTypes()))
        broadcastInto(use, slot);
    } else if (auto loop = dyn_cast<WhileOp>(op)) {
      for (auto [use, slot] :
           llvm::zip(loop.getInitsMutable(),
                     loop.getBefore().front().getArgumentTypes()))
        broadcastInto(use, slot);
    }
  });
}

struct VaryingPropagationPass
    : public mlir::osl::impl::VaryingPropagationBase<VaryingPropagationPass> {
  void runOnOperation() override {
    func::FuncOp func = getOperation();
    bool changed = true;
    while (changed) {
      changed = false;
      func.walk<WalkOrder::PreOrder>([&](Operation *op) {
        if (auto ifOp = dyn_cast<IfOp>(op))
          changed |= propagateIf(ifOp);
        else if (auto loop = dyn_cast<WhileOp>(op))
          changed |= propagateWhile(loop);
        else if (isDataOp(op) && llvm::any_of(op->getOperands(), isVaryingValue))
          for (Value r : op->getResults())
            changed |= makeVarying(r);
      });
    }
    // A broadcast placed before this pass (of what a layer left in a
    // global) whose value turned out varying is that value.
    func.walk([](BroadcastOp op) {
      if (isVaryingValue(op.getValue())) {
        op.replaceAllUsesWith(op.getValue());
        op.erase();
      }
    });
    insertBroadcasts(func);
  }
};

} // namespace
