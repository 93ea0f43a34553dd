//===- NoiseCalls.cpp - Noise as calls of library functions ----------------===//
//
// Each noise becomes a call of a private function per recipe: what its code
// is built from (kind, periodicity, width, the osl types of its operands and
// result, the Gabor mode). Two calls of one recipe share the function, and
// its compiled object is keyed by the recipe (OslCompiler/LibraryObjects.h):
// where the object is at hand and nothing needs the code (no derivative is
// taken through the noise, no call site would inline it), the function is a
// declaration and its code is never built - a shader calling 48 noise
// routines compiled before builds none of them.
//
//===----------------------------------------------------------------------===//
#include "OslToVector.h"

#include "OslLanes/GaborBuilder.h"
#include "OslLanes/LibraryRegion.h"
#include "OslLanes/NoiseBuilder.h"
#include "mlir/IR/Matchers.h"
#include "mlir/Interfaces/LoopLikeInterface.h"

using namespace mlir;
using namespace mlir::osl;
using namespace mlir::osl::lowering;

namespace {

/// What a noise routine's code is built from, besides the width.
struct NoiseRecipe {
  NoiseKind kind;
  bool periodic;
  Type resultType;               ///< osl type
  SmallVector<Type> coordTypes;  ///< osl types, made varying for a varying noise
  SmallVector<Type> derivTypes;  ///< Gabor's dP/dx and dP/dy (osl types)
  std::optional<int32_t> gaborMode; ///< a constant "anisotropic" picks the code
  bool gaborFilterOff = false;      ///< a constant do_filter of 0

  bool gabor() const { return kind == NoiseKind::gabor; }

  std::string name() const {
    std::string routine = ("noise_" + stringifyNoiseKind(kind)).str();
    return periodic ? routine + "_periodic" : routine;
  }

