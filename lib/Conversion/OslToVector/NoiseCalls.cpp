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
#include "OslLanes/LibraryFunctions.h"
#include "OslLanes/NoiseBuilder.h"
#include "mlir/Dialect/SCF/IR/SCF.h"
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

/// Gabor's options in the order its routine takes them.
SmallVector<Value> gaborOptionList(const GaborOptions &options) {
  return {options.anisotropic, options.direction[0], options.direction[1],
          options.direction[2], options.bandwidth, options.impulses, options.doFilter};
}

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
  return gaborOptionList(withGaborDefaults(lanes.b, lanes.loc, options));
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
/// constant point (its copy folds) or runs in a loop (the spills around a
/// call repeat), as osl-inline-library judges; cell and hash noise are
/// small enough that it may inline them anywhere. A constant period folds
/// only the lattice's remainders, which the routine computes in a few
/// vector ops (osl-lower-to-llvm divides its lanes in double precision):
/// measured on the testsuite's pnoise, copies compiled in about twice the
/// time of calls and shaded slower (12.4 against 7.5 ns per point).
bool siteMayInline(Operation *op, const NoiseRecipe &recipe, ValueRange coords) {
  if (recipe.gabor()) // a loop itself: never inlined
    return false;
  if (recipe.kind == NoiseKind::cell || recipe.kind == NoiseKind::hash)
    return true;
  ValueRange points = recipe.periodic ? coords.take_front(coords.size() / 2) : coords;
  return llvm::any_of(points, isConstantOperand) ||
         op->getParentOfType<LoopLikeOpInterface>() || op->getParentOfType<WhileOp>();
}

/// One call of a noise routine: its recipe and operands (converted).
struct NoiseCall {
  NoiseRecipe recipe;
  SmallVector<Value> coords, derivs, options;
};

/// A call of `kind` at `coords` (converted; of osl types `coordTypes`)
/// for a noise of osl type `resultType`: a varying noise's uniform
/// coordinates are broadcast before the call, which broadcast them first
/// thing anyway, so its function takes varying operands only, as the
/// prebuilt library's do. Gabor's derivs and options are added by
/// addGaborOperands.
NoiseCall noiseCall(NoiseKind kind, bool periodic, Type resultType, ValueRange coords,
                    TypeRange coordTypes, Components &lanes, const TypeConverter &converter) {
  NoiseCall call{{kind, periodic, resultType, {}, {}, std::nullopt, false}, {}, {}, {}};
  for (auto [value, type] : llvm::zip(coords, coordTypes)) {
    if (isVarying(resultType) && !isVarying(type)) {
      Type varyingType = withUniformity(type, true);
      call.coords.push_back(
          lanes.pack(lanes.unpack(value, type, true), converter.convertType(varyingType)));
      call.recipe.coordTypes.push_back(varyingType);
    } else {
      call.coords.push_back(value);
      call.recipe.coordTypes.push_back(type);
    }
  }
  return call;
}

/// A Gabor call's filter derivatives (converted, of osl types `derivTypes`)
/// and options (gaborOptionList's order); a 4th coordinate and its period
/// dropped.
void addGaborOperands(NoiseCall &call, ValueRange derivs, TypeRange derivTypes,
                      SmallVector<Value> options) {
  NoiseRecipe &recipe = call.recipe;
  if (isTriple(getUniformType(recipe.coordTypes[0])) &&
      call.coords.size() == (recipe.periodic ? 4u : 2u)) {
    // OSL's Gabor noise ignores a 4th coordinate and its period: the
    // routine of a 3D point serves.
    auto drop = [&](size_t i) {
      call.coords.erase(call.coords.begin() + i);
      recipe.coordTypes.erase(recipe.coordTypes.begin() + i);
    };
    if (recipe.periodic)
      drop(3); // (point, time, point period, time period)
    drop(1);
  }
  call.derivs.assign(derivs.begin(), derivs.end());
  recipe.derivTypes.assign(derivTypes.begin(), derivTypes.end());
  APInt known;
  if (matchPattern(options[0], m_ConstantInt(&known)))
    recipe.gaborMode = int32_t(known.getSExtValue());
  recipe.gaborFilterOff = matchPattern(options[6], m_ConstantInt(&known)) && known.isZero();
  call.options = std::move(options);
}

