//===- UnrollConstantLoops.cpp - Straight-line code for counted loops
//------===//
//
// Each trip is peeled into a scf.execute_region of its own (the condition's
// operations in one, the body's in the next) and folded there, so that a
// trip costs what it holds, and a loop that turns out not to unroll is put
// back by erasing the regions. Once the condition folds to false the
// regions are inlined and the loop's results are the values the condition
// forwarded.
//
// Loops are visited innermost first, and the function is folded after each
// unrolled loop: an outer loop's trip count, or a later loop's bound, may
// fold only then.
//
//===----------------------------------------------------------------------===//
#include "OslDialect/OslDialect.h"
#include "OslTransforms/Passes.h"
#include "VaryingTypes.h"

#include "mlir/IR/IRMapping.h"
#include "mlir/IR/Matchers.h"
#include "mlir/Transforms/GreedyPatternRewriteDriver.h"
#include "llvm/ADT/SmallPtrSet.h"

namespace mlir::osl {
#define GEN_PASS_DEF_UNROLLCONSTANTLOOPS
#include "OslTransforms/Passes.h.inc"
} // namespace mlir::osl

using namespace mlir;
using namespace mlir::osl;

namespace {

/// The value of a constant i1, if `v` is one.
std::optional<bool> constantCondition(Value v) {
  llvm::APInt bits;
  if (!matchPattern(v, m_ConstantInt(&bits)))
    return std::nullopt;
  return !bits.isZero();
}

int64_t countOps(Region &region) {
  int64_t n = 0;
  region.walk([&](Operation *) { ++n; });
  return n;
}

/// Whether `loop` reads or writes an array element at an index it carries:
/// a select on `index == k` (or `<=`, `>=` at the ends) with `index` an
/// argument of a loop's block - the chain of selects an array access by a
/// computed index is. Only such loops gain from unrolling (their indices
/// become constants); unrolling others only costs compile time. A read of
/// a long array is an osl.pick, which reads its elements from memory at
/// any index (a load for a uniform one): it does not count.
bool indexesArrays(WhileOp loop) {
  auto carried = [](Value v) {
    auto arg = dyn_cast<BlockArgument>(v);
    return arg && isa<WhileOp>(arg.getOwner()->getParentOp());
  };
  bool found = false;
  loop->walk([&](SelectOp select) {
    auto cmp = select.getCondition().getDefiningOp<CmpOp>();
    if (!cmp)
      return WalkResult::advance();
    Value a = cmp->getOperand(0), b = cmp->getOperand(1);
    if ((carried(a) && matchPattern(b, m_Constant())) ||
        (carried(b) && matchPattern(a, m_Constant()))) {
      found = true;
      return WalkResult::interrupt();
    }
    return WalkResult::advance();
  });
  return found;
}

/// Why a loop was not unrolled: its condition did not fold (yet), or it
/// will never be (too big, or nothing to gain).
enum class Outcome { Unrolled, NotConstant, TooBig };

class LoopUnroller {
public:
  LoopUnroller(const FrozenRewritePatternSet &folding, int64_t maxTrips, int64_t maxOps)
      : folding(folding), maxTrips(maxTrips), maxOps(maxOps) {}

  Outcome unroll(WhileOp loop) {
    Block &before = loop.getBefore().front();
    Block &after = loop.getAfter().front();
    auto condition = cast<ConditionOp>(before.getTerminator());
    if (isVarying(condition.getCondition().getType()))
      return Outcome::NotConstant;
    if (!indexesArrays(loop))
      return Outcome::TooBig; // never worth it
    OpBuilder b(loop);
    SmallVector<scf::ExecuteRegionOp> trips;
    SmallVector<Value> carried(loop.getInits());
    int64_t ops = 0;
    for (int64_t trip = 0;; ++trip) {
      // The condition: [condition, forwarded values...].
      SmallVector<Value> forwarded = {condition.getCondition()};
      llvm::append_range(forwarded, condition.getArgs());
      scf::ExecuteRegionOp test = peel(b, before, carried, forwarded, loop.getLoc());
      trips.push_back(test);
      ops += countOps(test.getRegion());
      auto testYield = cast<scf::YieldOp>(test.getRegion().front().getTerminator());
      std::optional<bool> goOn = constantCondition(testYield.getOperand(0));
      if (!goOn || (*goOn && (trip >= maxTrips || ops > maxOps))) {
        // Put back (but for constants the folding hoisted to the
        // function's entry, dead): later trips use earlier ones only.
        for (scf::ExecuteRegionOp t : llvm::reverse(trips))
          t.erase();
        return goOn ? Outcome::TooBig : Outcome::NotConstant;
      }
      SmallVector<Value> results = exits(test);
      results.erase(results.begin());
      if (!*goOn) {
        // The loop's uses first: inlining replaces the regions' results.
        // A result the loop typed uniform may now be a varying value: the
        // ops reading it follow (osl.deriv's type is its value's).
        loop.replaceAllUsesWith(results);
        loop.erase();
        makeDataUsersVarying(results);
        for (scf::ExecuteRegionOp t : trips)
          inlineRegion(t);
        return Outcome::Unrolled;
      }
      auto yield = cast<YieldOp>(after.getTerminator());
      scf::ExecuteRegionOp body =
          peel(b, after, results, SmallVector<Value>(yield.getValues()), loop.getLoc());
      trips.push_back(body);
      ops += countOps(body.getRegion());
      carried = exits(body);
    }
  }

private:
  /// A copy of `block`'s operations, its arguments bound to `args`, in a
  /// region of its own that yields `yielded` (values of `block`), folded.
  scf::ExecuteRegionOp peel(OpBuilder &b, Block &block, ValueRange args, ValueRange yielded,
                            Location loc) {
    SmallVector<Type> types;
    for (Value v : yielded)
      types.push_back(v.getType());
    auto region = b.create<scf::ExecuteRegionOp>(loc, types);
    Block *copy = b.createBlock(&region.getRegion());
    IRMapping mapping;
    mapping.map(block.getArguments(), args);
    for (Operation &op : block.without_terminator())
      b.clone(op, mapping);
    // The trip's copies read the values the last trip left, which may be
    // varying where the loop's arguments were typed uniform.
    makeDataUsersVarying(args);
    SmallVector<Value> mapped;
    for (Value v : yielded)
      mapped.push_back(mapping.lookupOrDefault(v));
    b.create<scf::YieldOp>(loc, mapped);
    b.setInsertionPointAfter(region);
    // The region's ops (nested ones too: an arm a folded branch inlines is
    // folded with them) and those the folding makes; the region is not
    // isolated from above, so the greedy driver takes them as a list.
    SmallVector<Operation *> ops;
    region.getRegion().walk([&](Operation *op) { ops.push_back(op); });
    // The driver takes its list from the back: reversed, it folds
    // definitions before their users (each op once, where the walk's order
    // revisited users as their operands folded; a trip of hex_tiles' outer
    // loop, 642 ops, folded in 0.7 instead of 2.7 ms, to the same IR).
    std::reverse(ops.begin(), ops.end());
    GreedyRewriteConfig config;
    config.strictMode = GreedyRewriteStrictness::ExistingAndNewOps;
    (void)applyOpPatternsAndFold(ops, folding, config);
    // Folding may change a yielded value's type (a varying-looking value
    // folded to a uniform constant): the region's results follow it.
    auto terminator = cast<scf::YieldOp>(copy->getTerminator());
    for (auto [result, value] : llvm::zip(region.getResults(), terminator.getOperands()))
      result.setType(value.getType());
    return region;
  }

