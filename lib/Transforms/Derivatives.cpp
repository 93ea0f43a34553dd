//===- Derivatives.cpp - Forward-mode derivatives of lane code -------------===//
//
// Each osl.lane_deriv asks for d(value)/dx (or y, z). The value is lane code
// by now (arith, math, vector), so the derivative follows it back to the
// loads of shader globals, whose derivative rows (dPdx, dudx, ...) are in
// the globals block, and applies the chain rule forward. Only the values a
// derivative is asked of are differentiated (null means "derivative 0"), so
// a shader without Dx pays nothing. Library routines (noise, spline inversion)
// are calls here: a derivative through one calls its dual routine, or
// differentiates a copy of its code like anything else.
//
//===----------------------------------------------------------------------===//
#include "OslDialect/OslDialect.h"
#include "OslAbi/GlobalsLayout.h"
#include "OslAbi/Texture.h"
#include "OslLanes/LaneMath.h"
#include "OslLanes/LibraryFunctions.h"
#include "OslAbi/Library.h"
#include "OslTransforms/Passes.h"

#include "mlir/Dialect/Arith/IR/Arith.h"
#include "mlir/Dialect/LLVMIR/LLVMDialect.h"
#include "mlir/Dialect/Math/IR/Math.h"
#include "mlir/Dialect/SCF/IR/SCF.h"
#include "mlir/Dialect/Vector/IR/VectorOps.h"
#include "mlir/Dialect/Func/IR/FuncOps.h"
#include "mlir/IR/Builders.h"
#include "mlir/IR/IRMapping.h"

#include <limits>

namespace mlir::osl {
#define GEN_PASS_DEF_DERIVATIVES
#include "OslTransforms/Passes.h.inc"
} // namespace mlir::osl

using namespace mlir;
using namespace mlir::osl;

namespace {

/// The attribute osl-convert-to-vector puts on a load of a global's row.
constexpr const char *kGlobalRowAttr = "osl.global_row";
/// Marks the loads of derivative rows made here.
constexpr const char *kDerivativeRowAttr = "osl.derivative_row";
/// On a loop or branch rebuilt to carry derivatives: how many of its inits
/// and results it had before (the rest are derivatives).
constexpr const char *kPrimalCountsAttr = "osl.primal_counts";

struct DualRoutines;

class Differentiator {
public:
  Differentiator(StringRef axis, DualRoutines *duals = nullptr) : axis(axis), duals(duals) {}

  /// Takes `d` as the derivative of `v` (a routine's argument, or a dual
  /// call's result whose derivative along this axis an earlier one made).
  void seed(Value v, Value d) { memo[v] = d; }

  /// d(v)/d(axis), or null for 0; failure for an operation it cannot
  /// differentiate (reported at `user`).
  FailureOr<Value> derive(Value v, Operation *user) {
    if (!isFloatValue(v))
      return Value();
    if (auto it = memo.find(v); it != memo.end())
      return it->second;
    // A call of a library function differentiates as its code copied in
    // place, unless a call of its dual routine replaces it.
    if (auto call = v.getDefiningOp<func::CallOp>())
      if (func::FuncOp callee = libraryCallee(call)) {
        unsigned i = cast<OpResult>(v).getResultNumber();
        FailureOr<std::optional<Value>> dual = replaceByDual(call, callee, i, user);
        if (failed(dual))
          return failure();
        if (*dual)
          return **dual;
        // (osl-convert-to-vector builds the code of every routine a
        // derivative request depends on.)
        if (callee.isDeclaration())
          return fail(user, "a library routine whose code was not built");
        return derive(inlineCall(call, callee)[i], user);
      }
    if (auto ifOp = v.getDefiningOp<scf::IfOp>()) // memoizes the rebuilt branch
      return deriveIfResult(ifOp, cast<OpResult>(v), user);
    // Likewise a loop's result (v dies with the loop it rebuilds: a memo
    // entry for it could be found by a later value at the same address).
    if (isa_and_nonnull<scf::ForOp, scf::WhileOp>(v.getDefiningOp())) {
      unsigned index = cast<OpResult>(v).getResultNumber(); // v is gone after
      FailureOr<Operation *> rebuilt = deriveLoop(v.getDefiningOp(), user);
      if (failed(rebuilt))
        return failure();
      return memo.lookup((*rebuilt)->getResult(index));
    }
    FailureOr<Value> d = compute(v, user);
    if (succeeded(d))
      memo[v] = *d;
    return d;
  }

  /// Drops what is known of `v` before its op is erased: a value made
  /// later may reuse its storage, and must not find this entry.
  void forget(Value v) { memo.erase(v); }

  static Value zeroLike(OpBuilder &b, Location loc, Type t) {
    return b.create<arith::ConstantOp>(loc, b.getZeroAttr(t));
  }

private:
  static bool isFloatValue(Value v) {
    return isa<FloatType>(getElementTypeOrSelf(v.getType()));
  }

