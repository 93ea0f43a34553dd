//===- ControlFlowOps.cpp - osl.if, osl.while and their terminators ------===//
//
// Their verifiers, canonicalization, and the control flow between their
// regions that RegionBranchOpInterface describes.
//
//===----------------------------------------------------------------------===//
#include "OslDialect/OslDialect.h"

#include "mlir/Dialect/Arith/IR/Arith.h"
#include "mlir/IR/Matchers.h"
#include "mlir/IR/TypeUtilities.h"
#include "mlir/IR/PatternMatch.h"

using namespace mlir;
using namespace mlir::osl;

//===----------------------------------------------------------------------===//
// Control flow between regions (RegionBranchOpInterface)
//===----------------------------------------------------------------------===//

// Before osl-varying-propagation a uniform value may flow into a varying
// slot: the edges compare base types.
static bool sameBaseType(Type lhs, Type rhs) {
  return getUniformType(lhs) == getUniformType(rhs);
}
bool IfOp::areTypesCompatible(Type lhs, Type rhs) { return sameBaseType(lhs, rhs); }
bool WhileOp::areTypesCompatible(Type lhs, Type rhs) { return sameBaseType(lhs, rhs); }

/// Either arm from the op; the arms to the op's results.
void IfOp::getSuccessorRegions(RegionBranchPoint point,
                               SmallVectorImpl<RegionSuccessor> &regions) {
  if (point.isParent()) {
    regions.push_back(RegionSuccessor(&getThenRegion()));
    regions.push_back(RegionSuccessor(&getElseRegion()));
    return;
  }
  regions.push_back(RegionSuccessor(getResults()));
}

/// Each point runs an arm at most once (a varying condition runs both arms
/// for the batch, each for its own points).
void IfOp::getRegionInvocationBounds(ArrayRef<Attribute>,
                                     SmallVectorImpl<InvocationBounds> &bounds) {
  bounds.assign(2, InvocationBounds(0, 1));
}

/// The op enters `cond` with its inits; `cond` goes to `do` or leaves with
/// what osl.condition forwards; `do` goes back to `cond`.
void WhileOp::getSuccessorRegions(RegionBranchPoint point,
                                  SmallVectorImpl<RegionSuccessor> &regions) {
  if (point.isParent() || point.getRegionOrNull() == &getAfter()) {
    regions.push_back(RegionSuccessor(&getBefore(), getBefore().getArguments()));
    return;
  }
  regions.push_back(RegionSuccessor(&getAfter(), getAfter().getArguments()));
  regions.push_back(RegionSuccessor(getResults()));
}

OperandRange WhileOp::getEntrySuccessorOperands(RegionBranchPoint) { return getInits(); }

MutableOperandRange ConditionOp::getMutableSuccessorOperands(RegionBranchPoint) {
  return getArgsMutable();
}

// The region verifiers run after the ops inside them have verified, so a
// malformed terminator (too few operands) is reported, not read. The types
// along the edges are RegionBranchOpInterface's to check.
LogicalResult IfOp::verifyRegions() {
  for (Region *region : {&getThenRegion(), &getElseRegion()}) {
    if (region->empty() || region->front().empty())
      return emitOpError("regions must end in osl.yield");
    if (!isa<YieldOp>(region->front().back()))
      return emitOpError("regions must end in osl.yield");
  }
  return success();
}

namespace {
/// Results an if does not need: a value both arms yield unchanged (defined
/// before the if), and i1 results that are the condition itself
/// (`true`/`false`) or its negation. The front end makes many of these from
/// jump flags. Unused results go too. What is left keeps its arms; an if with no results and
/// empty arms disappears.
struct SimplifyIfResults : public OpRewritePattern<IfOp> {
  using OpRewritePattern::OpRewritePattern;

  static std::optional<bool> constantBool(Value v) {
    if (auto c = v.getDefiningOp<arith::ConstantOp>())
      if (auto b = dyn_cast<BoolAttr>(c.getValue()))
        return b.getValue();
    if (auto c = v.getDefiningOp<arith::ConstantOp>())
      if (auto i = dyn_cast<IntegerAttr>(c.getValue()); i && i.getType().isInteger(1))
        return i.getValue().getBoolValue();
    if (auto b = v.getDefiningOp<BroadcastOp>())
      return constantBool(b.getValue());
    return std::nullopt;
  }

