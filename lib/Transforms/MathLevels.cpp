//===- MathLevels.cpp - the fast and precise math levels ------------------===//
//
// polynomial: MLIR's own polynomial approximations for every op. They stay
//   in vector registers and use no tables; their error was measured, not
//   taken on trust (bench/math_chart.py, bounds in bench/MATH.md).
// fast: per op, the faster of OSL's algorithm and MLIR's approximation in
//   bench/osl-mathbench at width 16 (isOslFasterAt below).
// precise: glibc's double-precision functions, whose error is below one
//   double ULP; rounding that result to f32 is within 1 f32 ULP of the
//   correctly rounded value (it can only differ from it when the exact
//   value lies within 2^-29 ULP of a rounding midpoint). One scalar call
//   per lane costs tens of ns; it is the accurate path, not a fast one.
//   The same function runs for a scalar and for every lane of a vector, so
//   results are bit-identical at every width. A library function that is
//   several ops (sinh from exp, asin from atan2 and sqrt, log10 as a scaled
//   log) has its internal steps marked by LaneMath (kOneRoundingAttr); they
//   are computed in double with it, so it too is rounded once.
//
//===----------------------------------------------------------------------===//
#include "MathLevels.h"
#include "OslLanes/LaneMath.h"
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
  if (name == "double")
    return MathLevel::Double;
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
  case MathLevel::Double:
    return "double";
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

namespace {

Type withF64(Type t) {
  if (auto vec = dyn_cast<VectorType>(t))
    return vec.clone(Float64Type::get(t.getContext()));
  return Float64Type::get(t.getContext());
}

/// An internal arithmetic step of a library function (LaneMath.h).
bool isOneRoundingStep(Operation *op) {
  return op && op->hasAttr(mlir::osl::kOneRoundingAttr) && op->getNumResults() == 1 &&
         getElementTypeOrSelf(op->getResult(0)).isF32() &&
         isa<arith::AddFOp, arith::SubFOp, arith::MulFOp, arith::DivFOp, arith::NegFOp,
             math::SqrtOp>(op);
}

/// `op` rebuilt on f64 `operands` (same name and attributes).
Operation *cloneInDouble(OpBuilder &b, Operation *op, ValueRange operands) {
  OperationState state(op->getLoc(), op->getName());
  state.addOperands(operands);
  state.addTypes(withF64(op->getResult(0).getType()));
  state.addAttributes(op->getAttrs());
  return b.create(state);
}

/// `v` in double: the unrounded value when v is a rounded double, the
/// function's internal steps recomputed in double, else v extended (exact).
Value inDouble(OpBuilder &b, Value v) {
  Operation *def = v.getDefiningOp();
  if (auto trunc = dyn_cast_or_null<arith::TruncFOp>(def))
    if (getElementTypeOrSelf(trunc.getIn()).isF64())
      return trunc.getIn();
  if (isOneRoundingStep(def)) {
    SmallVector<Value, 2> operands;
    for (Value operand : def->getOperands())
      operands.push_back(inDouble(b, operand));
    return cloneInDouble(b, def, operands)->getResult(0);
  }
  return b.create<arith::ExtFOp>(v.getLoc(), withF64(v.getType()), v);
}

bool isRoundedDoubleOrConstant(Value v) {
  Operation *def = v.getDefiningOp();
  if (auto trunc = dyn_cast_or_null<arith::TruncFOp>(def))
    return getElementTypeOrSelf(trunc.getIn()).isF64();
  return isa_and_nonnull<arith::ConstantOp>(def);
}

} // namespace

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
  SmallVector<arith::TruncFOp> rounded;
  for (Operation *op : ops) {
    OpBuilder b(op);
    // A user's argument is the float the shader computed; the internal
    // steps of a function (asin's sqrt(1 - x^2)) are recomputed in double.
    SmallVector<Value, 2> operands;
    for (Value operand : op->getOperands())
      operands.push_back(op->hasAttr(mlir::osl::kOneRoundingAttr)
                             ? inDouble(b, operand)
                             : b.create<arith::ExtFOp>(op->getLoc(), withF64(operand.getType()),
                                                       operand)
                                   .getResult());
    Operation *w = cloneInDouble(b, op, operands);
    wide.push_back(w);
    auto narrow = b.create<arith::TruncFOp>(op->getLoc(), op->getResult(0).getType(),
                                            w->getResult(0));
    rounded.push_back(narrow);
    op->getResult(0).replaceAllUsesWith(narrow.getResult());
    op->erase();
  }
  // Steps that follow (sinh's (e - 1/e) / 2, log10's scaling, erfc's 1 -
  // erf) are done in double too when all their operands are rounded
  // doubles or constants, so the function is rounded once.
  while (!rounded.empty()) {
    arith::TruncFOp t = rounded.pop_back_val();
    SmallVector<Operation *> users(t->getUsers().begin(), t->getUsers().end());
    for (Operation *user : users) {
      if (!isOneRoundingStep(user) || !llvm::all_of(user->getOperands(), isRoundedDoubleOrConstant))
        continue;
      OpBuilder b(user);
      SmallVector<Value, 2> operands;
      for (Value operand : user->getOperands())
        operands.push_back(inDouble(b, operand));
      Operation *w = cloneInDouble(b, user, operands);
      auto narrow = b.create<arith::TruncFOp>(user->getLoc(), user->getResult(0).getType(),
                                              w->getResult(0));
      user->getResult(0).replaceAllUsesWith(narrow.getResult());
      user->erase();
      rounded.push_back(narrow);
    }
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