  FailureOr<Value> compute(Value v, Operation *user) {
    Operation *def = v.getDefiningOp();
    if (!def) {
      // A value carried around a loop: the loop carries its derivative too
      // (its region arguments move to the rebuilt loop with their blocks).
      Operation *parent = v.getParentBlock()->getParentOp();
      if (isa<scf::ForOp, scf::WhileOp>(parent)) {
        if (failed(deriveLoop(parent, user)))
          return failure();
        return memo.lookup(v);
      }
      return isa<func::FuncOp>(parent) ? FailureOr<Value>(Value()) // pointers
                                       : fail(user, parent->getName().getStringRef());
    }
    if (isa<arith::ConstantOp>(def) || def->hasAttr(kNoDerivativeAttr))
      return Value();
    // A derivative has no derivatives of its own in OSL (Dx(Dx(x)) is 0,
    // filterwidth of a filterwidth too): requests are resolved outermost
    // first, so an inner one is still an osl.lane_deriv here.
    if (isa<LaneDerivOp>(def))
      return Value();
    // A scalar spread over the lanes is a uniform value meeting a varying
    // one: it is the same at every point, so its derivative is 0 (even when
    // it is carried around a loop, e.g. an fbm's frequency).
    if (auto splat = dyn_cast<vector::BroadcastOp>(def))
      if (!isa<VectorType>(splat.getSource().getType()))
        return Value();
    if (auto load = dyn_cast<LLVM::LoadOp>(def))
      return deriveGlobal(load, user);
    auto rule = def->getAttrOfType<StringAttr>(kDualRuleAttr);
    if (rule && rule.getValue() == kDualRuleNone)
      return Value();
    if (def->getNumRegions() > 0) // loops: not yet
      return fail(user, def->getName().getStringRef());
    if (rule && rule.getValue() == kDualRuleSignFlip)
      return deriveSignFlip(def, user);
    if (rule && rule.getValue() == kDualRuleOslPow)
      return deriveOslPow(cast<arith::SelectOp>(def), user);

    // Operands' derivatives first (they are placed after their own
    // definitions, so they dominate this one's).
    SmallVector<Value> d;
    bool anyNonZero = false;
    for (Value operand : def->getOperands()) {
      FailureOr<Value> od = derive(operand, user);
      if (failed(od))
        return failure();
      d.push_back(*od);
      anyNonZero |= bool(*od);
    }
    if (!anyNonZero)
      return Value(); // a function of constants and integers
    OpBuilder b(def->getContext());
    b.setInsertionPointAfter(def);
    Location loc = def->getLoc();
    if (rule && rule.getValue() == kDualRuleValueOnly && isa<arith::SelectOp>(def))
      return d[2];
    auto dz = [&](unsigned i) { return d[i] ? d[i] : zeroLike(b, loc, def->getOperand(i).getType()); };
    Value x = def->getNumOperands() > 0 ? def->getOperand(0) : Value();

    // Linear in their float operands: the same op on the derivatives.
    if (isa<arith::AddFOp, arith::SubFOp, arith::NegFOp, vector::ExtractOp,
            vector::InsertOp, vector::FromElementsOp, vector::BroadcastOp,
            vector::ShapeCastOp, vector::SplatOp, vector::ShuffleOp, vector::TransposeOp,
            arith::SelectOp, LanePickOp>(def)) {
      IRMapping map;
      for (unsigned i = 0; i < def->getNumOperands(); ++i)
        if (isFloatValue(def->getOperand(i)))
          map.map(def->getOperand(i), dz(i));
      return b.clone(*def, map)->getResult(0);
    }
    if (isa<arith::MulFOp>(def)) // (xy)' = x'y + xy'
      return sum(b, loc, product(b, loc, d[0], def->getOperand(1)),
                 product(b, loc, x, d[1]));
    if (isa<arith::DivFOp>(def)) {
      // OSL's dual division, rounding and all: (x' - (x/y) y') times 1/y,
      // where 1/y is 0 if it is not finite.
      Value q = def->getResult(0), y = def->getOperand(1);
      Value num = d[1] ? (d[0] ? b.create<arith::SubFOp>(loc, d[0], product(b, loc, q, d[1]))
                                      .getResult()
                               : b.create<arith::NegFOp>(loc, product(b, loc, q, d[1]))
                                     .getResult())
                       : d[0];
      Value inverse = b.create<arith::DivFOp>(loc, lane::constantLike(b, loc, y, 1), y);
      Value finite = b.create<arith::CmpFOp>(
          loc, arith::CmpFPredicate::OLT, b.create<math::AbsFOp>(loc, inverse),
          lane::constantLike(b, loc, y, std::numeric_limits<double>::infinity()));
      inverse = b.create<arith::SelectOp>(loc, finite, inverse, zeroLike(b, loc, y.getType()));
      return b.create<arith::MulFOp>(loc, inverse, num).getResult();
    }
    if (isa<math::FmaOp>(def)) // (xy + z)'
      return sum(b, loc,
                 sum(b, loc, product(b, loc, d[0], def->getOperand(1)),
                     product(b, loc, x, d[1])),
                 d[2]);
    if (isa<arith::MaximumFOp, arith::MinimumFOp, arith::MaxNumFOp, arith::MinNumFOp>(def)) {
      // The derivative of whichever operand was chosen.
      Value pickFirst = b.create<arith::CmpFOp>(loc, arith::CmpFPredicate::OEQ,
                                                def->getResult(0), x);
      return b.create<arith::SelectOp>(loc, pickFirst, dz(0), dz(1)).getResult();
    }
    if (isa<arith::RemFOp>(def)) // OSL's dual fmod keeps the dividend's derivative
      return d[0];
    if (isa<math::FloorOp, math::CeilOp, math::TruncOp, math::RoundOp,
            math::RoundEvenOp, arith::BitcastOp>(def))
      return Value(); // piecewise constant
    if (isa<math::CopySignOp>(def)) { // |x| with y's sign: x' * sign(x) * sign(y)
      Value one = b.create<arith::ConstantOp>(loc, b.getFloatAttr(getElementTypeOrSelf(x.getType()), 1.0));
      if (auto vt = dyn_cast<VectorType>(x.getType()))
        one = b.create<vector::BroadcastOp>(loc, vt, one);
      Value s = b.create<math::CopySignOp>(loc, one, x);
      s = b.create<math::CopySignOp>(loc, s, def->getOperand(1));
      return product(b, loc, s, d[0]);
    }
    // f(x)' = f'(x) x'
    if (def->getNumOperands() == 1) {
      Value slope = unarySlope(b, loc, def, x);
      if (!slope)
        return fail(user, def->getName().getStringRef());
      return product(b, loc, slope, d[0]);
    }
    if (auto atan2 = dyn_cast<math::Atan2Op>(def)) { // atan2(y, x)
      // (x y' - y x') / (x^2 + y^2); OSL's rule is its negation.
      Value y = atan2.getLhs(), xx = atan2.getRhs();
      bool oslRule = rule && rule.getValue() == kDualRuleOslAtan2;
      Value den = b.create<arith::AddFOp>(loc, b.create<arith::MulFOp>(loc, xx, xx),
                                          b.create<arith::MulFOp>(loc, y, y));
      Value plus = oslRule ? product(b, loc, y, d[1]) : product(b, loc, xx, d[0]);
      Value minus = oslRule ? product(b, loc, xx, d[0]) : product(b, loc, y, d[1]);
      Value num = minus ? (plus ? b.create<arith::SubFOp>(loc, plus, minus).getResult()
                                : b.create<arith::NegFOp>(loc, minus).getResult())
                        : plus;
      return b.create<arith::DivFOp>(loc, num, den).getResult();
    }
    if (isa<math::PowFOp>(def)) { // x^y: y x^(y-1) x' + x^y ln(x) y'
      Value p = def->getResult(0), y = def->getOperand(1);
      Value t0 = d[0] ? product(b, loc, b.create<arith::DivFOp>(
                                            loc, b.create<arith::MulFOp>(loc, y, p), x),
                                d[0])
                      : Value();
      Value t1 = d[1] ? product(b, loc, b.create<arith::MulFOp>(
                                            loc, p, b.create<math::LogOp>(loc, x)),
                                d[1])
                      : Value();
      return sum(b, loc, t0, t1);
    }
    return fail(user, def->getName().getStringRef());
  }