  LogicalResult matchAndRewrite(IfOp op, PatternRewriter &rewriter) const override {
    auto thenYield = cast<YieldOp>(op.getThenRegion().front().getTerminator());
    auto elseYield = cast<YieldOp>(op.getElseRegion().front().getTerminator());
    SmallVector<Value> replacement(op.getNumResults());
    SmallVector<bool> drop(op.getNumResults(), false);
    bool changed = false;
    for (unsigned i = 0; i < op.getNumResults(); ++i) {
      if (op.getResult(i).use_empty()) {
        drop[i] = changed = true;
        continue;
      }
      Value t = thenYield.getValues()[i], e = elseYield.getValues()[i];
      Type resultType = op.getResult(i).getType();
      if (t == e && !op->isAncestor(t.getParentBlock()->getParentOp())) {
        replacement[i] = t;
      } else if (getUniformType(resultType).isInteger(1)) {
        auto ct = constantBool(t), ce = constantBool(e);
        if (ct && ce && *ct && !*ce)
          replacement[i] = op.getCondition();
        else if (ct && ce && !*ct && *ce) {
          rewriter.setInsertionPoint(op);
          replacement[i] = rewriter.create<NotOp>(op.getLoc(), op.getCondition());
        }
      }
      // Uniformity may differ before osl-varying-propagation, which
      // recomputes it; base types must agree.
      if (replacement[i] &&
          getUniformType(replacement[i].getType()) != getUniformType(resultType))
        replacement[i] = Value();
      changed |= bool(replacement[i]);
    }
    bool emptyArms = op.getNumResults() == 0 &&
                     op.getThenRegion().front().getOperations().size() == 1 &&
                     op.getElseRegion().front().getOperations().size() == 1;
    if (emptyArms) {
      rewriter.eraseOp(op);
      return success();
    }
    if (!changed)
      return failure();
    SmallVector<Type> keptTypes;
    SmallVector<Value> thenKept, elseKept;
    for (unsigned i = 0; i < op.getNumResults(); ++i)
      if (!replacement[i] && !drop[i]) {
        keptTypes.push_back(op.getResult(i).getType());
        thenKept.push_back(thenYield.getValues()[i]);
        elseKept.push_back(elseYield.getValues()[i]);
      }
    rewriter.setInsertionPoint(op);
    auto newIf = rewriter.create<IfOp>(op.getLoc(), keptTypes, op.getCondition());
    rewriter.inlineRegionBefore(op.getThenRegion(), newIf.getThenRegion(),
                                newIf.getThenRegion().end());
    rewriter.inlineRegionBefore(op.getElseRegion(), newIf.getElseRegion(),
                                newIf.getElseRegion().end());
    rewriter.setInsertionPoint(thenYield);
    rewriter.replaceOpWithNewOp<YieldOp>(thenYield, thenKept);
    rewriter.setInsertionPoint(elseYield);
    rewriter.replaceOpWithNewOp<YieldOp>(elseYield, elseKept);
    for (unsigned i = 0, k = 0; i < op.getNumResults(); ++i)
      if (!replacement[i] && !drop[i])
        replacement[i] = newIf.getResult(k++);
    rewriter.replaceOp(op, replacement);
    return success();
  }
};
} // namespace

void IfOp::getCanonicalizationPatterns(RewritePatternSet &results, MLIRContext *context) {
  results.add<SimplifyIfResults>(context);
}