  /// What `region` yields, as values usable after it: a value defined
  /// outside it itself, a constant folded inside it a copy made before it
  /// (so that the next trip folds with it); else the region's result.
  static SmallVector<Value> exits(scf::ExecuteRegionOp region) {
    auto yield = cast<scf::YieldOp>(region.getRegion().front().getTerminator());
    SmallVector<Value> values;
    OpBuilder b(region);
    for (auto [result, value] : llvm::zip(region.getResults(), yield.getOperands())) {
      bool inside = region->isProperAncestor(value.getParentRegion()->getParentOp()) ||
                    value.getParentRegion() == &region.getRegion();
      // A constant folded inside: a copy before the region.
      if (inside && matchPattern(value, m_Constant()))
        values.push_back(b.clone(*value.getDefiningOp())->getResult(0));
      else
        values.push_back(inside ? Value(result) : value);
    }
    return values;
  }

  static void inlineRegion(scf::ExecuteRegionOp region) {
    Block &block = region.getRegion().front();
    auto yield = cast<scf::YieldOp>(block.getTerminator());
    SmallVector<Value> values(yield.getOperands());
    yield.erase();
    region->getBlock()->getOperations().splice(Block::iterator(region), block.getOperations());
    region.replaceAllUsesWith(values);
    region.erase();
  }

  const FrozenRewritePatternSet &folding;
  int64_t maxTrips, maxOps;
};

struct UnrollConstantLoopsPass
    : public mlir::osl::impl::UnrollConstantLoopsBase<UnrollConstantLoopsPass> {
  using UnrollConstantLoopsBase::UnrollConstantLoopsBase;

  LogicalResult initialize(MLIRContext *ctx) override {
    RewritePatternSet patterns(ctx);
    populateFoldConstantsPatterns(patterns);
    folding = FrozenRewritePatternSet(std::move(patterns));
    return success();
  }

  void runOnOperation() override {
    func::FuncOp func = getOperation();
    LoopUnroller unroller(folding, maxTrips, maxOps);
    // Loops unrolled inside loops unrolled: at most 4 * max-ops operations
    // more in the whole function, however deep the nest.
    int64_t budget = 4 * maxOps, before = countOps(func.getBody());
    llvm::SmallPtrSet<Operation *, 8> tooBig;
    for (bool changed = true; changed;) {
      changed = false;
      SmallVector<WhileOp> loops;
      func.walk([&](WhileOp loop) { loops.push_back(loop); }); // innermost first
      for (WhileOp loop : loops) {
        if (tooBig.count(loop) || countOps(func.getBody()) - before > budget)
          continue;
        Outcome outcome = unroller.unroll(loop);
        if (outcome == Outcome::TooBig)
          tooBig.insert(loop);
        if (outcome == Outcome::Unrolled) {
          changed = true;
          // Loops erased with it may leave their addresses to new ones.
          tooBig.clear();
          break;
        }
      }
      // Folding only: region simplification (dead block arguments, block
      // merging) is the canonicalizer's, once, after this pass. Run after
      // every unrolled loop, it cost hex_tiles 1.3% of its whole compile
      // (callgrind: 416M -> 411M instructions, the same LLVM IR).
      GreedyRewriteConfig config;
      config.enableRegionSimplification = GreedySimplifyRegionLevel::Disabled;
      if (changed && failed(applyPatternsAndFoldGreedily(func, folding, config)))
        return signalPassFailure();
    }
  }

  FrozenRewritePatternSet folding;
};

} // namespace