  /// pow's select(cmpf false x y, dual, plain) (lane::pow): the value
  /// becomes OSL's dual x^(y-1) * x, and the derivative OSL's
  /// y x^(y-1) x' + x^y ln(x) y'.
  FailureOr<Value> deriveOslPow(arith::SelectOp select, Operation *user) {
    auto carrier = select.getCondition().getDefiningOp<arith::CmpFOp>();
    Value x = carrier.getLhs(), y = carrier.getRhs();
    Value dual = select.getTrueValue();
    Value below = dual.getDefiningOp()->getOperand(0);
    select.getFalseValueMutable().assign(dual);
    FailureOr<Value> dx = derive(x, user), dy = derive(y, user);
    if (failed(dx) || failed(dy))
      return failure();
    OpBuilder b(select);
    b.setInsertionPointAfter(select);
    Location loc = select.getLoc();
    Value t0 = *dx ? product(b, loc, b.create<arith::MulFOp>(loc, y, below), *dx) : Value();
    Value t1 = *dy ? product(b, loc, b.create<arith::MulFOp>(loc, select.getResult(),
                                                             b.create<math::LogOp>(loc, x)),
                             *dy)
                   : Value();
    return sum(b, loc, t0, t1);
  }

  /// A result of a uniform branch: the branch is rebuilt to also yield the
  /// derivatives of all its float results (each arm differentiates what it
  /// yields), once.
  FailureOr<Value> deriveIfResult(scf::IfOp ifOp, OpResult v, Operation *user) {
    auto thenYield = ifOp.thenYield(), elseYield = ifOp.elseYield();
    SmallVector<unsigned> floats;
    SmallVector<Value> thenD, elseD;
    // Only the branch's own results: those a rebuild for another axis added
    // are derivatives, which have none (and would lead back to the loop
    // being rebuilt, through the loop-carried derivatives they use).
    size_t primal = primalCounts(ifOp, 0).second;
    for (unsigned i = 0; i < primal; ++i) {
      if (!isFloatValue(ifOp.getResult(i)))
        continue;
      FailureOr<Value> t = derive(thenYield.getOperand(i), user);
      FailureOr<Value> e = derive(elseYield.getOperand(i), user);
      if (failed(t) || failed(e))
        return failure();
      floats.push_back(i);
      thenD.push_back(*t);
      elseD.push_back(*e);
    }
    auto fill = [&](scf::YieldOp yield, SmallVector<Value> &ds) {
      OpBuilder b(yield);
      for (auto [k, d] : llvm::enumerate(ds))
        if (!d)
          d = zeroLike(b, yield.getLoc(), ifOp.getResult(floats[k]).getType());
      yield.getResultsMutable().append(ds);
    };
    fill(thenYield, thenD);
    fill(elseYield, elseD);
    SmallVector<Type> types(ifOp.getResultTypes());
    for (unsigned i : floats)
      types.push_back(ifOp.getResult(i).getType());
    OpBuilder b(ifOp);
    auto rebuilt = b.create<scf::IfOp>(ifOp.getLoc(), types, ifOp.getCondition(),
                                       /*withElse=*/true);
    rebuilt.getThenRegion().takeBody(ifOp.getThenRegion());
    rebuilt.getElseRegion().takeBody(ifOp.getElseRegion());
    rebuilt->setAttr(kPrimalCountsAttr,
                     DenseI64ArrayAttr::get(ifOp.getContext(), {0, int64_t(primal)}));
    unsigned n = ifOp.getNumResults();
    for (unsigned i = 0; i < n; ++i) {
      Value old = ifOp.getResult(i);
      old.replaceAllUsesWith(rebuilt.getResult(i));
      if (auto it = memo.find(old); it != memo.end()) {
        memo[rebuilt.getResult(i)] = it->second;
        memo.erase(it);
      }
    }
    for (auto [k, i] : llvm::enumerate(floats))
      memo[rebuilt.getResult(i)] = rebuilt.getResult(n + k);
    Value requested = rebuilt.getResult(v.getResultNumber());
    ifOp.erase();
    return memo[requested];
  }

