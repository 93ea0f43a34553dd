//===- LowerToLLVM.cpp - vector/arith/math/scf to the LLVM dialect --------===//
//
// Math first becomes polynomial approximations in the same vector types
// (so a 16-wide sin stays in zmm registers instead of 16 sinf calls, and
// the same polynomial runs at every width), then everything is converted
// to LLVM in one full conversion.
//
//===----------------------------------------------------------------------===//
#include "OslConversion/Passes.h"
#include "OslDialect/OslDialect.h"
#include "OslSupport/PatternRoots.h"

#include "mlir/Conversion/ArithToLLVM/ArithToLLVM.h"
#include "mlir/Conversion/ControlFlowToLLVM/ControlFlowToLLVM.h"
#include "mlir/Conversion/FuncToLLVM/ConvertFuncToLLVM.h"
#include "mlir/Conversion/LLVMCommon/ConversionTarget.h"
#include "mlir/Conversion/LLVMCommon/TypeConverter.h"
#include "mlir/Conversion/MathToLLVM/MathToLLVM.h"
#include "mlir/Conversion/ReconcileUnrealizedCasts/ReconcileUnrealizedCasts.h"
#include "mlir/Pass/PassManager.h"
#include "mlir/Conversion/SCFToControlFlow/SCFToControlFlow.h"
#include "mlir/Conversion/VectorToLLVM/ConvertVectorToLLVM.h"
#include "mlir/Dialect/ControlFlow/IR/ControlFlow.h"
#include "mlir/Dialect/ControlFlow/IR/ControlFlowOps.h"
#include "mlir/Dialect/SCF/IR/SCF.h"
#include "mlir/Dialect/Vector/IR/VectorOps.h"
#include "mlir/Dialect/Math/Transforms/Passes.h"
#include "mlir/Dialect/LLVMIR/LLVMDialect.h"
#include "mlir/Dialect/Vector/Transforms/LoweringPatterns.h"
#include "mlir/IR/Matchers.h"
#include "mlir/Transforms/DialectConversion.h"
#include "mlir/Transforms/GreedyPatternRewriteDriver.h"

#include <map>
#include <vector>

namespace mlir::osl {
#define GEN_PASS_DEF_LOWERTOLLVM
#include "OslConversion/Passes.h.inc"
} // namespace mlir::osl

using namespace mlir;

