//===- InsertMaskStack.cpp - Varying control flow to masked code ----------===//
//
// OSL's batched rules (as its SIMD backend masks): entering a varying `if` pushes
// cond AND top; both arms run under their masks and their values merge per
// lane. A varying loop iterates while any lane is active and lanes that
// left keep their values. Every mask is a value here; the innermost one is
// threaded down the recursion, so nested constructs see `top` directly.
//
// Arms are pure (outputs are written once, at the end of the shader), so
// running an arm for lanes that are off is harmless, except for loops,
// which would iterate for those lanes: they are seeded with the mask.
// Large arms are skipped when no lane of the batch takes them.
//
//===----------------------------------------------------------------------===//
#include "OslDialect/OslDialect.h"
#include "OslTransforms/Passes.h"

#include "mlir/Dialect/Arith/IR/Arith.h"
#include "mlir/IR/Builders.h"
#include "llvm/ADT/TypeSwitch.h"
#include "mlir/IR/IRMapping.h"

namespace mlir::osl {
#define GEN_PASS_DEF_INSERTMASKSTACK
#include "OslTransforms/Passes.h.inc"
} // namespace mlir::osl

using namespace mlir;
using namespace mlir::osl;

namespace {

class MaskStackBuilder {
public:
  MaskStackBuilder(func::FuncOp func, int skipThreshold, bool countLanes)
      : func(func), skipThreshold(skipThreshold), countLanes(countLanes) {}

  LogicalResult run() { return processBlock(func.getBody().front(), Value()); }

private:
  /// `mask` is the innermost active mask; null means every lane of the
  /// batch (no varying construct encloses this block).
  LogicalResult processBlock(Block &block, Value mask) {
    for (Operation &op : llvm::make_early_inc_range(block)) {
      LogicalResult result = success();
      if (auto ifOp = dyn_cast<IfOp>(op))
        result = isVarying(ifOp.getCondition().getType())
                     ? flattenVaryingIf(ifOp, mask)
                     : convertUniformIf(ifOp, mask);
      else if (auto loop = dyn_cast<WhileOp>(op))
        result = isVarying(loopCondition(loop).getCondition().getType())
                     ? maskVaryingLoop(loop, mask)
                     : convertUniformLoop(loop, mask);
      else if (mask)
        // Side effects (text, messages): only the points that reach them.
        llvm::TypeSwitch<Operation *>(&op)
            .Case<PrintOp, SetMessageOp, GetMessageOp, PointCloudOp>(
                [&](auto sideEffect) { sideEffect.getMaskMutable().assign(mask); });
      if (failed(result))
        return failure();
    }
    return success();
  }

  static ConditionOp loopCondition(WhileOp loop) {
    return cast<ConditionOp>(loop.getBefore().front().getTerminator());
  }

  /// The batch mask, created once at function entry when first needed.
  Value batchMask() {
    if (!entryMask) {
      OpBuilder b = OpBuilder::atBlockBegin(&func.getBody().front());
      entryMask = b.create<BatchMaskOp>(func.getLoc(),
                                        VaryingType::get(b.getI1Type()));
    }
    return entryMask;
  }

  Value andMask(OpBuilder &b, Location loc, Value mask, Value cond) {
    return mask ? b.create<AndOp>(loc, mask, cond).getResult() : cond;
  }

  static LogicalResult checkSlots(Operation *op, TypeRange from, TypeRange to) {
    for (auto [f, t] : llvm::zip(from, to))
      if (f != t)
        return op->emitOpError("value of type ")
               << f << " flows into " << t
               << "; run osl-varying-propagation first";
    return success();
  }