  /// Rebuilds `loop` (scf.for or scf.while) carrying one more value per
  /// float carried value, its derivative, and memoizes those for the
  /// region arguments and results. Every float carried value is
  /// differentiated: a loop is rebuilt once per axis.
  FailureOr<Operation *> deriveLoop(Operation *loop, Operation *user) {
    if (auto forOp = dyn_cast<scf::ForOp>(loop))
      return deriveFor(forOp, user);
    return deriveWhile(cast<scf::WhileOp>(loop), user);
  }

  /// The derivatives of `values[i]` for i in `which` (0 where null),
  /// appended to `out`; placed before `at` when they are 0.
  LogicalResult deriveAll(ValueRange values, ArrayRef<unsigned> which, Operation *at,
                          Operation *user, SmallVectorImpl<Value> &out) {
    for (unsigned i : which) {
      FailureOr<Value> d = derive(values[i], user);
      if (failed(d))
        return failure();
      Value dv = *d;
      if (!dv) {
        OpBuilder b(at);
        dv = zeroLike(b, at->getLoc(), values[i].getType());
      }
      out.push_back(dv);
    }
    return success();
  }

  /// The float ones among the first `count` of `types`.
  static SmallVector<unsigned> floatIndices(TypeRange types, size_t count) {
    SmallVector<unsigned> floats;
    for (auto [i, t] : llvm::enumerate(types.take_front(count)))
      if (isa<FloatType>(getElementTypeOrSelf(t)))
        floats.push_back(unsigned(i));
    return floats;
  }

  /// How many of a loop's carried values (inits) and results are its own,
  /// not derivatives an earlier axis added: those have no derivatives.
  static std::pair<size_t, size_t> primalCounts(Operation *loop, size_t inits) {
    if (auto counts = loop->getAttrOfType<DenseI64ArrayAttr>(kPrimalCountsAttr))
      return {size_t(counts[0]), size_t(counts[1])};
    return {inits, loop->getNumResults()};
  }

  /// `rebuilt` replaces `old`, whose first results it has, then one
  /// derivative per float result in `floats`.
  void replaceLoop(Operation *old, Operation *rebuilt, ArrayRef<unsigned> floats) {
    unsigned n = old->getNumResults();
    for (unsigned i = 0; i < n; ++i) {
      Value result = old->getResult(i);
      result.replaceAllUsesWith(rebuilt->getResult(i));
      if (auto it = memo.find(result); it != memo.end()) {
        memo[rebuilt->getResult(i)] = it->second;
        memo.erase(it);
      }
    }
    for (auto [k, i] : llvm::enumerate(floats))
      memo[rebuilt->getResult(i)] = rebuilt->getResult(n + k);
    rebuilt->setDiscardableAttrs(old->getDiscardableAttrDictionary());
    if (!rebuilt->hasAttr(kPrimalCountsAttr)) {
      size_t inits = old->getNumOperands() - (isa<scf::ForOp>(old) ? 3 : 0);
      rebuilt->setAttr(kPrimalCountsAttr,
                       DenseI64ArrayAttr::get(old->getContext(), {int64_t(inits), int64_t(n)}));
    }
    old->erase();
  }

  FailureOr<Operation *> deriveFor(scf::ForOp loop, Operation *user) {
    SmallVector<unsigned> floats =
        floatIndices(loop.getResultTypes(), primalCounts(loop, loop.getInitArgs().size()).second);
    SmallVector<Value> dInits;
    if (failed(deriveAll(loop.getInitArgs(), floats, loop, user, dInits)))
      return failure();
    // The inits as they are now: deriving them may have rebuilt the loop
    // that made one (an earlier loop's result).
    SmallVector<Value> inits(loop.getInitArgs());
    inits.append(dInits);
    OpBuilder b(loop);
    auto rebuilt = b.create<scf::ForOp>(loop.getLoc(), loop.getLowerBound(),
                                        loop.getUpperBound(), loop.getStep(), inits);
    rebuilt.getRegion().takeBody(loop.getRegion());
    Block *body = rebuilt.getBody();
    for (unsigned i : floats)
      memo[body->getArgument(1 + i)] =
          body->addArgument(loop.getResult(i).getType(), loop.getLoc());
    replaceLoop(loop, rebuilt, floats);
    auto yield = cast<scf::YieldOp>(body->getTerminator());
    SmallVector<Value> dYield;
    if (failed(deriveAll(yield.getOperands(), floats, yield, user, dYield)))
      return failure();
    yield.getResultsMutable().append(dYield);
    return rebuilt.getOperation();
  }

