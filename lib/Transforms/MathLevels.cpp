//===- MathLevels.cpp - the fast and precise math levels ------------------===//
//
// polynomial: MLIR's own polynomial approximations for every op. They stay
//   in vector registers and use no tables; their error was measured, not
//   taken on trust (bench/math-chart.sh, bounds in bench/MATH.md).
// fast: per op, the faster of OSL's algorithm and MLIR's approximation in
//   bench/osl-mathbench at width 16 (isOslFasterAt below).
// precise: glibc's double-precision functions, whose error is below one
//   double ULP; rounding that result to f32 is within 1 f32 ULP of the
//   correctly rounded value (it can only differ from it when the exact
//   value lies within 2^-29 ULP of a rounding midpoint). One scalar call
//   per lane costs tens of ns; it is the accurate path, not a fast one.
//   The same function runs for a scalar and for every lane of a vector, so
//   results are bit-identical at every width.
//
//===----------------------------------------------------------------------===//
#include "MathLevels.h"
#include "OslTransforms/Passes.h"

#include "mlir/Conversion/MathToLibm/MathToLibm.h"
#include "mlir/Dialect/Arith/IR/Arith.h"
#include "mlir/Dialect/Math/IR/Math.h"
#include "mlir/Dialect/Math/Transforms/Approximation.h"
#include "mlir/Dialect/Math/Transforms/Passes.h"
#include "mlir/Transforms/GreedyPatternRewriteDriver.h"

#include <cmath>

using namespace mlir;

std::optional<osl::MathLevel> osl::parseMathLevel(llvm::StringRef name) {
  if (name == "fast")
    return MathLevel::Fast;
  if (name == "default")
    return MathLevel::Default;
  if (name == "precise")
    return MathLevel::Precise;
  return std::nullopt;
}

const char *osl::mathLevelName(MathLevel level) {
  switch (level) {
  case MathLevel::Fast:
    return "fast";
  case MathLevel::Default:
    return "default";
  case MathLevel::Precise:
    return "precise";
  case MathLevel::Polynomial:
    return "polynomial";
  }
  return "?";
}

namespace {

/// log10(x) = log(x) / ln 10; MLIR approximates log but not log10.
struct Log10ThroughLog : public OpRewritePattern<math::Log10Op> {
  using OpRewritePattern::OpRewritePattern;
  LogicalResult matchAndRewrite(math::Log10Op op, PatternRewriter &rewriter) const override {
    Type type = op.getType();
    if (!getElementTypeOrSelf(type).isF32())
      return failure();
    Location loc = op.getLoc();
    TypedAttr scale = rewriter.getF32FloatAttr(float(1 / M_LN10));
    if (auto vec = dyn_cast<VectorType>(type))
      scale = DenseElementsAttr::get(vec, scale);
    Value log = rewriter.create<math::LogOp>(loc, op.getOperand());
    Value c = rewriter.create<arith::ConstantOp>(loc, scale);
    rewriter.replaceOpWithNewOp<arith::MulFOp>(op, log, c);
    return success();
  }
};

/// Shape-matched f32 constant.
Value f32Constant(OpBuilder &b, Location loc, Type like, float v) {
  TypedAttr attr = b.getF32FloatAttr(v);
  if (auto vec = dyn_cast<VectorType>(like))
    attr = DenseElementsAttr::get(vec, attr);
  return b.create<arith::ConstantOp>(loc, attr);
}

/// pow(x, y) = exp(y log x) through MLIR's exp and log approximations. The
/// base is never negative here (lane::pow passes |x| and applies OSL's sign
/// rules). MLIR's own powf expansion gave NaN for bases and exponents near
/// 0 (pow(1e-30, 1e-30)), where OSL gives 1.
struct PowThroughExpLog : public OpRewritePattern<math::PowFOp> {
  using OpRewritePattern::OpRewritePattern;
  LogicalResult matchAndRewrite(math::PowFOp op, PatternRewriter &rewriter) const override {
    if (!getElementTypeOrSelf(op.getType()).isF32())
      return failure();
    Location loc = op.getLoc();
    Value log = rewriter.create<math::LogOp>(loc, op.getLhs());
    Value product = rewriter.create<arith::MulFOp>(loc, op.getRhs(), log);
    rewriter.replaceOpWithNewOp<math::ExpOp>(op, product);
    return success();
  }
};

} // namespace

/// Measured (bench/MATH.md, 16 lanes): OSL's atan 0.15 ns/point vs MLIR's
/// 0.23, atan2 0.25 vs 0.64, pow 0.65 vs 0.77; MLIR's tan (sin/cos) breaks
/// down to +-inf or NaN at large arguments where OSL's does not. MLIR's
/// sin, cos, exp and log are as fast or faster and more accurate.
bool osl::isOslFasterAt(Operation *op) {
  return isa<math::TanOp, math::AtanOp, math::Atan2Op, math::PowFOp>(op);
}