  LogicalResult flattenVaryingIf(IfOp op, Value mask) {
    OpBuilder b(op);
    Location loc = op.getLoc();
    Value cond = op.getCondition();
    Value notCond = b.create<NotOp>(loc, cond);
    // Masks below a varying if always include the batch's live lanes, so
    // tail lanes of a partial batch never run a loop or force an arm.
    Value outer = mask ? mask : batchMask();
    Value thenMask = andMask(b, loc, outer, cond);
    Value elseMask = andMask(b, loc, outer, notCond);
    Block &thenBlock = op.getThenRegion().front();
    Block &elseBlock = op.getElseRegion().front();
    if (failed(processBlock(thenBlock, thenMask)) ||
        failed(processBlock(elseBlock, elseMask)))
      return failure();
    auto thenYield = cast<YieldOp>(thenBlock.getTerminator());
    auto elseYield = cast<YieldOp>(elseBlock.getTerminator());
    if (failed(checkSlots(op, thenYield.getValues().getTypes(), op.getResultTypes())) ||
        failed(checkSlots(op, elseYield.getValues().getTypes(), op.getResultTypes())))
      return failure();
    // One arm with operations and one that only passes values on (`if (c)
    // { ...; break; }`, an accumulation): in a loop the arm is guarded
    // even when small, and its merge happens inside the guard, so
    // when no lane takes it the loop's values pass on without waiting for
    // the condition (a loop-carried chain the branch breaks, as OSL's
    // batched code branches around every arm).
    bool thenOnly = passesValuesOn(elseBlock), elseOnly = passesValuesOn(thenBlock);
    if (thenOnly != elseOnly) {
      Block &arm = thenOnly ? thenBlock : elseBlock;
      if (worthSkipping(arm) || (loopDepth > 0 && workIn(arm) >= kLoopArmWork)) {
        op.replaceAllUsesWith(inlineGuardedArm(op, arm, thenOnly ? thenMask : elseMask,
                                               thenOnly));
        op.erase();
        return success();
      }
    }
    SmallVector<Value> thenValues = inlineArm(op, thenBlock, thenMask);
    SmallVector<Value> elseValues = inlineArm(op, elseBlock, elseMask);
    b.setInsertionPoint(op);
    SmallVector<Value> merged;
    for (auto [t, e] : llvm::zip(thenValues, elseValues))
      merged.push_back(t == e ? t : b.create<SelectOp>(loc, cond, t, e).getResult());
    op.replaceAllUsesWith(merged);
    op.erase();
    return success();
  }

  /// Whether any lane takes `arm`; marked cold (kColdArmAttr) when the
  /// arm reports an error, as range checks do on every array access.
  static Value buildArmTest(OpBuilder &b, Location loc, Block &arm, Value armMask) {
    auto any = b.create<AnyOp>(loc, b.getI1Type(), armMask);
    bool reportsError = arm.walk([](PrintOp print) {
                             return print.getStream() == "error" ||
                                            print.getStream() == "renderer_error"
                                        ? WalkResult::interrupt()
                                        : WalkResult::advance();
                           }).wasInterrupted();
    if (reportsError)
      any->setAttr(kColdArmAttr, b.getUnitAttr());
    return any;
  }

  /// `scf.if (any(armMask))` before `op` (with an else block when it has
  /// `results`), holding the arm's operations; the caller adds the yields
  /// (the builder adds none: an arm that yields nothing, e.g. one that only
  /// prints, still needs its scf.yield).
  scf::IfOp guardArm(IfOp op, Block &arm, Value armMask, TypeRange results) {
    OpBuilder b(op);
    Value taken = buildArmTest(b, op.getLoc(), arm, armMask);
    auto guard = b.create<scf::IfOp>(op.getLoc(), results, taken,
                                     /*withThen=*/true, /*withElse=*/!results.empty());
    Block *thenBlock = guard.thenBlock();
    thenBlock->getOperations().splice(thenBlock->begin(), arm.getOperations(), arm.begin(),
                                      arm.getTerminator()->getIterator());
    return guard;
  }

  /// Operations in a loop's one-sided arm from which it is guarded: fewer
  /// (`if (c) n += 1;`) cost less than the test.
  static constexpr int kLoopArmWork = 3;