namespace {
/// Whether `v` is a constant 0 (every component of a triple), through a
/// broadcast.
bool isConstantZero(Value v) {
  if (auto broadcast = v.getDefiningOp<BroadcastOp>())
    v = broadcast.getValue();
  Attribute attr;
  if (!matchPattern(v, m_Constant(&attr)))
    return false;
  if (auto f = dyn_cast<FloatAttr>(attr))
    return f.getValue().isZero();
  if (auto dense = dyn_cast<DenseElementsAttr>(attr))
    return llvm::all_of(dense.getValues<APFloat>(), [](const APFloat &f) { return f.isZero(); });
  return false;
}

/// 0^y is 0 for any y that is not the constant 0: OSL's optimizer folds it
/// so (constfold_pow), also where y turns out 0 at run time, where OSL's
/// pow itself would give 1.
struct PowOfZeroBase : public OpRewritePattern<PowOp> {
  using OpRewritePattern::OpRewritePattern;
  LogicalResult matchAndRewrite(PowOp op, PatternRewriter &b) const override {
    if (!isConstantZero(op.getLhs()) || isConstantZero(op.getRhs()))
      return failure();
    b.replaceOp(op, buildZero(b, op.getLoc(), op.getType()));
    return success();
  }
};

/// pow(x, c) for a constant float c, rewritten as OSL's optimizer rewrites
/// it (constfold_pow): c = 0 gives 1 and 1 gives x, whatever x is; for an x
/// not constant, 2 gives x*x, 0.5 sqrt(x), -0.5 inversesqrt(x), 1/3 cbrt(x). These round apart
/// from pow's by an ulp or more, and shaders' outputs show it.
struct PowOfConstantExponent : public OpRewritePattern<PowOp> {
  using OpRewritePattern::OpRewritePattern;
  LogicalResult matchAndRewrite(PowOp op, PatternRewriter &b) const override {
    // A float exponent (with a triple base, the front end made it a splat
    // triple; a triple exponent of three values is not rewritten, as in OSL).
    Attribute exponent;
    if (!matchPattern(op.getRhs(), m_Constant(&exponent)))
      return failure();
    // (Checked first: a pattern that fails must not have changed the IR.)
    if (op.getLhs().getType() != op.getType())
      return failure();
    float c;
    if (auto f = dyn_cast<FloatAttr>(exponent))
      c = float(f.getValueAsDouble());
    else if (auto dense = dyn_cast<DenseFPElementsAttr>(exponent); dense && dense.isSplat())
      c = dense.getSplatValue<APFloat>().convertToFloat();
    else
      return failure();
    Value x = op.getLhs();
    Location loc = op.getLoc();
    Value result;
    if (c == 0.0f) {
      Type base = getUniformType(op.getType());
      Value one = b.create<arith::ConstantOp>(loc, b.getFloatAttr(mlir::getElementTypeOrSelf(base), 1.0));
      if (isa<VectorType>(base))
        one = b.create<ConstructOp>(loc, one, one, one);
      result = isVarying(op.getType()) ? b.create<BroadcastOp>(loc, op.getType(), one).getResult()
                                       : one;
    } else if (c == 1.0f) {
      result = x;
    } else if (matchPattern(x, m_Constant())) {
      // Both constant: OSL evaluates its own pow there (clamped: 1e20^2 is
      // FLT_MAX, not x*x's inf), which the kernel's pow reproduces.
      return failure();
    } else if (c == 2.0f) {
      result = b.create<MulOp>(loc, x, x);
    } else if (c == 0.5f) {
      result = b.create<SqrtOp>(loc, x);
    } else if (c == -0.5f) {
      result = b.create<InverseSqrtOp>(loc, x);
    } else if (c == 1.0f / 3.0f) {
      result = b.create<CbrtOp>(loc, x);
    }
    if (!result || result.getType() != op.getType())
      return failure();
    b.replaceOp(op, result);
    return success();
  }
};

/// x - x is 0 even when x is not a constant (an inf or a NaN at run time):
/// OSL's optimizer folds it so (constfold_sub), and shaders' outputs
/// show it.
struct SubOfItself : public OpRewritePattern<SubOp> {
  using OpRewritePattern::OpRewritePattern;
  LogicalResult matchAndRewrite(SubOp op, PatternRewriter &b) const override {
    if (op.getLhs() != op.getRhs())
      return failure();
    b.replaceOp(op, buildZero(b, op.getLoc(), op.getType()));
    return success();
  }
};

/// x * 0 and 0 * x are 0 for any x, inf and NaN included, when the 0 is a
/// constant: OSL's optimizer folds them so (constfold_mul), before it
/// evaluates a product of constants: -1 * 0 is 0, not -0 (hence the
/// benefit, above osl-fold-constants' evaluation). Not the products of a
/// library routine's code (kIeeeProductAttr).
struct MulByZero : public OpRewritePattern<MulOp> {
  MulByZero(MLIRContext *ctx) : OpRewritePattern(ctx, /*benefit=*/2) {}
  LogicalResult matchAndRewrite(MulOp op, PatternRewriter &b) const override {
    if (op->hasAttr(kIeeeProductAttr))
      return failure();
    if (!isConstantZero(op.getLhs()) && !isConstantZero(op.getRhs()))
      return failure();
    b.replaceOp(op, buildZero(b, op.getLoc(), op.getType()));
    return success();
  }
};

} // namespace

void SubOp::getCanonicalizationPatterns(RewritePatternSet &results, MLIRContext *context) {
  results.add<SubOfItself>(context);
}

void MulOp::getCanonicalizationPatterns(RewritePatternSet &results, MLIRContext *context) {
  results.add<MulByZero>(context);
}

void PowOp::getCanonicalizationPatterns(RewritePatternSet &results, MLIRContext *context) {
  results.add<PowOfZeroBase, PowOfConstantExponent>(context);
}

LogicalResult WhileOp::verifyRegions() {
  if (getBefore().empty() || getAfter().empty() || getBefore().front().empty() ||
      getAfter().front().empty())
    return emitOpError("needs a 'cond' and a 'do' region, each ending in its terminator");
  // What flows along each edge is checked by RegionBranchOpInterface's
  // verifier (getSuccessorRegions, areTypesCompatible).
  if (!isa<ConditionOp>(getBefore().front().back()))
    return emitOpError("'cond' region must end in osl.condition");
  if (!isa<YieldOp>(getAfter().front().back()))
    return emitOpError("'do' region must end in osl.yield");
  return success();
}