  FailureOr<Operation *> deriveWhile(scf::WhileOp loop, Operation *user) {
    Block &before = loop.getBefore().front(), &after = loop.getAfter().front();
    auto [ownInits, ownResults] = primalCounts(loop, loop.getInits().size());
    SmallVector<unsigned> carried = floatIndices(before.getArgumentTypes(), ownInits);
    SmallVector<unsigned> forwarded = floatIndices(loop.getResultTypes(), ownResults);
    SmallVector<Value> dInits;
    if (failed(deriveAll(loop.getInits(), carried, loop, user, dInits)))
      return failure();
    // As in deriveFor: read the inits after deriving them.
    SmallVector<Value> inits(loop.getInits());
    inits.append(dInits);
    SmallVector<Type> types(loop.getResultTypes());
    for (unsigned j : forwarded)
      types.push_back(loop.getResult(j).getType());
    OpBuilder b(loop);
    auto rebuilt = b.create<scf::WhileOp>(loop.getLoc(), types, inits);
    rebuilt.getBefore().takeBody(loop.getBefore());
    rebuilt.getAfter().takeBody(loop.getAfter());
    for (unsigned i : carried)
      memo[before.getArgument(i)] =
          before.addArgument(before.getArgument(i).getType(), loop.getLoc());
    for (unsigned j : forwarded)
      memo[after.getArgument(j)] =
          after.addArgument(after.getArgument(j).getType(), loop.getLoc());
    replaceLoop(loop, rebuilt, forwarded);
    auto condition = rebuilt.getConditionOp();
    SmallVector<Value> dForwarded;
    if (failed(deriveAll(condition.getArgs(), forwarded, condition, user, dForwarded)))
      return failure();
    condition.getArgsMutable().append(dForwarded);
    auto yield = cast<scf::YieldOp>(after.getTerminator());
    SmallVector<Value> dYield;
    if (failed(deriveAll(yield.getOperands(), carried, yield, user, dYield)))
      return failure();
    yield.getResultsMutable().append(dYield);
    return rebuilt.getOperation();
  }

  /// f'(x) for the unary math ops (result r = f(x) where that helps).
  Value unarySlope(OpBuilder &b, Location loc, Operation *def, Value x) {
    Value r = def->getResult(0);
    Type t = x.getType();
    auto cst = [&](double c) -> Value {
      Value s = b.create<arith::ConstantOp>(loc, b.getFloatAttr(getElementTypeOrSelf(t), c));
      if (auto vt = dyn_cast<VectorType>(t))
        s = b.create<vector::BroadcastOp>(loc, vt, s);
      return s;
    };
    auto mul = [&](Value a, Value c) { return b.create<arith::MulFOp>(loc, a, c).getResult(); };
    auto div = [&](Value a, Value c) { return b.create<arith::DivFOp>(loc, a, c).getResult(); };
    auto sub = [&](Value a, Value c) { return b.create<arith::SubFOp>(loc, a, c).getResult(); };
    auto add = [&](Value a, Value c) { return b.create<arith::AddFOp>(loc, a, c).getResult(); };
    if (isa<math::SinOp>(def))
      return b.create<math::CosOp>(loc, x);
    if (isa<math::CosOp>(def))
      return b.create<arith::NegFOp>(loc, b.create<math::SinOp>(loc, x));
    if (isa<math::TanOp>(def))
      return add(cst(1), mul(r, r));
    if (isa<math::AtanOp>(def))
      return div(cst(1), add(cst(1), mul(x, x)));
    if (isa<math::TanhOp>(def))
      return sub(cst(1), mul(r, r));
    if (isa<math::SinhOp>(def)) // OSL's duals: cosh and sinh of the value
      return b.create<math::CoshOp>(loc, x);
    if (isa<math::CoshOp>(def))
      return b.create<math::SinhOp>(loc, x);
    if (isa<math::AsinOp, math::AcosOp>(def)) {
      // +-1/sqrt(1 - x^2), and 0 at |x| = 1 as OSL's duals have it.
      Value inside = b.create<arith::CmpFOp>(loc, arith::CmpFPredicate::OLT,
                                             b.create<math::AbsFOp>(loc, x), cst(1));
      Value slope = div(cst(isa<math::AsinOp>(def) ? 1 : -1),
                        b.create<math::SqrtOp>(loc, sub(cst(1), mul(x, x))));
      return b.create<arith::SelectOp>(loc, inside, slope, cst(0)).getResult();
    }
    if (isa<math::ExpOp>(def))
      return r;
    if (isa<math::Exp2Op>(def))
      return mul(r, cst(0.69314718055994530942));
    if (isa<math::ExpM1Op>(def))
      return add(r, cst(1));
    if (isa<math::LogOp>(def))
      return div(cst(1), x);
    if (isa<math::Log2Op>(def))
      return div(cst(1.44269504088896340736), x);
    if (isa<math::Log10Op>(def))
      return div(cst(0.43429448190325182765), x);
    if (isa<math::SqrtOp>(def)) {
      // OSL's: no slope where sqrt is 0 or undefined (x <= 0), not inf.
      Value positive = b.create<arith::CmpFOp>(loc, arith::CmpFPredicate::OGT, x, cst(0));
      return b.create<arith::SelectOp>(loc, positive, div(cst(0.5), r), cst(0));
    }
    if (isa<math::RsqrtOp>(def))
      return mul(cst(-0.5), mul(r, div(r, x)));
    if (isa<math::AbsFOp>(def)) {
      // OSL's: x >= 0 ? x' : -x', so -0 keeps its slope (and NaN flips it).
      Value nonNegative = b.create<arith::CmpFOp>(loc, arith::CmpFPredicate::OGE, x, cst(0));
      return b.create<arith::SelectOp>(loc, nonNegative, cst(1), cst(-1));
    }
    if (isa<math::ErfOp>(def)) // 2/sqrt(pi) e^(-x^2)
      return mul(cst(1.12837916709551257390),
                 b.create<math::ExpOp>(loc, b.create<arith::NegFOp>(loc, mul(x, x))));
    if (isa<math::CbrtOp>(def)) // 1 / (3 r^2)
      return div(cst(1), mul(cst(3), mul(r, r)));
    if (isa<arith::SIToFPOp, arith::UIToFPOp>(def))
      return cst(0);
    return Value();
  }