  std::string text(int64_t width) const {
    std::string s;
    llvm::raw_string_ostream os(s);
    os << "noise " << stringifyNoiseKind(kind) << (periodic ? " periodic" : "") << " width "
       << width << " (";
    llvm::interleaveComma(coordTypes, os);
    os << ") -> " << resultType;
    if (gabor()) {
      os << " derivs (";
      llvm::interleaveComma(derivTypes, os);
      os << ") anisotropic ";
      if (gaborMode)
        os << *gaborMode;
      else
        os << "operand";
      os << " filter " << (gaborFilterOff ? "off" : "operand");
    }
    return s;
  }
};

/// The options of a Gabor noise as scalars (osl-lane-group-filter made them
/// uniform), OSL's default for each one the call leaves out, in the order
/// the routine takes them.
SmallVector<Value> gaborOptionValues(NoiseOp op, NoiseOp::Adaptor adaptor, Components &lanes) {
  auto scalar = [&](Value converted, Value original) {
    return converted ? lanes.unpack(converted, original.getType(), false)[0] : Value();
  };
  GaborOptions options;
  options.anisotropic = scalar(adaptor.getAnisotropic(), op.getAnisotropic());
  options.bandwidth = scalar(adaptor.getBandwidth(), op.getBandwidth());
  options.impulses = scalar(adaptor.getImpulses(), op.getImpulses());
  options.doFilter = scalar(adaptor.getDoFilter(), op.getDoFilter());
  if (op.getDirection()) {
    SmallVector<Value> dir = lanes.unpack(adaptor.getDirection(), op.getDirection().getType(), false);
    options.direction = {dir[0], dir[1], dir[2]};
  }
  options = withGaborDefaults(lanes.b, lanes.loc, options);
  return {options.anisotropic, options.direction[0], options.direction[1],
          options.direction[2], options.bandwidth, options.impulses, options.doFilter};
}

/// Gabor noise: the point (and its derivatives and period) made 3D.
Value buildGabor(const NoiseRecipe &recipe, ValueRange coords, ValueRange derivs,
                 ValueRange optionValues, Components &lanes, Type resultType) {
  OpBuilder &b = lanes.b;
  Location loc = lanes.loc;
  bool varying = isVarying(recipe.resultType);
  GaborOptions options;
  options.anisotropic = recipe.gaborMode
                            ? b.create<arith::ConstantOp>(loc, b.getI32IntegerAttr(*recipe.gaborMode))
                            : optionValues[0];
  options.direction = {optionValues[1], optionValues[2], optionValues[3]};
  options.bandwidth = optionValues[4];
  options.impulses = optionValues[5];
  options.doFilter = recipe.gaborFilterOff
                         ? b.create<arith::ConstantOp>(loc, b.getI32IntegerAttr(0))
                         : optionValues[6];
  SmallVector<Value> flat;
  for (auto [value, type] : llvm::zip(coords, recipe.coordTypes))
    llvm::append_range(flat, lanes.unpack(value, type, varying));
  // A triple point has 3 values, a float domain 1 or 2 (a 4th coordinate
  // and its period are ignored, as OSL does).
  size_t ncoords = recipe.periodic ? coords.size() / 2 : coords.size();
  bool triple = isTriple(getUniformType(recipe.coordTypes[0]));
  size_t pointSize = triple ? 3 : ncoords;
  size_t domainSize = triple ? (ncoords == 2 ? 4 : 3) : ncoords;
  Type laneType = flat[0].getType();
  auto point3 = [&](ArrayRef<Value> v) {
    std::array<Value, 3> p;
    for (size_t k = 0; k < 3; ++k)
      p[k] = k < v.size() ? v[k] : lane::constant(b, loc, laneType, 0.0);
    return p;
  };
  ArrayRef<Value> all(flat);
  GaborPoint point;
  point.p = point3(all.take_front(pointSize));
  if (recipe.periodic)
    point.period = point3(all.drop_front(domainSize).take_front(pointSize));
  if (!derivs.empty()) {
    SmallVector<Value> d;
    for (auto [value, type] : llvm::zip(derivs, recipe.derivTypes))
      llvm::append_range(d, lanes.unpack(value, type, varying));
    point.dPdx = point3(ArrayRef<Value>(d).take_front(pointSize));
    point.dPdy = point3(ArrayRef<Value>(d).drop_front(pointSize));
  }
  if (isTriple(getUniformType(recipe.resultType)))
    return lanes.pack(buildGaborTriple(b, loc, point, options), resultType);
  return buildGaborFloat(b, loc, point, options);
}

/// The noise of a non-Gabor kind.
Value buildNoise(const NoiseRecipe &recipe, ValueRange coordValues, Components &lanes,
                 Type resultType) {
  OpBuilder &b = lanes.b;
  Location loc = lanes.loc;
  SmallVector<Value> coords;
  for (auto [value, type] : llvm::zip(coordValues, recipe.coordTypes))
    llvm::append_range(coords, lanes.unpack(value, type, isVarying(recipe.resultType)));
  bool triple = isTriple(getUniformType(recipe.resultType));
  if (recipe.periodic) {
    ArrayRef<Value> all(coords);
    ArrayRef<Value> points = all.take_front(all.size() / 2);
    ArrayRef<Value> periods = all.drop_front(all.size() / 2);
    if (!triple)
      return buildPeriodicNoiseFloat(b, loc, recipe.kind, points, periods);
    return lanes.pack(buildPeriodicNoiseTriple(b, loc, recipe.kind, points, periods),
                      resultType);
  }
  if (triple)
    return lanes.pack(buildNoiseTriple(b, loc, recipe.kind, coords), resultType);
  return buildNoiseFloat(b, loc, recipe.kind, coords);
}

/// Whether a call at `op` would be inlined for its site: it passes a
/// constant (its copy folds) or runs in a loop (the spills around a call
/// repeat), as osl-outline-library judges; cell and hash noise are small
/// enough that it may inline them anywhere.
bool siteMayInline(Operation *op, const NoiseRecipe &recipe, ValueRange coords) {
  if (recipe.gabor()) // a loop itself: never inlined
    return false;
  if (recipe.kind == NoiseKind::cell || recipe.kind == NoiseKind::hash)
    return true;
  return llvm::any_of(coords, isConstantOperand) ||
         op->getParentOfType<LoopLikeOpInterface>() || op->getParentOfType<WhileOp>();
}

struct NoiseLowering : public OslPattern<NoiseOp> {
  NoiseLowering(const VaryingTypeConverter &converter, MLIRContext *ctx,
                const LibraryRoutineNeeds &needs)
      : OslPattern(converter, ctx), needs(needs) {}
  const LibraryRoutineNeeds &needs;

