//===- MathLevels.cpp - the fast and precise math levels ------------------===//
//
// fast: MLIR's own polynomial approximations. They stay in vector
//   registers and use no tables; their error was measured, not taken on
//   trust (bench/math-chart.sh, bounds in bench/MATH.md).
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
  populateExpandPowFPattern(patterns);
  patterns.add<Log10ThroughLog>(patterns.getContext());
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
    Value narrow = b.create<arith::TruncFOp>(op->getLoc(), f32Type, w->getResult(0));
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