/// Emits `call` at `b` as a call of its recipe's library function (made in
/// `anchor`'s module), of converted type `resultType`. `keepCall`: it
/// stays a call (osl.keep_call); `differentiated`: a derivative goes
/// through it.
func::CallOp emitNoiseCall(OpBuilder &b, Location loc, Operation *anchor, const NoiseCall &call,
                           Type resultType, int64_t width, const LibraryRoutineNeeds &needs,
                           bool keepCall, bool differentiated) {
  const NoiseRecipe &recipe = call.recipe;
  SmallVector<Value> operands(call.coords);
  llvm::append_range(operands, call.derivs);
  llvm::append_range(operands, call.options);
  auto type = FunctionType::get(b.getContext(), ValueRange(operands).getTypes(), resultType);
  std::string text = recipe.text(width);
  bool needCode = !keepCall || needs.needCode(text, differentiated);
  size_t ncoords = call.coords.size(), nderivs = call.derivs.size();
  func::FuncOp func = libraryFunction(
      b, anchor, recipe.name(), text, type, needCode, [&] { return needs.available(text); },
      [&](OpBuilder &inner, ValueRange args) -> SmallVector<Value> {
        Components lanes{inner, loc, width};
        if (recipe.gabor())
          return {buildGabor(recipe, args.take_front(ncoords),
                             args.drop_front(ncoords).take_front(nderivs),
                             args.drop_front(ncoords + nderivs), lanes, resultType)};
        return {buildNoise(recipe, args, lanes, resultType)};
      });
  if (nderivs && !func->hasAttr(kDerivativeArgsAttr)) {
    SmallVector<int64_t> indices;
    for (size_t i = 0; i < nderivs; ++i)
      indices.push_back(int64_t(ncoords + i));
    func->setAttr(kDerivativeArgsAttr, b.getDenseI64ArrayAttr(indices));
  }
  auto callOp = b.create<func::CallOp>(loc, func, operands);
  if (keepCall)
    callOp->setAttr(kKeepCallAttr, b.getUnitAttr());
  return callOp;
}

/// A pattern of a noise op, which knows which routines need their code.
template <typename OpTy> struct NoisePattern : public OslPattern<OpTy> {
  NoisePattern(const VaryingTypeConverter &converter, MLIRContext *ctx,
               const LibraryRoutineNeeds &needs)
      : OslPattern<OpTy>(converter, ctx), needs(needs) {}
  const LibraryRoutineNeeds &needs;
};

struct NoiseLowering : public NoisePattern<NoiseOp> {
  using NoisePattern::NoisePattern;

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
    NoiseCall call = noiseCall(kind, op.getPeriodic(), op.getType(), adaptor.getCoords(),
                               op.getCoords().getTypes(), outer, *getTypeConverter());
    if (call.recipe.gabor())
      addGaborOperands(call, adaptor.getDerivs(), op.getDerivs().getTypes(),
                       gaborOptionValues(op, adaptor, outer));
    bool keepCall = !siteMayInline(op, call.recipe, call.coords);
    auto callOp = emitNoiseCall(rewriter, loc, op, call, convert(op.getType()), width, needs,
                                keepCall, needs.derivativeOf.contains(op));
    rewriter.replaceOp(op, callOp.getResults());
    return success();
  }
};

/// The kinds a noise_by_kind chooses among, in the order its code tests
/// them: all of them, so that one routine per signature serves every shader
/// (and the prebuilt library has it), whichever names the shader uses.
SmallVector<NoiseKind> kindsByKind(bool periodic) {
  SmallVector<NoiseKind> kinds{NoiseKind::perlin, NoiseKind::uperlin, NoiseKind::cell,
                               NoiseKind::hash, NoiseKind::gabor};
  if (!periodic)
    llvm::append_range(kinds, ArrayRef<NoiseKind>{NoiseKind::simplex, NoiseKind::usimplex});
  return kinds;
}

