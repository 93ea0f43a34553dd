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
  SmallVector<Type> carried = {maskType, op.getResult().getType(), op.getAlpha().getType()};
  SmallVector<Value> init = {pending, buildZero(b, loc, carried[1]),
                             buildZero(b, loc, carried[2])};
  auto loop = b.create<scf::WhileOp>(loc, carried, init);

  Block *before = b.createBlock(&loop.getBefore(), {}, carried, {loc, loc, loc});
  b.setInsertionPointToEnd(before);
  Value any = b.create<AnyOp>(loc, b.getI1Type(), before->getArgument(0));
  b.create<scf::ConditionOp>(loc, any, before->getArguments());

  Block *after = b.createBlock(&loop.getAfter(), {}, carried, {loc, loc, loc});
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
  Value result = b.create<SelectOp>(loc, group, groupCall.getResult(), after->getArgument(1));
  Value alpha = b.create<SelectOp>(loc, group, groupCall.getAlpha(), after->getArgument(2));
  Value stillLeft = b.create<AndOp>(loc, lanesLeft, b.create<NotOp>(loc, same));
  b.create<scf::YieldOp>(loc, ValueRange{stillLeft, result, alpha});

  op.getResult().replaceAllUsesWith(loop.getResult(1));
  op.getAlpha().replaceAllUsesWith(loop.getResult(2));
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
