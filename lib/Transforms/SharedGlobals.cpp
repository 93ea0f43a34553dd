//===- SharedGlobals.cpp - Globals a group's layers share -----------------===//
#include "SharedGlobals.h"

#include "OslDialect/OslDialect.h"

#include "mlir/IR/Builders.h"
#include "mlir/IR/Dominance.h"
#include "llvm/ADT/DenseMap.h"

using namespace mlir;
using namespace mlir::osl;

void mlir::osl::forwardWrittenGlobals(func::FuncOp group) {
  SmallVector<SetGlobalOp> writes;
  group.walk([&](SetGlobalOp op) { writes.push_back(op); });
  if (writes.empty())
    return;
  SmallVector<GlobalOp> reads;
  group.walk([&](GlobalOp op) { reads.push_back(op); });
  DominanceInfo dominance(group);
  // A global is varying: a uniform value written to it is broadcast once,
  // after the write (osl-varying-propagation drops the broadcast if the
  // value turns out varying).
  llvm::DenseMap<Operation *, Value> asRead;
  auto valueOf = [&](SetGlobalOp write, Type readType) {
    Value &v = asRead[write];
    if (v)
      return v;
    v = write.getValue();
    if (!isVarying(v.getType())) {
      OpBuilder b(write);
      v = b.create<BroadcastOp>(write.getLoc(), readType, v);
      v.getDefiningOp()->setDiscardableAttrs(write->getDiscardableAttrDictionary());
    }
    return v;
  };
  for (GlobalOp read : reads) {
    SetGlobalOp latest;
    for (SetGlobalOp write : writes)
      if (write.getName() == read.getName() &&
          dominance.properlyDominates(write.getOperation(), read.getOperation()) &&
          (!latest || dominance.properlyDominates(latest.getOperation(), write.getOperation())))
        latest = write;
    if (latest) {
      read.replaceAllUsesWith(valueOf(latest, read.getType()));
      read.erase();
    }
  }
  for (SetGlobalOp write : writes)
    write.erase();
}