  /// bitcast(xor(bitcast(v), s)) is v with the signs s selects flipped;
  /// its derivative is v' flipped alike.
  FailureOr<Value> deriveSignFlip(Operation *def, Operation *user) {
    auto flip = def->getOperand(0).getDefiningOp<arith::XOrIOp>();
    auto bits = flip ? flip.getLhs().getDefiningOp<arith::BitcastOp>() : nullptr;
    if (!bits)
      return fail(user, "a sign flip that is not bitcast(xor(bitcast(v), s))");
    FailureOr<Value> dv = derive(bits.getIn(), user);
    if (failed(dv) || !*dv)
      return dv;
    OpBuilder b(def->getContext());
    b.setInsertionPointAfter(def);
    Location loc = def->getLoc();
    Value dbits = b.create<arith::BitcastOp>(loc, bits.getType(), *dv);
    Value dflip = b.create<arith::XOrIOp>(loc, dbits, flip.getRhs());
    return b.create<arith::BitcastOp>(loc, def->getResult(0).getType(), dflip).getResult();
  }

  /// Row `row` of the block `load` reads from (its GEP's base), loaded as
  /// `load` is and marked as a derivative row (no derivatives of its own);
  /// null when the address is not a GEP of such a block.
  static Value loadSiblingRow(OpBuilder &b, LLVM::LoadOp load, int64_t row) {
    auto gep = load.getAddr().getDefiningOp<LLVM::GEPOp>();
    if (!gep)
      return Value();
    auto rowType = dyn_cast<VectorType>(load.getType());
    int64_t width = rowType ? rowType.getDimSize(0) : 1; // scalar: reference mode
    auto addr = b.create<LLVM::GEPOp>(load.getLoc(), gep.getType(), b.getF32Type(),
                                      gep.getBase(), ArrayRef<LLVM::GEPArg>{int32_t(row * width)});
    auto v = b.create<LLVM::LoadOp>(load.getLoc(), load.getType(), addr, 4);
    v->setAttr(kDerivativeRowAttr, b.getUnitAttr());
    return v.getResult();
  }

  /// A 2D lookup's result: d(result)/ds * ds/daxis + d(result)/dt *
  /// dt/daxis, all rows of the lookup's block (read right after the result,
  /// before a loop's next lookup writes the block again).
  FailureOr<Value> deriveTextureResult(LLVM::LoadOp load, Operation *user) {
    int64_t row = load->getAttrOfType<IntegerAttr>(kTextureResultRowAttr).getInt();
    if (axis != "x" && axis != "y")
      return Value();
    auto gep = load.getAddr().getDefiningOp<LLVM::GEPOp>();
    if (!gep)
      return fail(user, "a texture result loaded from an unknown address");
    askForSlopes(gep.getBase());
    OpBuilder b(load->getContext());
    b.setInsertionPointAfter(load);
    Location loc = load.getLoc();
    auto rowValue = [&](int64_t r) { return loadSiblingRow(b, load, r); };
    int64_t k = row - ::osl::kTextureResultRow;
    int64_t d = ::osl::kTextureDerivRow + (axis == "x" ? 0 : 2); // ds/daxis, dt/daxis
    Value ds = b.create<arith::MulFOp>(loc, rowValue(::osl::kTextureDsRow + k), rowValue(d));
    Value dt = b.create<arith::MulFOp>(loc, rowValue(::osl::kTextureDtRow + k), rowValue(d + 1));
    return b.create<arith::AddFOp>(loc, ds, dt).getResult();
  }

  /// The lookups writing the block of rows at `block` (one call site; lane
  /// groups clone it) compute the slopes of their results too.
  static void askForSlopes(Value block) {
    for (Operation *user : block.getUsers()) {
      auto call = dyn_cast<LLVM::CallOp>(user);
      if (!call || call.getCallee() != StringRef("osl_rt_texture"))
        continue;
      constexpr unsigned kFlagsOperand = ::osl::kTextureFlagsArgument;
      Value flags = call.getArgOperands()[kFlagsOperand];
      auto constant = flags.getDefiningOp<arith::ConstantIntOp>();
      if (!constant || (constant.value() & ::osl::kTextureWantsDerivatives))
        continue;
      OpBuilder b(call);
      call->setOperand(kFlagsOperand,
                       b.create<arith::ConstantIntOp>(
                           call.getLoc(), constant.value() | ::osl::kTextureWantsDerivatives, 32));
    }
  }

  /// Derivative of a load of a global's row: the matching derivative row
  /// (dPdx for P, dudy for u...); 0 for globals without derivatives.
  FailureOr<Value> deriveGlobal(LLVM::LoadOp load, Operation *user) {
    if (load->hasAttr(kDerivativeRowAttr))
      return Value(); // no second derivatives, as in OSL
    if (load->hasAttr(kTextureResultRowAttr))
      return deriveTextureResult(load, user);
    auto rowAttr = load->getAttrOfType<IntegerAttr>(kGlobalRowAttr);
    if (!rowAttr)
      return fail(user, "a load that is not a shader global");
    int64_t row = rowAttr.getInt();
    const ::osl::GlobalSlot *slot = nullptr;
    for (const ::osl::GlobalSlot &s : ::osl::kGlobalSlots)
      if (row >= s.row && row < s.row + s.rows)
        slot = &s;
    std::string name = "d" + std::string(slot->name) + "d" + axis.str();
    const ::osl::GlobalSlot *dslot = ::osl::findGlobal(name);
    if (!dslot)
      return Value();
    OpBuilder b(load);
    Value derivative = loadSiblingRow(b, load, dslot->row + (row - slot->row));
    if (!derivative)
      return fail(user, "a global loaded from an unknown address");
    return derivative;
  }