/// The noise of each lane's kind (`kind`: an i32, or W lanes of one): for
/// each kind some lane has, a call of its routine, its lanes selected. A
/// lane of no kind is 0.
struct NoiseByKindBody {
  bool periodic;
  Type oslResultType;
  SmallVector<Type> coordTypes; ///< the calls' osl types (made varying as the result)
  SmallVector<Type> derivTypes;
  Type resultType; ///< converted
  int64_t width;
  Operation *anchor;
  const LibraryRoutineNeeds &needs;
  const TypeConverter &converter;
  bool differentiated;

  Value build(OpBuilder &b, Location loc, Value kind, ValueRange coords,
              ValueRange derivs) const {
    bool varying = isVarying(oslResultType);
    Value result = lane::constant(b, loc, resultType, 0.0);
    for (NoiseKind k : kindsByKind(periodic)) {
      Value isK = b.create<arith::CmpIOp>(
          loc, arith::CmpIPredicate::eq, kind,
          lane::constant(b, loc, kind.getType(), double(int32_t(k))));
      Value any = varying ? b.create<vector::ReductionOp>(loc, vector::CombiningKind::OR, isK)
                                .getResult()
                          : isK;
      auto guard = b.create<scf::IfOp>(loc, TypeRange{resultType}, any, true, true);
      {
        OpBuilder::InsertionGuard inThen(b);
        b.setInsertionPointToStart(guard.thenBlock());
        Components lanes{b, loc, width};
        NoiseCall call = noiseCall(k, periodic, oslResultType, coords, coordTypes, lanes,
                                   converter);
        if (call.recipe.gabor())
          addGaborOperands(call, derivs, derivTypes,
                           gaborOptionList(withGaborDefaults(b, loc, GaborOptions{})));
        Value value = emitNoiseCall(b, loc, anchor, call, resultType, width, needs,
                                    /*keepCall=*/true, differentiated)
                          .getResult(0);
        Value mask = isK;
        if (auto shaped = dyn_cast<VectorType>(resultType); varying && shaped.getRank() == 2)
          mask = b.create<vector::BroadcastOp>(
              loc, VectorType::get(shaped.getShape(), b.getI1Type()), isK);
        b.create<scf::YieldOp>(loc, b.create<arith::SelectOp>(loc, mask, value, result)
                                        .getResult());
        b.setInsertionPointToStart(guard.elseBlock());
        b.create<scf::YieldOp>(loc, result);
      }
      result = guard.getResult(0);
    }
    return result;
  }

  std::string recipe() const {
    std::string s;
    llvm::raw_string_ostream os(s);
    os << "noise by kind" << (periodic ? " periodic" : "") << " width " << width << " (";
    llvm::interleaveComma(coordTypes, os);
    os << ") derivs (";
    llvm::interleaveComma(derivTypes, os);
    os << ") -> " << oslResultType;
    return s;
  }
};

struct NoiseByKindLowering : public NoisePattern<NoiseByKindOp> {
  using NoisePattern::NoisePattern;

