//===- LaneGroupFilter.cpp - One call per group of agreeing lanes ---------===//
//
// OpenImageIO takes a texture's file, wrap modes, interpolation and
// subimage once per call. Where the shader chooses one of them per point,
// the lookup runs once per group of lanes that agree: the first pending
// lane leads, the lanes whose choices equal its own join it, the call is
// made for that group with the lead's (uniform) choices, and the group
// leaves the pending set; repeat until no lane is pending. Each lane is
// looked up exactly once, with its own options, so the results equal a
// lane-by-lane evaluation; a batch whose lanes agree makes one call.
//
//===----------------------------------------------------------------------===//
#include "OslDialect/OslDialect.h"
#include "OslTransforms/Passes.h"

#include "mlir/Dialect/Arith/IR/Arith.h"
#include "mlir/Dialect/SCF/IR/SCF.h"

namespace mlir::osl {
#define GEN_PASS_DEF_LANEGROUPFILTER
#include "OslTransforms/Passes.h.inc"
} // namespace mlir::osl

using namespace mlir;
using namespace mlir::osl;

namespace {

void splitIntoLaneGroups(TextureOp op) {
  SmallVector<Value> varyingChoices;
  for (Value c : op.getChoices())
    if (isVarying(c.getType()) && !llvm::is_contained(varyingChoices, c))
      varyingChoices.push_back(c);
  if (varyingChoices.empty())
    return;
  OpBuilder b(op);
  Location loc = op.getLoc();
  Type maskType = VaryingType::get(b.getI1Type());
  Value pending = op.getMask() ? op.getMask() : b.create<BatchMaskOp>(loc, maskType);
  // The loop carries the lanes left and every result of the lookup.
  SmallVector<Type> carried = {maskType};
  SmallVector<Value> init = {pending};
  for (Value r : op->getResults()) {
    carried.push_back(r.getType());
    init.push_back(buildZero(b, loc, r.getType()));
  }
  SmallVector<Location> locs(carried.size(), loc);
  auto loop = b.create<scf::WhileOp>(loc, carried, init);

  Block *before = b.createBlock(&loop.getBefore(), {}, carried, locs);
  b.setInsertionPointToEnd(before);
  Value any = b.create<AnyOp>(loc, b.getI1Type(), before->getArgument(0));
  b.create<scf::ConditionOp>(loc, any, before->getArguments());

  Block *after = b.createBlock(&loop.getAfter(), {}, carried, locs);
  b.setInsertionPointToEnd(after);
  Value lanesLeft = after->getArgument(0);
  // The lead's choices, and the lanes that made the same ones.
  IRMapping leadChoices;
  Value same;
  for (Value c : varyingChoices) {
    Type uniform = getUniformType(c.getType());
    Value lead = b.create<FirstLaneOp>(loc, uniform, c, lanesLeft);
    Value leadEverywhere = b.create<BroadcastOp>(loc, c.getType(), lead);
    Value eq = b.create<CmpOp>(loc, "eq", c, leadEverywhere);
    same = same ? b.create<AndOp>(loc, same, eq).getResult() : eq;
    leadChoices.map(c, lead);
  }
  Value group = b.create<AndOp>(loc, lanesLeft, same);
  auto groupCall = cast<TextureOp>(b.clone(*op));
  for (OpOperand &choice : groupCall.getChoicesMutable())
    choice.set(leadChoices.lookupOrDefault(choice.get()));
  groupCall.getMaskMutable().assign(group);
  SmallVector<Value> yielded = {b.create<AndOp>(loc, lanesLeft, b.create<NotOp>(loc, same))};
  for (auto [i, r] : llvm::enumerate(groupCall->getResults()))
    yielded.push_back(b.create<SelectOp>(loc, group, r, after->getArgument(i + 1)));
  b.create<scf::YieldOp>(loc, yielded);

  for (auto [i, r] : llvm::enumerate(op->getResults()))
    r.replaceAllUsesWith(loop.getResult(i + 1));
  op.erase();
}

struct LaneGroupFilterPass
    : public mlir::osl::impl::LaneGroupFilterBase<LaneGroupFilterPass> {
  void runOnOperation() override {
    SmallVector<TextureOp> lookups;
    getOperation().walk([&](TextureOp op) { lookups.push_back(op); });
    for (TextureOp op : lookups)
      splitIntoLaneGroups(op);
  }
};

} // namespace