  /// Values made up front (constants, broadcasts).
  static bool isMadeUpFront(Operation &op) {
    return op.hasTrait<OpTrait::ConstantLike>() || isa<BroadcastOp>(op);
  }

  /// What flattening adds to an arm besides its own computation: masks
  /// (not, and, or of i1 lanes), merges, tests and yields.
  static bool isBookkeeping(Operation &op) {
    if (isa<SelectOp, AnyOp, YieldOp, scf::YieldOp, scf::IfOp>(op))
      return true;
    return isa<NotOp, AndOp, OrOp>(op) &&
           getUniformType(op.getResult(0).getType()).isInteger(1);
  }

  /// An arm that computes nothing (after its own nested constructs were
  /// flattened): its values come from outside, constants or broadcasts.
  static bool passesValuesOn(Block &arm) {
    return llvm::all_of(arm.without_terminator(), isMadeUpFront);
  }

  static int workIn(Block &arm) {
    int count = 0;
    arm.walk([&](Operation *op) { count += !isMadeUpFront(*op) && !isBookkeeping(*op); });
    return count;
  }

  /// `op`'s merged values when only `arm` has operations: under
  /// `scf.if (any(armMask))` the arm runs and each slot merges by the
  /// condition; otherwise the other arm's values (defined outside the if)
  /// pass on unchanged.
  SmallVector<Value> inlineGuardedArm(IfOp op, Block &arm, Value armMask, bool armIsThen) {
    Location loc = op.getLoc();
    Block &other = armIsThen ? op.getElseRegion().front() : op.getThenRegion().front();
    SmallVector<Value> armValues(cast<YieldOp>(arm.getTerminator()).getValues());
    SmallVector<Value> otherValues(cast<YieldOp>(other.getTerminator()).getValues());
    countActiveLanes(arm, loc, armMask);
    op->getBlock()->getOperations().splice(op->getIterator(), other.getOperations(),
                                           other.begin(), other.getTerminator()->getIterator());
    scf::IfOp guard = guardArm(op, arm, armMask, op.getResultTypes());
    OpBuilder tb = OpBuilder::atBlockEnd(guard.thenBlock());
    SmallVector<Value> merged;
    for (auto [a, o] : llvm::zip(armValues, otherValues))
      merged.push_back(a == o ? a
                              : tb.create<SelectOp>(loc, op.getCondition(), armIsThen ? a : o,
                                                    armIsThen ? o : a)
                                    .getResult());
    tb.create<scf::YieldOp>(loc, merged);
    if (op.getNumResults() > 0)
      OpBuilder::atBlockBegin(guard.elseBlock()).create<scf::YieldOp>(loc, otherValues);
    return SmallVector<Value>(guard.getResults());
  }

  /// Moves an arm's operations before `op` and returns the values it
  /// yields. A large arm goes under `scf.if (any(armMask))`; when it is
  /// skipped its values are zeros, which only lanes outside the arm's mask
  /// would see, and the merge never picks them for those lanes.
  SmallVector<Value> inlineArm(IfOp op, Block &arm, Value armMask) {
    auto yield = cast<YieldOp>(arm.getTerminator());
    countActiveLanes(arm, op.getLoc(), armMask);
    SmallVector<Value> values(yield.getValues());
    Block *parent = op->getBlock();
    if (!worthSkipping(arm)) {
      parent->getOperations().splice(op->getIterator(), arm.getOperations(),
                                     arm.begin(), yield->getIterator());
      return values;
    }
    Location loc = op.getLoc();
    // Only values made inside the arm need to leave the guard.
    SmallVector<Value> inner;
    for (Value v : values)
      if (v.getParentBlock() == &arm && !llvm::is_contained(inner, v))
        inner.push_back(v);
    scf::IfOp guard = guardArm(op, arm, armMask, TypeRange(ValueRange(inner)));
    OpBuilder::atBlockEnd(guard.thenBlock()).create<scf::YieldOp>(loc, inner);
    if (!inner.empty()) {
      OpBuilder eb = OpBuilder::atBlockBegin(guard.elseBlock());
      SmallVector<Value> zeros;
      for (Value v : inner)
        zeros.push_back(buildZero(eb, loc, v.getType()));
      eb.create<scf::YieldOp>(loc, zeros);
    }
    for (Value &v : values)
      if (auto *it = llvm::find(inner, v); it != inner.end())
        v = guard.getResult(it - inner.begin());
    return values;
  }