  static Value product(OpBuilder &b, Location loc, Value a, Value c) {
    if (!a || !c)
      return Value();
    return b.create<arith::MulFOp>(loc, a, c);
  }
  static Value sum(OpBuilder &b, Location loc, Value a, Value c) {
    if (!a)
      return c;
    if (!c)
      return a;
    return b.create<arith::AddFOp>(loc, a, c);
  }

  FailureOr<Value> fail(Operation *user, StringRef what) {
    user->emitError("cannot take the derivative through ") << what << " yet";
    return failure();
  }

  /// Replaces `call` by a call of its routine's dual (DualRoutines) where
  /// that applies: the x axis's derivatives of its arguments are made now,
  /// the y axis's are asked for by new requests, and the call's results
  /// (`v` among them) get their x derivatives here and their y ones
  /// seeded for the y axis. Returns the x derivative of result `index`;
  /// none where a dual does not apply.
  FailureOr<std::optional<Value>> replaceByDual(func::CallOp call, func::FuncOp callee,
                                                unsigned index, Operation *user);

public:
  StringRef axis;

private:
  DualRoutines *duals;
  DenseMap<Value, Value> memo;
};

/// A routine that stays a call (osl.keep_call: too big to inline) is
/// differentiated by a call of its dual routine: the routine's code and its
/// derivatives along x and y (tangents given for its varying float
/// arguments), built once from its recipe, the function's code
/// differentiated as it would be in place - one call instead of a copy of
/// the routine and its derivatives in the kernel (as OSL's batched library
/// calls its noise on dual numbers). It is keyed by its recipe too, so one
/// compiled before is declared, not built. Shaders asking for derivatives
/// along z (volumes) differentiate routines in place.
struct DualRoutines {
  LibraryObjectAvailable available;
  /// The y derivatives of dual calls' results, for the y axis.
  SmallVector<std::pair<Value, Value>> ySeeds;
  /// The requests of the y axis (the dual calls' y tangents join them).
  SmallVector<LaneDerivOp> *yRequests = nullptr;

  /// Whether argument `i` of `callee` has a tangent: a varying float that
  /// is not a derivative itself (a uniform one has none; in reference
  /// mode, where every value is uniform, routines are differentiated in
  /// place).
  static bool isTangentArg(func::FuncOp callee, unsigned i) {
    Type t = callee.getArgumentTypes()[i];
    if (!isa<VectorType>(t) || !isa<FloatType>(getElementTypeOrSelf(t)))
      return false;
    auto derivatives = callee->getAttrOfType<DenseI64ArrayAttr>(kDerivativeArgsAttr);
    return !derivatives || !llvm::is_contained(derivatives.asArrayRef(), int64_t(i));
  }