namespace {


constexpr llvm::StringLiteral kLaneGuardAttr = "osl.lane_guard";

/// Operations in a guarded arm up to which LLVM might speculate it (its
/// own budget is a few instructions; arms guarded for their work - loops,
/// noise, texture - are far larger or make calls, and stay branches by
/// themselves).
constexpr int kSpeculableArmOps = 24;

/// Whether `op` tests if any lane takes an arm (an OR reduction of the
/// arm's mask) that is cold (it reports an error) or small
/// (osl-insert-mask-stack guards such arms in loops).
bool isUnlikelyOrSmallLaneGuard(scf::IfOp op) {
  auto any = op.getCondition().getDefiningOp<vector::ReductionOp>();
  if (!any || any.getKind() != vector::CombiningKind::OR)
    return false;
  if (any->hasAttr(osl::kColdArmAttr))
    return true;
  int ops = 0;
  bool calls = false;
  op.getThenRegion().walk([&](Operation *nested) {
    ++ops;
    calls |= isa<CallOpInterface>(nested);
  });
  return !calls && ops <= kSpeculableArmOps;
}

/// Those lane guards' branches are tagged (kLaneGuardAttr) for
/// weighLaneGuards.
LogicalResult lowerStructuredControlFlow(ModuleOp module) {
  llvm::DenseSet<Value> guardConditions;
  module.walk([&](scf::IfOp op) {
    if (isUnlikelyOrSmallLaneGuard(op))
      guardConditions.insert(op.getCondition());
  });
  RewritePatternSet patterns(module.getContext());
  populateSCFToControlFlowConversionPatterns(patterns);
  ConversionTarget target(*module.getContext());
  target.addIllegalDialect<scf::SCFDialect>();
  target.markUnknownOpDynamicallyLegal([](Operation *) { return true; });
  if (failed(applyPartialConversion(module, target, std::move(patterns))))
    return failure();
  module.walk([&](cf::CondBranchOp br) {
    if (guardConditions.contains(br.getCondition()))
      br->setAttr(kLaneGuardAttr, UnitAttr::get(module.getContext()));
  });
  return success();
}

/// A cold arm's branch says skipping is likely, which moves the arm out of
/// line. So does a small arm's: without weights LLVM's SimplifyCFG
/// speculates the arm back into selects on the arm's mask, which brings
/// back the dependence on the condition the guard removes; weights beyond
/// its "predictable" threshold (99%) keep the branch. Other guards (large
/// arms, calls) stay branches by themselves and are often taken by some
/// lane, so they get no weights.
void weighLaneGuards(ModuleOp module) {
  module.walk([](LLVM::CondBrOp br) {
    if (br->removeAttr(kLaneGuardAttr))
      br.setBranchWeights(llvm::ArrayRef<int32_t>{1, 1000});
  });
}

/// The shift amount of `shift` when it is the same constant in every lane.
std::optional<uint64_t> constantShift(Value amount) {
  APInt value;
  if (!matchPattern(amount, m_ConstantInt(&value)))
    return std::nullopt;
  return value.getZExtValue();
}

/// (x << k) | (x >> (bits - k)) becomes one funnel shift, LLVM's rotate:
/// the noise hashes are mostly rotates, and handing them to codegen as three
/// instructions each left its instruction selection to find them again
/// (a quarter of marble's kernel is rotates).
void formRotates(ModuleOp module) {
  SmallVector<arith::OrIOp> ors;
  module.walk([&](arith::OrIOp op) { ors.push_back(op); });
  for (arith::OrIOp op : ors) {
    for (int order = 0; order < 2; ++order) {
      auto left = op->getOperand(order).getDefiningOp<arith::ShLIOp>();
      auto right = op->getOperand(1 - order).getDefiningOp<arith::ShRUIOp>();
      if (!left || !right || left.getLhs() != right.getLhs())
        continue;
      std::optional<uint64_t> k = constantShift(left.getRhs());
      std::optional<uint64_t> rest = constantShift(right.getRhs());
      unsigned bits = getElementTypeOrSelf(op.getType()).getIntOrFloatBitWidth();
      if (!k || !rest || *k == 0 || *k >= bits || *k + *rest != bits)
        continue;
      OpBuilder b(op);
      Value x = left.getLhs();
      Value rotated = b.create<LLVM::FshlOp>(op.getLoc(), op.getType(), x, x, left.getRhs());
      op.replaceAllUsesWith(rotated);
      op.erase();
      if (left->use_empty())
        left.erase();
      if (right->use_empty())
        right.erase();
      break;
    }
  }
}

/// Each osl.codegen_fence as llvm.arithmetic.fence on its bits seen as
/// f32: LLVM's instruction selection looks through neither it nor its
/// bitcasts' pairing, and emits nothing for it.
void lowerCodegenFences(ModuleOp module) {
  SmallVector<osl::CodegenFenceOp> fences;
  module.walk([&](osl::CodegenFenceOp op) { fences.push_back(op); });
  for (osl::CodegenFenceOp op : fences) {
    OpBuilder b(op);
    Type bits = op.getType();
    Type floats = b.getF32Type();
    if (auto vec = dyn_cast<VectorType>(bits))
      floats = VectorType::get(vec.getShape(), floats);
    Value asFloats = b.create<arith::BitcastOp>(op.getLoc(), floats, op.getValue());
    auto fence = b.create<LLVM::CallIntrinsicOp>(op.getLoc(), floats, "llvm.arithmetic.fence",
                                                 ValueRange{asFloats});
    op.replaceAllUsesWith(
        b.create<arith::BitcastOp>(op.getLoc(), bits, fence->getResult(0)).getResult());
    op.erase();
  }
}

/// Vector int / and % by lanes not known to be one constant divide in
/// double precision. x86 has no vector integer division, so LLVM divides
/// lane by lane with idiv; a double holds every int, and the correctly
/// rounded n/d truncates to the exact quotient (its error, under
/// |n| 2^-53, is below 1/|d|, the least distance of a quotient that is not
/// whole from a whole number): two vector divisions give idiv's results
/// bit for bit. Where divsi/remsi is defined (no lane divides by 0 or
/// INT_MIN by -1, which their producers rule out) so is this. Constant
/// divisors stay: LLVM multiplies by them. Ints wider than 32 bits stay
/// too: a double does not hold them all.
void divideLanesInDouble(ModuleOp module) {
  SmallVector<Operation *> divisions;
  module.walk([&](Operation *op) {
    if (!isa<arith::DivSIOp, arith::RemSIOp>(op) ||
        matchPattern(op->getOperand(1), m_Constant()))
      return;
    auto type = dyn_cast<VectorType>(op->getResultTypes()[0]);
    if (type && type.getElementType().getIntOrFloatBitWidth() <= 32)
      divisions.push_back(op);
  });
  for (Operation *op : divisions) {
    OpBuilder b(op);
    Location loc = op->getLoc();
    Value num = op->getOperand(0), den = op->getOperand(1);
    auto type = cast<VectorType>(num.getType());
    Type f64 = VectorType::get(type.getShape(), b.getF64Type());
    Value quotient = b.create<arith::FPToSIOp>( // truncates
        loc, type,
        b.create<arith::DivFOp>(loc, b.create<arith::SIToFPOp>(loc, f64, num),
                                b.create<arith::SIToFPOp>(loc, f64, den)));
    Value result = quotient;
    if (isa<arith::RemSIOp>(op))
      result = b.create<arith::SubIOp>(loc, num, b.create<arith::MulIOp>(loc, quotient, den));
    op->getResult(0).replaceAllUsesWith(result);
    op->erase();
  }
}

/// Where `element` can be stored: right after its definition, or after the
/// stack blocks at the top of the entry block for an argument of it.
void setInsertionAfterDefinition(OpBuilder &b, Value element, Operation *lastBlock) {
  auto arg = dyn_cast<BlockArgument>(element);
  if (arg && arg.getOwner() == lastBlock->getBlock())
    b.setInsertionPointAfter(lastBlock);
  else
    b.setInsertionPointAfterValue(element);
}

/// Whether an element of `pick` is defined anew on each trip of a loop
/// around the pick (an array updated in the loop that reads it): storing
/// the whole array every trip would cost more than selecting over it.
bool elementsChangeEachTrip(osl::LanePickOp pick) {
  Operation *loop = pick->getParentOp();
  while (loop && !isa<scf::WhileOp, scf::ForOp>(loop))
    loop = isa<FunctionOpInterface>(loop) ? nullptr : loop->getParentOp();
  if (!loop)
    return false;
  return llvm::any_of(pick.getElements(), [&](Value e) {
    return loop->isProperAncestor(e.getParentBlock()->getParentOp()) ||
           e.getParentBlock()->getParentOp() == loop;
  });
}

/// The pick as a chain of selects from the last element down (the index
/// is within the elements).
Value selectElement(OpBuilder &b, Location loc, osl::LanePickOp pick) {
  Value index = pick.getIndex();
  auto elements = pick.getElements();
  Value acc = elements.back();
  for (int64_t k = int64_t(elements.size()) - 2; k >= 0; --k) {
    Value bound = b.create<arith::ConstantOp>(
        loc, isa<VectorType>(index.getType())
                 ? TypedAttr(DenseElementsAttr::get(cast<ShapedType>(index.getType()),
                                                    b.getI32IntegerAttr(int32_t(k))))
                 : TypedAttr(b.getI32IntegerAttr(int32_t(k))));
    Value below = b.create<arith::CmpIOp>(loc, arith::CmpIPredicate::sle, index, bound);
    acc = b.create<arith::SelectOp>(loc, below, elements[k], acc);
  }
  return acc;
}

/// osl.lane_pick: each list of elements gets a stack block in the entry
/// block, and each element is stored there right after its definition, so
/// it need not stay live (or be selected over) until the read: a load for
/// a uniform index, a gather for a per-lane one. Picks of the same list
/// (the same array read at two indices) share the block. A pick in a loop
/// that redefines its elements selects instead.
void keepPickedElementsInMemory(FunctionOpInterface func) {
  SmallVector<osl::LanePickOp> picks;
  func.walk([&](osl::LanePickOp op) { picks.push_back(op); });
  // Picks are met in dominance order (one block per region), so a pick
  // whose result is another's element is lowered before that one is keyed.
  std::map<std::vector<void *>, Value> blocks;
  auto ptr = LLVM::LLVMPointerType::get(func.getContext());
  for (osl::LanePickOp pick : picks) {
    OpBuilder b(pick);
    Location loc = pick.getLoc();
    if (elementsChangeEachTrip(pick)) {
      pick.replaceAllUsesWith(selectElement(b, loc, pick));
      pick.erase();
      continue;
    }
    Type element = pick.getType();
    int64_t count = int64_t(pick.getElements().size());
    auto blockType = LLVM::LLVMArrayType::get(element, count);
    std::vector<void *> key;
    for (Value e : pick.getElements())
      key.push_back(e.getAsOpaquePointer());
    Value &block = blocks[key];
    if (!block) {
      Block &entry = func.getFunctionBody().front();
      b.setInsertionPointToStart(&entry);
      Value one = b.create<LLVM::ConstantOp>(loc, b.getI64Type(), b.getI64IntegerAttr(1));
      block = b.create<LLVM::AllocaOp>(loc, ptr, blockType, one);
      for (auto [k, e] : llvm::enumerate(pick.getElements())) {
        setInsertionAfterDefinition(b, e, block.getDefiningOp());
        Value slot = b.create<LLVM::GEPOp>(loc, ptr, blockType, block,
                                           ArrayRef<LLVM::GEPArg>{0, int32_t(k)});
        b.create<LLVM::StoreOp>(loc, e, slot);
      }
      b.setInsertionPoint(pick);
    }
    Value index = pick.getIndex();
    auto lanes = dyn_cast<VectorType>(index.getType());
    if (!lanes) {
      Value slot = b.create<LLVM::GEPOp>(loc, ptr, blockType, block,
                                         ArrayRef<LLVM::GEPArg>{0, index});
      pick.replaceAllUsesWith(b.create<LLVM::LoadOp>(loc, element, slot).getResult());
      pick.erase();
      continue;
    }
    // Lane l of element index[l] is scalar index[l] * W + l of the block.
    int64_t width = lanes.getNumElements();
    Type scalar = getElementTypeOrSelf(element);
    SmallVector<int32_t> iota;
    for (int64_t l = 0; l < width; ++l)
      iota.push_back(int32_t(l));
    Value laneOffsets = b.create<arith::ConstantOp>(loc, b.getI32VectorAttr(iota));
    Value stride = b.create<arith::ConstantOp>(
        loc, DenseElementsAttr::get(lanes, b.getI32IntegerAttr(int32_t(width))));
    Value offsets = b.create<arith::AddIOp>(
        loc, b.create<arith::MulIOp>(loc, index, stride), laneOffsets);
    Value addresses = b.create<LLVM::GEPOp>(loc, LLVM::getVectorType(ptr, width), scalar,
                                            block, ValueRange{offsets});
    Value all = b.create<arith::ConstantOp>(
        loc, DenseElementsAttr::get(VectorType::get({width}, b.getI1Type()), true));
    Value zero = b.create<arith::ConstantOp>(loc, b.getZeroAttr(element));
    Value gathered = b.create<LLVM::masked_gather>(loc, element, addresses, all,
                                                   ValueRange{zero}, b.getI32IntegerAttr(4));
    pick.replaceAllUsesWith(gathered);
    pick.erase();
  }
}

void keepPickedElementsInMemory(ModuleOp module) {
  module.walk([](FunctionOpInterface func) { keepPickedElementsInMemory(func); });
}

LogicalResult convertToLLVM(ModuleOp module) {
  MLIRContext *ctx = module.getContext();
  {
    // n-D vector ops (triples of W lanes) become 1-D ones LLVM understands.
    RewritePatternSet patterns(ctx);
    vector::populateVectorBroadcastLoweringPatterns(patterns);
    vector::populateVectorMaskOpLoweringPatterns(patterns);
    vector::populateVectorShapeCastLoweringPatterns(patterns);
    // Only these rewrites: the driver's default block merging (Aggressive
    // region simplification) merged blocks of the unstructured control
    // flow whose arguments then no longer matched their branches (the
    // differential tester's seed 3619, in reference mode).
    GreedyRewriteConfig config;
    config.enableRegionSimplification = GreedySimplifyRegionLevel::Disabled;
    if (osl::hasPatternRoot(module, patterns) &&
        failed(applyPatternsAndFoldGreedily(module, std::move(patterns), config)))
      return failure();
  }
  LLVMTypeConverter converter(ctx);
  RewritePatternSet patterns(ctx);
  arith::populateArithToLLVMConversionPatterns(converter, patterns);
  populateMathToLLVMConversionPatterns(converter, patterns);
  populateVectorToLLVMConversionPatterns(converter, patterns);
  populateFuncToLLVMConversionPatterns(converter, patterns);
  cf::populateControlFlowToLLVMConversionPatterns(converter, patterns);
  LLVMConversionTarget target(*ctx);
  target.addLegalOp<ModuleOp>();
  return applyFullConversion(module, target, std::move(patterns));
}

struct LowerToLLVMPass
    : public mlir::osl::impl::LowerToLLVMBase<LowerToLLVMPass> {
  void runOnOperation() override {
    ModuleOp module = getOperation();
    keepPickedElementsInMemory(module);
    formRotates(module);
    lowerCodegenFences(module);
    divideLanesInDouble(module);
    if (failed(lowerStructuredControlFlow(module)) ||
        failed(convertToLLVM(module)))
      return signalPassFailure();
    // Casts between converted and unconverted types pair up and vanish.
    OpPassManager cleanup(ModuleOp::getOperationName());
    cleanup.addPass(createReconcileUnrealizedCastsPass());
    if (failed(runPipeline(cleanup, module)))
      return signalPassFailure();
    weighLaneGuards(module);
  }
};

} // namespace