  /// With count-lanes, `block` starts by counting the batch's shading
  /// points among `mask`'s lanes; ops built here dominate the whole block.
  void countActiveLanes(Block &block, Location loc, Value mask) {
    if (!countLanes)
      return;
    OpBuilder b = OpBuilder::atBlockBegin(&block);
    Value active = b.create<AndOp>(loc, batchMask(), mask);
    b.create<CountLanesOp>(loc, active);
  }

  /// Loops, the library calls that expand to hundreds of operations
  /// (noise, splineinverse) and calls into the runtime (texture, string
  /// functions, prints, messages) always pay for the test.
  bool worthSkipping(Block &arm) {
    int64_t count = 0;
    bool expensive = false;
    arm.walk([&](Operation *nested) {
      ++count;
      expensive |= isa<scf::WhileOp, WhileOp, NoiseOp, NoiseByKindOp, SplineInverseOp, TextureOp,
                      StringCallOp, PrintOp, SetMessageOp, GetMessageOp, PointCloudOp>(nested);
    });
    return expensive || count > skipThreshold;
  }

  LogicalResult convertUniformIf(IfOp op, Value mask) {
    OpBuilder b(op);
    auto newIf = b.create<scf::IfOp>(op.getLoc(), op.getResultTypes(),
                                     op.getCondition(), false, false);
    newIf.getThenRegion().takeBody(op.getThenRegion());
    newIf.getElseRegion().takeBody(op.getElseRegion());
    for (Region *region : {&newIf.getThenRegion(), &newIf.getElseRegion()}) {
      Block &block = region->front();
      if (failed(processBlock(block, mask)))
        return failure();
      auto yield = cast<YieldOp>(block.getTerminator());
      if (failed(checkSlots(op, yield.getValues().getTypes(), op.getResultTypes())))
        return failure();
      OpBuilder yb(yield);
      yb.create<scf::YieldOp>(yield.getLoc(), yield.getValues());
      yield.erase();
    }
    op.replaceAllUsesWith(newIf.getResults());
    op.erase();
    return success();
  }

  LogicalResult convertUniformLoop(WhileOp op, Value mask) {
    OpBuilder b(op);
    auto loop = b.create<scf::WhileOp>(op.getLoc(), op.getResultTypes(),
                                       op.getInits());
    loop.getBefore().takeBody(op.getBefore());
    loop.getAfter().takeBody(op.getAfter());
    ++loopDepth;
    LogicalResult body = success(succeeded(processBlock(loop.getBefore().front(), mask)) &&
                                 succeeded(processBlock(loop.getAfter().front(), mask)));
    --loopDepth;
    if (failed(body))
      return failure();
    auto cond = cast<ConditionOp>(loop.getBefore().front().getTerminator());
    auto yield = cast<YieldOp>(loop.getAfter().front().getTerminator());
    if (failed(checkSlots(op, op.getInits().getTypes(),
                          loop.getBefore().getArgumentTypes())) ||
        failed(checkSlots(op, cond.getArgs().getTypes(), op.getResultTypes())) ||
        failed(checkSlots(op, yield.getValues().getTypes(),
                          loop.getBefore().getArgumentTypes())))
      return failure();
    OpBuilder cb(cond);
    cb.create<scf::ConditionOp>(cond.getLoc(), cond.getCondition(), cond.getArgs());
    cond.erase();
    OpBuilder yb(yield);
    yb.create<scf::YieldOp>(yield.getLoc(), yield.getValues());
    yield.erase();
    op.replaceAllUsesWith(loop.getResults());
    op.erase();
    return success();
  }