  LogicalResult matchAndRewrite(NoiseByKindOp op, OpAdaptor adaptor,
                                ConversionPatternRewriter &rewriter) const override {
    Location loc = op.getLoc();
    Components outer{rewriter, loc, width};
    bool varying = isVarying(op.getType());
    // Every operand made as varying as the noise: one signature per domain.
    // (The body needs the osl types of the coordinates and derivatives.)
    auto operand = [&](Value converted, Type oslType, SmallVector<Value> &values,
                       SmallVector<Type> *types = nullptr) {
      Type type = withUniformity(getUniformType(oslType), varying);
      values.push_back(outer.pack(outer.unpack(converted, oslType, varying), convert(type)));
      if (types)
        types->push_back(type);
    };
    SmallVector<Value> kind, coords, derivs;
    SmallVector<Type> coordTypes, derivTypes;
    operand(adaptor.getKind(), op.getKind().getType(), kind);
    for (auto [value, original] : llvm::zip(adaptor.getCoords(), op.getCoords()))
      operand(value, original.getType(), coords, &coordTypes);
    for (auto [value, original] : llvm::zip(adaptor.getDerivs(), op.getDerivs()))
      operand(value, original.getType(), derivs, &derivTypes);
    bool differentiated = needs.derivativeOf.contains(op);
    NoiseByKindBody body{op.getPeriodic(), op.getType(), coordTypes, derivTypes,
                         convert(op.getType()), width, op, needs, *getTypeConverter(),
                         differentiated};
    if (differentiated) {
      // A derivative goes through each kind's call: osl-derivatives takes
      // them one by one, the tests in place.
      rewriter.replaceOp(op, body.build(rewriter, loc, kind[0], coords, derivs));
      return success();
    }
    SmallVector<Value> operands{kind[0]};
    llvm::append_range(operands, coords);
    llvm::append_range(operands, derivs);
    auto type = FunctionType::get(getContext(), ValueRange(operands).getTypes(),
                                  body.resultType);
    std::string text = body.recipe();
    size_t ncoords = coords.size();
    func::FuncOp func = libraryFunction(
        rewriter, op, op.getPeriodic() ? "noise_by_kind_periodic" : "noise_by_kind", text, type,
        /*needCode=*/!needs.available, [&] { return needs.available(text); },
        [&](OpBuilder &b, ValueRange args) -> SmallVector<Value> {
          return {body.build(b, loc, args[0], args.slice(1, ncoords),
                             args.drop_front(1 + ncoords))};
        });
    if (func.isDeclaration() && !func->hasAttr(kLibraryCalleesAttr)) {
      // Its object calls each kind's routine: theirs are linked beside it.
      // The body is built in a scratch region and dropped, for the kinds'
      // functions it makes (declarations where compiled before) and names;
      // once per kernel, the first call site's.
      SmallVector<Attribute> callees;
      OpBuilder::InsertionGuard guard(rewriter);
      auto scratch = rewriter.create<scf::ExecuteRegionOp>(loc, TypeRange{});
      rewriter.setInsertionPointToStart(&scratch.getRegion().emplaceBlock());
      body.build(rewriter, loc, kind[0], coords, derivs);
      scratch.walk([&](func::CallOp call) { callees.push_back(call.getCalleeAttr()); });
      rewriter.eraseOp(scratch);
      func->setAttr(kLibraryCalleesAttr, rewriter.getArrayAttr(callees));
    }
    auto call = rewriter.create<func::CallOp>(loc, func, operands);
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
  // osl-derivatives differentiates through a routine's code: a noise (or
  // splineinverse) any derivative request depends on keeps its code.
  DenseSet<Operation *> slice;
  root->walk([&](DerivOp d) {
    addBackwardSlice(d.getValue(), slice);
    inPlaceDerivatives |= d.getAxis() == DerivAxis::z;
  });
  for (Operation *op : slice)
    if (isa<NoiseOp, NoiseByKindOp, SplineInverseOp>(op))
      derivativeOf.insert(op);
}

bool LibraryRoutineNeeds::needCode(StringRef recipe, bool differentiated) const {
  // A routine a derivative goes through is differentiated by its dual
  // routine (osl-derivatives), built from its code unless compiled
  // before; along z, by its code copied in place.
  return !available ||
         (differentiated && (inPlaceDerivatives || !available(dualRecipeOf(recipe))));
}

void mlir::osl::lowering::populateNoisePatterns(const VaryingTypeConverter &converter,
                                                RewritePatternSet &patterns,
                                                const LibraryRoutineNeeds &needs) {
  patterns.add<NoiseLowering, NoiseByKindLowering>(converter, patterns.getContext(), needs);
}