/// Where MLIR's approximations break down, the fast level applies OSL's
/// rule: sin and cos of arguments whose reduction fails (|x| ~ 1e30 gives
/// +-inf) are 0 like OSL's out-of-[-1, 1] results, and atan2 of two
/// infinities is the angle of the signs' diagonal (MLIR's gives NaN).
void osl::guardFastMath(ModuleOp module, bool oslAlgorithmsWhereFaster) {
  SmallVector<Operation *> ops;
  module.walk([&](Operation *op) {
    if (oslAlgorithmsWhereFaster && isOslFasterAt(op))
      return; // OSL's algorithm has its own rules
    if (isa<math::SinOp, math::CosOp, math::Atan2Op>(op) &&
        getElementTypeOrSelf(op->getResult(0)).isF32())
      ops.push_back(op);
  });
  for (Operation *op : ops) {
    Location loc = op->getLoc();
    Type type = op->getResult(0).getType();
    OpBuilder b(op);
    if (auto atan2 = dyn_cast<math::Atan2Op>(op)) {
      Value inf = f32Constant(b, loc, type, INFINITY);
      Value one = f32Constant(b, loc, type, 1.0f);
      auto isInf = [&](Value v) {
        return b.create<arith::CmpFOp>(loc, arith::CmpFPredicate::OEQ,
                                       b.create<math::AbsFOp>(loc, v), inf);
      };
      Value both = b.create<arith::AndIOp>(loc, isInf(atan2.getLhs()), isInf(atan2.getRhs()));
      auto unit = [&](Value v) {
        return b.create<arith::SelectOp>(loc, both, b.create<math::CopySignOp>(loc, one, v), v);
      };
      atan2.getLhsMutable().assign(unit(atan2.getLhs()));
      atan2.getRhsMutable().assign(unit(atan2.getRhs()));
      continue;
    }
    b.setInsertionPointAfter(op);
    Value r = op->getResult(0);
    Value magnitude = b.create<math::AbsFOp>(loc, r);
    Value outside = b.create<arith::CmpFOp>(loc, arith::CmpFPredicate::OGT, magnitude,
                                            f32Constant(b, loc, type, 1.0f));
    Value guarded = b.create<arith::SelectOp>(loc, outside, f32Constant(b, loc, type, 0.0f), r);
    r.replaceUsesWithIf(guarded, [&](OpOperand &use) {
      return use.getOwner() != magnitude.getDefiningOp() &&
             use.getOwner() != guarded.getDefiningOp();
    });
  }
}

namespace {

/// The ops the precise level evaluates in f64. The others (sqrt, floor,
/// abs, copysign, fma...) are exact or correctly rounded in f32 already.
bool isTranscendental(Operation *op) {
  return isa<math::SinOp, math::CosOp, math::TanOp, math::AsinOp, math::AcosOp,
             math::AtanOp, math::Atan2Op, math::SinhOp, math::CoshOp, math::TanhOp,
             math::AsinhOp, math::AcoshOp, math::AtanhOp, math::ExpOp, math::Exp2Op,
             math::ExpM1Op, math::LogOp, math::Log2Op, math::Log10Op, math::Log1pOp,
             math::PowFOp, math::ErfOp, math::CbrtOp>(op);
}

} // namespace

void osl::populateFastMathPatterns(RewritePatternSet &patterns) {
  populateExpandTanPattern(patterns);
  populateExpandExp2FPattern(patterns);
  patterns.add<Log10ThroughLog, PowThroughExpLog>(patterns.getContext());
  populateMathPolynomialApproximationPatterns(patterns);
}

LogicalResult osl::computeInDoubleWithLibm(ModuleOp module) {
  SmallVector<Operation *> ops;
  SmallVector<Operation *> wide;
  module.walk([&](Operation *op) {
    if (!isTranscendental(op) || op->getNumResults() != 1)
      return;
    Type element = getElementTypeOrSelf(op->getResult(0));
    if (element.isF32())
      ops.push_back(op);
    else if (element.isF64()) // already double (math kernels' reference)
      wide.push_back(op);
  });
  for (Operation *op : ops) {
    OpBuilder b(op);
    Type f32Type = op->getResult(0).getType();
    Type f64Type = f32Type;
    if (auto vec = dyn_cast<VectorType>(f32Type))
      f64Type = vec.clone(b.getF64Type());
    else
      f64Type = b.getF64Type();
    OperationState state(op->getLoc(), op->getName());
    for (Value operand : op->getOperands())
      state.addOperands(b.create<arith::ExtFOp>(op->getLoc(), f64Type, operand).getResult());
    state.addTypes(f64Type);
    state.addAttributes(op->getAttrs());
    Operation *w = b.create(state);
    wide.push_back(w);
    Value result = w->getResult(0);
    // A result only scaled by a constant (log10 is log(x) * (1/ln 10)) is
    // scaled in double, so the function is rounded once.
    Operation *user = op->getResult(0).hasOneUse() ? *op->getResult(0).getUsers().begin()
                                                   : nullptr;
    if (auto mul = dyn_cast_or_null<arith::MulFOp>(user)) {
      Value other = mul.getLhs() == op->getResult(0) ? mul.getRhs() : mul.getLhs();
      if (other.getDefiningOp<arith::ConstantOp>()) {
        b.setInsertionPoint(mul);
        Value scale = b.create<arith::ExtFOp>(op->getLoc(), f64Type, other);
        Value scaled = b.create<arith::MulFOp>(op->getLoc(), result, scale);
        mul.getResult().replaceAllUsesWith(
            b.create<arith::TruncFOp>(op->getLoc(), f32Type, scaled).getResult());
        mul.erase();
        op->erase();
        continue;
      }
    }
    Value narrow = b.create<arith::TruncFOp>(op->getLoc(), f32Type, result);
    op->getResult(0).replaceAllUsesWith(narrow);
    op->erase();
  }
  if (wide.empty())
    return success();
  // Only the widened ops (and the scalar ops their unrolling creates) become
  // calls: floor, sqrt... elsewhere must stay single instructions.
  RewritePatternSet patterns(module.getContext());
  populateMathToLibmConversionPatterns(patterns);
  GreedyRewriteConfig config;
  config.strictMode = GreedyRewriteStrictness::ExistingAndNewOps;
  return applyOpPatternsAndFold(wide, std::move(patterns), config);
}