  /// The loop carries its active mask as one more value: the condition
  /// clears lanes whose condition failed, the loop goes on while any lane
  /// is set, and the body's results only replace the values of set lanes.
  LogicalResult maskVaryingLoop(WhileOp op, Value mask) {
    OpBuilder b(op);
    Location loc = op.getLoc();
    Type maskType = VaryingType::get(b.getI1Type());
    Value entry = mask ? mask : batchMask();
    SmallVector<Value> inits(op.getInits());
    inits.push_back(entry);
    SmallVector<Type> types(op.getResultTypes());
    types.push_back(maskType);
    auto loop = b.create<scf::WhileOp>(loc, types, inits);
    loop.getBefore().takeBody(op.getBefore());
    loop.getAfter().takeBody(op.getAfter());
    Block &before = loop.getBefore().front();
    Block &after = loop.getAfter().front();
    Value beforeMask = before.addArgument(maskType, loc);
    Value afterMask = after.addArgument(maskType, loc);
    ++loopDepth;
    LogicalResult body = success(succeeded(processBlock(before, beforeMask)) &&
                                 succeeded(processBlock(after, afterMask)));
    --loopDepth;
    if (failed(body))
      return failure();
    countActiveLanes(after, loc, afterMask);

    auto cond = cast<ConditionOp>(before.getTerminator());
    if (failed(checkSlots(op, cond.getArgs().getTypes(), op.getResultTypes())) ||
        failed(checkSlots(op, op.getInits().getTypes(),
                          TypeRange(before.getArgumentTypes()).drop_back())))
      return failure();
    OpBuilder cb(cond);
    Value stillActive = cb.create<AndOp>(cond.getLoc(), beforeMask, cond.getCondition());
    Value anyActive = cb.create<AnyOp>(cond.getLoc(), cb.getI1Type(), stillActive);
    // A condition with side effects (`while (++i < n)`, a call with an
    // output argument) forwards new values: lanes that evaluated it take
    // them (even those it now sends out), lanes that left before keep
    // their carried values.
    SmallVector<Value> forwarded;
    for (auto [value, carried] :
         llvm::zip(cond.getArgs(), before.getArguments().drop_back()))
      forwarded.push_back(value == carried
                              ? value
                              : cb.create<SelectOp>(cond.getLoc(), beforeMask, value, carried)
                                    .getResult());
    forwarded.push_back(stillActive);
    cb.create<scf::ConditionOp>(cond.getLoc(), anyActive, forwarded);
    cond.erase();

    auto yield = cast<YieldOp>(after.getTerminator());
    if (failed(checkSlots(op, yield.getValues().getTypes(),
                          TypeRange(before.getArgumentTypes()).drop_back())))
      return failure();
    OpBuilder yb(yield);
    SmallVector<Value> next;
    for (auto [value, previous] :
         llvm::zip(yield.getValues(), after.getArguments().drop_back()))
      next.push_back(value == previous
                         ? value
                         : yb.create<SelectOp>(yield.getLoc(), afterMask, value,
                                               previous)
                               .getResult());
    next.push_back(afterMask);
    yb.create<scf::YieldOp>(yield.getLoc(), next);
    yield.erase();

    op.replaceAllUsesWith(loop.getResults().drop_back());
    op.erase();
    return success();
  }

  func::FuncOp func;
  int skipThreshold;
  bool countLanes;
  Value entryMask;
  int loopDepth = 0;
};

struct InsertMaskStackPass
    : public mlir::osl::impl::InsertMaskStackBase<InsertMaskStackPass> {
  using InsertMaskStackBase::InsertMaskStackBase;
  void runOnOperation() override {
    if (failed(MaskStackBuilder(getOperation(), skipThreshold, countLanes).run()))
      signalPassFailure();
  }
};

} // namespace