  LogicalResult matchAndRewrite(NoiseOp op, OpAdaptor adaptor,
                                ConversionPatternRewriter &rewriter) const override {
    NoiseKind kind = op.getKind();
    if (kind == NoiseKind::gabor)
      for (Value option : op.getOptions())
        if (isVarying(option.getType()))
          return op.emitError("gabor options chosen per point must be split into lane "
                              "groups first (osl-lane-group-filter)");
    if (op.getPeriodic() && (kind == NoiseKind::simplex || kind == NoiseKind::usimplex))
      return op.emitError("periodic '") << stringifyNoiseKind(kind) << "' noise is not defined";
    Location loc = op.getLoc();
    Components outer{rewriter, loc, width};
    NoiseRecipe recipe{kind, op.getPeriodic(), op.getType(), {}, {}, std::nullopt, false};
    // A varying noise's uniform coordinates are broadcast before the call,
    // which broadcast them first thing anyway: its function then takes
    // varying operands only, as the prebuilt library's do.
    SmallVector<Value> coords;
    for (auto [value, type] : llvm::zip(adaptor.getCoords(), op.getCoords().getTypes())) {
      if (isVarying(op.getType()) && !isVarying(type)) {
        Type varyingType = withUniformity(type, true);
        coords.push_back(outer.pack(outer.unpack(value, type, true), convert(varyingType)));
        recipe.coordTypes.push_back(varyingType);
      } else {
        coords.push_back(value);
        recipe.coordTypes.push_back(type);
      }
    }
    SmallVector<Value> derivs, options;
    if (recipe.gabor() && isTriple(getUniformType(recipe.coordTypes[0])) &&
        coords.size() == (recipe.periodic ? 4u : 2u)) {
      // OSL's Gabor noise ignores a 4th coordinate and its period: the
      // routine of a 3D point serves.
      auto drop = [&](size_t i) {
        coords.erase(coords.begin() + i);
        recipe.coordTypes.erase(recipe.coordTypes.begin() + i);
      };
      if (recipe.periodic)
        drop(3); // (point, time, point period, time period)
      drop(1);
    }
    if (recipe.gabor()) {
      derivs.assign(adaptor.getDerivs().begin(), adaptor.getDerivs().end());
      for (Type t : op.getDerivs().getTypes())
        recipe.derivTypes.push_back(t);
      options = gaborOptionValues(op, adaptor, outer);
      APInt known;
      if (matchPattern(options[0], m_ConstantInt(&known)))
        recipe.gaborMode = int32_t(known.getSExtValue());
      recipe.gaborFilterOff = matchPattern(options[6], m_ConstantInt(&known)) && known.isZero();
    }
    SmallVector<Value> operands(coords);
    llvm::append_range(operands, derivs);
    llvm::append_range(operands, options);
    Type resultType = convert(op.getType());
    auto type = FunctionType::get(getContext(), ValueRange(operands).getTypes(), resultType);
    std::string text = recipe.text(width);
    bool keepCall = !siteMayInline(op, recipe, coords);
    // A routine a derivative goes through is differentiated by its dual
    // routine (osl-derivatives), built from its code unless compiled
    // before; along z, by its code copied in place.
    bool needCode = !keepCall || !needs.available ||
                    (needs.derivativeOf.contains(op) &&
                     (needs.inPlaceDerivatives || !needs.available(dualRecipeOf(text))));
    size_t ncoords = coords.size(), nderivs = derivs.size();
    func::FuncOp func = libraryFunction(
        rewriter, op, recipe.name(), text, type, needCode,
        [&] { return needs.available(text); },
        [&](OpBuilder &b, ValueRange args) -> SmallVector<Value> {
          Components inner{b, loc, width};
          if (recipe.gabor())
            return {buildGabor(recipe, args.take_front(ncoords),
                               args.drop_front(ncoords).take_front(nderivs),
                               args.drop_front(ncoords + nderivs), inner, resultType)};
          return {buildNoise(recipe, args, inner, resultType)};
        });
    if (!derivs.empty() && !func->hasAttr(kDerivativeArgsAttr)) {
      SmallVector<int64_t> indices;
      for (size_t i = 0; i < nderivs; ++i)
        indices.push_back(int64_t(ncoords + i));
      func->setAttr(kDerivativeArgsAttr, rewriter.getDenseI64ArrayAttr(indices));
    }
    auto call = rewriter.create<func::CallOp>(loc, func, operands);
    if (keepCall)
      call->setAttr(kKeepCallAttr, rewriter.getUnitAttr());
    rewriter.replaceOp(op, call.getResults());
    return success();
  }
};

/// Adds to `slice` every op whose result `v` may depend on (conservatively:
/// all code in a loop or branch it comes from).
void addBackwardSlice(Value v, DenseSet<Operation *> &slice) {
  SmallVector<Value> work{v};
  auto addOp = [&](Operation *op) {
    if (!slice.insert(op).second)
      return;
    llvm::append_range(work, op->getOperands());
    op->walk([&](Operation *inner) {
      if (inner != op && slice.insert(inner).second)
        llvm::append_range(work, inner->getOperands());
    });
  };
  while (!work.empty()) {
    Value value = work.pop_back_val();
    if (Operation *def = value.getDefiningOp())
      addOp(def);
    else if (Operation *parent = value.getParentBlock()->getParentOp();
             parent && !isa<func::FuncOp>(parent))
      addOp(parent);
  }
}

} // namespace

LibraryRoutineNeeds::LibraryRoutineNeeds(Operation *root, LibraryObjectAvailable available,
                                         bool referenceMode)
    : inPlaceDerivatives(referenceMode), available(std::move(available)) {
  // osl-derivatives differentiates through a routine's code: a noise any
  // derivative request depends on keeps its code.
  DenseSet<Operation *> slice;
  root->walk([&](DerivOp d) {
    addBackwardSlice(d.getValue(), slice);
    inPlaceDerivatives |= d.getAxis() == DerivAxis::z;
  });
  for (Operation *op : slice)
    if (isa<NoiseOp>(op))
      derivativeOf.insert(op);
}

void mlir::osl::lowering::populateNoisePatterns(const VaryingTypeConverter &converter,
                                                RewritePatternSet &patterns,
                                                const LibraryRoutineNeeds &needs) {
  patterns.add<NoiseLowering>(converter, patterns.getContext(), needs);
}