  /// The dual of `callee`, found or made; null (with an error at `user`)
  /// if its code cannot be differentiated.
  func::FuncOp dualOf(func::FuncOp callee, Operation *user) {
    auto recipe = callee->getAttrOfType<StringAttr>(kLibraryRecipeAttr).getValue();
    std::string dualRecipe = dualRecipeOf(recipe);
    StringRef routine = callee.getSymName()
                            .drop_front(StringRef(::osl::abi::kLibrarySymbolPrefix).size())
                            .rsplit('.')
                            .first;
    FunctionType type = callee.getFunctionType();
    SmallVector<Type> inputs(type.getInputs());
    for (int axis = 0; axis < 2; ++axis)
      for (auto [i, t] : llvm::enumerate(type.getInputs()))
        if (isTangentArg(callee, unsigned(i)))
          inputs.push_back(t);
    SmallVector<Type> results;
    for (int copy = 0; copy < 3; ++copy)
      llvm::append_range(results, type.getResults());
    auto dualType = FunctionType::get(callee.getContext(), inputs, results);
    // Its code: the routine's, then its derivatives along x and y. A
    // routine already differentiated once is found by name.
    bool failedToDerive = false;
    OpBuilder b(callee.getContext());
    func::FuncOp dual = libraryFunction(
        b, callee, (routine + "_dual").str(), dualRecipe, dualType, /*needCode=*/false,
        [&] { return available && available(dualRecipe); },
        [&](OpBuilder &b, ValueRange args) -> SmallVector<Value> {
          if (callee.isDeclaration()) {
            user->emitError("cannot take the derivative through a library routine "
                            "whose code was not built yet");
            failedToDerive = true;
            return {};
          }
          // What it returns is read from the copied return, its
          // derivatives appended there: deriving may rebuild a branch or
          // loop, which replaces the values it made.
          size_t n = type.getNumInputs();
          func::ReturnOp copied = cloneBody(b, callee, args.take_front(n));
          unsigned results = copied.getNumOperands();
          b.setInsertionPoint(copied);
          size_t next = n;
          for (StringRef axis : {"x", "y"}) {
            Differentiator diff(axis);
            for (size_t i = 0; i < n; ++i)
              if (isTangentArg(callee, unsigned(i)))
                diff.seed(args[i], args[next++]);
            for (unsigned j = 0; j < results; ++j) {
              Value r = copied.getOperand(j);
              FailureOr<Value> d = diff.derive(r, user);
              if (failed(d)) {
                failedToDerive = true;
                return {};
              }
              Value dv = *d ? *d : Differentiator::zeroLike(b, copied.getLoc(), r.getType());
              copied->insertOperands(copied.getNumOperands(), dv);
            }
          }
          SmallVector<Value> out(copied.getOperands());
          b.setInsertionPointToEnd(copied->getBlock()); // (the caller returns them)
          copied.erase();
          return out;
        });
    if (failedToDerive) {
      dual.erase();
      return {};
    }
    return dual;
  }
};

FailureOr<std::optional<Value>> Differentiator::replaceByDual(func::CallOp call,
                                                              func::FuncOp callee,
                                                              unsigned index, Operation *user) {
  // Along y only for a routine the x axis did not reach and whose code
  // was not built (its dual compiled before stands in): a call of the dual
  // for x, y and the value costs about what a copy of the routine would.
  bool alongY = axis == "y" && callee.isDeclaration();
  if (!duals || !call->hasAttr(kKeepCallAttr) || !(axis == "x" || alongY))
    return std::optional<Value>();
  func::FuncOp dual = duals->dualOf(callee, user);
  if (!dual)
    return failure();
  // The x tangents first: deriving an argument may rebuild the branch or
  // loop that made it, which replaces it (the call's operands follow).
  SmallVector<Value> tangents;
  OpBuilder b(call);
  for (auto [i, a] : llvm::enumerate(call.getOperands())) {
    if (!DualRoutines::isTangentArg(callee, unsigned(i)))
      continue;
    FailureOr<Value> d = derive(a, user);
    if (failed(d))
      return failure();
    tangents.push_back(*d);
  }
  SmallVector<Value> operands(call.getOperands()), dx, dy;
  auto tangent = tangents.begin();
  for (auto [i, a] : llvm::enumerate(call.getOperands())) {
    if (!DualRoutines::isTangentArg(callee, unsigned(i)))
      continue;
    Value d = *tangent++;
    if (!d)
      d = zeroLike(b, call.getLoc(), a.getType());
    if (alongY) {
      dx.push_back(zeroLike(b, call.getLoc(), a.getType()));
      dy.push_back(d);
      continue;
    }
    dx.push_back(d);
    auto request = b.create<LaneDerivOp>(call.getLoc(), a.getType(), a, DerivAxis::y);
    duals->yRequests->push_back(request);
    dy.push_back(request);
  }
  llvm::append_range(operands, dx);
  llvm::append_range(operands, dy);
  auto dualCall = b.create<func::CallOp>(call.getLoc(), dual, operands);
  dualCall->setAttr(kKeepCallAttr, b.getUnitAttr());
  unsigned n = call.getNumResults(), mine = alongY ? 2 * n : n;
  for (unsigned j = 0; j < n; ++j) {
    Value r = dualCall.getResult(j);
    call.getResult(j).replaceAllUsesWith(r);
    memo[r] = dualCall.getResult(mine + j);
    if (!alongY)
      duals->ySeeds.push_back({r, dualCall.getResult(2 * n + j)});
  }
  call.erase();
  return std::optional<Value>(dualCall.getResult(mine + index));
}

struct DerivativesPass : public mlir::osl::impl::DerivativesBase<DerivativesPass> {
  using DerivativesBase::DerivativesBase;
  DerivativesPass(const DerivativesOptions &options, LibraryObjectAvailable available)
      : DerivativesBase(options), available(std::move(available)) {}

  /// Which dual routines are compiled already (none without).
  LibraryObjectAvailable available;

  void runOnOperation() override {
    // Grouped by axis up front: each request is erased once resolved, so
    // none may be looked at again afterwards.
    SmallVector<LaneDerivOp> requests[3];
    getOperation().walk(
        [&](LaneDerivOp op) { requests[static_cast<int>(op.getAxis())].push_back(op); });
    DualRoutines duals{orAssumedCompiled(available, assumeCompiled), {}, &requests[1]};
    // (Only x and y: a routine a z derivative goes through is copied in place.)
    bool useDuals = dualRoutines && requests[2].empty();
    // One axis at a time: rebuilding a branch for one axis replaces values
    // another axis's memo would otherwise still hold.
    for (int k = 0; k < 3; ++k) {
      Differentiator diff(stringifyDerivAxis(static_cast<DerivAxis>(k)),
                          useDuals ? &duals : nullptr);
      if (k == 1)
        for (auto [value, d] : duals.ySeeds)
          diff.seed(value, d);
      // (Indexed: the x axis's dual calls add y requests.)
      for (size_t r = requests[k].size(); r-- > 0;) {
        LaneDerivOp op = requests[k][r];
        FailureOr<Value> d = diff.derive(op.getValue(), op);
        if (failed(d))
          return signalPassFailure();
        Value result = *d;
        if (!result) {
          OpBuilder b(op);
          result = Differentiator::zeroLike(b, op.getLoc(), op.getType());
        }
        // ...and for the later axes, the result is a derivative already. A
        // loop's or branch's result (or a loop's region argument) is marked
        // through result + -0, which folds away later: the loop itself must
        // stay differentiable.
        Operation *def = result.getDefiningOp();
        if (!def || def->getNumRegions() > 0) {
          OpBuilder b(op);
          Value negZero = lane::constant(b, op.getLoc(), result.getType(), -0.0);
          def = b.create<arith::AddFOp>(op.getLoc(), result, negZero);
          result = def->getResult(0);
        }
        def->setAttr(kNoDerivativeAttr, UnitAttr::get(def->getContext()));
        op.replaceAllUsesWith(result);
        diff.forget(op.getResult());
        op.erase();
      }
    }
  }
};

} // namespace

std::unique_ptr<Pass> mlir::osl::createDerivatives(const DerivativesOptions &options,
                                                   LibraryObjectAvailable available) {
  return std::make_unique<DerivativesPass>(options, std::move(available));
}
