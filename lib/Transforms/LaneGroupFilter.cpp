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
// Gabor noise's options (its filter and kernel) split the same way.
//
//===----------------------------------------------------------------------===//
#include "OslDialect/OslDialect.h"
#include "OslTransforms/Passes.h"

#include "mlir/Dialect/Arith/IR/Arith.h"
#include "mlir/Dialect/SCF/IR/SCF.h"
#include "llvm/ADT/TypeSwitch.h"

namespace mlir::osl {
#define GEN_PASS_DEF_LANEGROUPFILTER
#include "OslTransforms/Passes.h.inc"
} // namespace mlir::osl

using namespace mlir;
using namespace mlir::osl;

namespace {

/// Runs `op` once per group of lanes whose values of the operands
/// `choiceIndices` agree bit for bit (a lane always agrees with itself,
/// NaNs included). `mask` (null: the batch) holds the lanes to compute; a
/// lookup that takes a mask gets the group's through `setMask`, a pure op
/// computes every lane and keeps the group's.
void splitIntoLaneGroups(Operation *op, ArrayRef<unsigned> choiceIndices, Value mask,
                         function_ref<void(Operation *, Value)> setMask) {
  OpBuilder b(op);
  Location loc = op->getLoc();
  Type maskType = VaryingType::get(b.getI1Type());
  Value pending = mask ? mask : b.create<BatchMaskOp>(loc, maskType);
  // The loop carries the lanes left and every result of the op.
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
  for (unsigned index : choiceIndices) {
    Value c = op->getOperand(index);
    if (leadChoices.contains(c))
      continue;
    Type uniform = getUniformType(c.getType());
    Value lead = b.create<FirstLaneOp>(loc, uniform, c, lanesLeft);
    Value leadEverywhere = b.create<BroadcastOp>(loc, c.getType(), lead);
    Value eq = b.create<CmpOp>(loc, "same", c, leadEverywhere);
    same = same ? b.create<AndOp>(loc, same, eq).getResult() : eq;
    leadChoices.map(c, lead);
  }
  Value group = b.create<AndOp>(loc, lanesLeft, same);
  Operation *groupCall = b.clone(*op);
  for (unsigned index : choiceIndices)
    groupCall->setOperand(index, leadChoices.lookup(op->getOperand(index)));
  if (setMask)
    setMask(groupCall, group);
  SmallVector<Value> yielded = {b.create<AndOp>(loc, lanesLeft, b.create<NotOp>(loc, same))};
  for (auto [i, r] : llvm::enumerate(groupCall->getResults()))
    yielded.push_back(b.create<SelectOp>(loc, group, r, after->getArgument(i + 1)));
  b.create<scf::YieldOp>(loc, yielded);

  for (auto [i, r] : llvm::enumerate(op->getResults()))
    r.replaceAllUsesWith(loop.getResult(i + 1));
  op->erase();
}

/// The operand numbers of the operands in `ranges` whose values differ
/// per point.
SmallVector<unsigned> varyingOperands(ArrayRef<MutableOperandRange> ranges) {
  SmallVector<unsigned> indices;
  for (const MutableOperandRange &range : ranges)
    for (OpOperand &o : range)
      if (isVarying(o.get().getType()))
        indices.push_back(o.getOperandNumber());
  return indices;
}

void splitIntoLaneGroups(TextureOp op) {
  SmallVector<unsigned> choices = varyingOperands({op.getChoicesMutable()});
  if (choices.empty())
    return;
  splitIntoLaneGroups(op, choices, op.getMask(), [](Operation *call, Value group) {
    cast<TextureOp>(call).getMaskMutable().assign(group);
  });
}

/// Gabor noise evaluates its options once per call (the filter and the
/// kernel's frequency depend on them), so per-point options split it.
void splitIntoLaneGroups(NoiseOp op) {
  SmallVector<unsigned> choices = varyingOperands(
      {op.getAnisotropicMutable(), op.getDirectionMutable(), op.getBandwidthMutable(),
       op.getImpulsesMutable(), op.getDoFilterMutable()});
  if (choices.empty())
    return;
  splitIntoLaneGroups(op, choices, Value(), nullptr);
}

struct LaneGroupFilterPass
    : public mlir::osl::impl::LaneGroupFilterBase<LaneGroupFilterPass> {
  void runOnOperation() override {
    SmallVector<Operation *> ops;
    getOperation().walk([&](Operation *op) {
      if (isa<TextureOp, NoiseOp>(op))
        ops.push_back(op);
    });
    for (Operation *op : ops)
      llvm::TypeSwitch<Operation *>(op).Case<TextureOp, NoiseOp>(
          [](auto o) { splitIntoLaneGroups(o); });
  }
};

} // namespace
