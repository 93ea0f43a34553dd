//===- OslOps.cpp - osl dialect operations --------------------------------===//
//
// Verifiers check base types (f32, i32, i1, triple). Uniformity is not
// checked per op: the front end may leave values uniform that
// osl-varying-propagation later makes varying, so consistency of uniform
// and varying types is that pass's postcondition instead.
//
//===----------------------------------------------------------------------===//
#include "OslDialect/OslDialect.h"
#include "OslAbi/Closures.h"
#include "OslAbi/GlobalsLayout.h"
#include "OslAbi/PointCloud.h"
#include "OslAbi/Print.h"
#include "OslAbi/Strings.h"

#include "mlir/Dialect/Arith/IR/Arith.h"
#include "mlir/IR/Builders.h"
#include "mlir/IR/TypeUtilities.h"
#include "mlir/IR/OpImplementation.h"
#include "mlir/IR/Matchers.h"
#include "mlir/IR/PatternMatch.h"
#include "llvm/ADT/StringSwitch.h"

using namespace mlir;
using namespace mlir::osl;

#define GET_OP_CLASSES
#include "OslDialect/OslOps.cpp.inc"

//===----------------------------------------------------------------------===//
// Lane-wise ops
//===----------------------------------------------------------------------===//

static bool isNumeric(Type t) { return t.isF32() || t.isInteger(32) || isTriple(t); }
static bool isFloatLike(Type t) { return t.isF32() || isTriple(t); }

static bool anyVarying(ValueRange values) {
  return llvm::any_of(values, [](Value v) { return isVarying(v.getType()); });
}

Type mlir::osl::inferLaneResultType(LaneKind kind, ValueRange operands) {
  Builder b(operands.front().getContext());
  bool varying = anyVarying(operands);
  Type base;
  switch (kind) {
  case LaneKind::TripleToFloat:
    base = b.getF32Type();
    break;
  case LaneKind::Compare:
    base = b.getI1Type();
    break;
  case LaneKind::Construct:
    base = VectorType::get({3}, b.getF32Type());
    break;
  case LaneKind::Select:
    base = getUniformType(operands[1].getType());
    break;
  default:
    base = getUniformType(operands.front().getType());
  }
  return withUniformity(base, varying);
}

LogicalResult mlir::osl::verifyLaneOp(Operation *op, LaneKind kind) {
  SmallVector<Type> bases;
  for (Value v : op->getOperands())
    bases.push_back(getUniformType(v.getType()));
  Type result = getUniformType(op->getResult(0).getType());
  auto allSame = [&](ArrayRef<Type> types) {
    return llvm::all_equal(types);
  };
  switch (kind) {
  case LaneKind::Numeric:
  case LaneKind::Float:
  case LaneKind::Int:
  case LaneKind::Bool:
  case LaneKind::Triple: {
    auto accepts = [&](Type t) {
      switch (kind) {
      case LaneKind::Numeric: return isNumeric(t);
      case LaneKind::Float: return isFloatLike(t);
      case LaneKind::Int: return t.isInteger(32);
      case LaneKind::Bool: return t.isInteger(1);
      default: return isTriple(t);
      }
    };
    if (!allSame(bases) || !accepts(bases.front()))
      return op->emitOpError("operands must share one type accepted by this op, got ")
             << bases;
    if (result != bases.front())
      return op->emitOpError("result type ") << result
             << " must match operand type " << bases.front();
    return success();
  }
  case LaneKind::TripleToFloat:
    if (!llvm::all_of(bases, isTriple) || !result.isF32())
      return op->emitOpError("takes triples and gives f32");
    return success();
  case LaneKind::Compare: {
    // Closures compare for equality only (`if (Ci)` is Ci != the empty one).
    CmpPredicate predicate = cast<CmpOp>(op).getPredicate();
    bool closures = isa<ClosureType>(bases.front()) &&
                    (predicate == CmpPredicate::eq || predicate == CmpPredicate::ne);
    if (!allSame(bases) ||
        !(isNumeric(bases.front()) || bases.front().isInteger(1) || closures))
      return op->emitOpError("compares two values of one type, got ") << bases;
    if (!result.isInteger(1))
      return op->emitOpError("result must be i1");
    return success();
  }
  case LaneKind::Select:
    if (!bases[0].isInteger(1))
      return op->emitOpError("condition must be i1");
    if (bases[1] != bases[2] || result != bases[1])
      return op->emitOpError("both values and the result must share one type");
    return success();
  case LaneKind::Construct:
    if (!llvm::all_of(bases, [](Type t) { return t.isF32(); }) || !isTriple(result))
      return op->emitOpError("builds a vector<3xf32> from three f32");
    return success();
  }
  return success();
}

//===----------------------------------------------------------------------===//
// Interface ops
//===----------------------------------------------------------------------===//

LogicalResult GlobalOp::verify() {
  const ::osl::GlobalSlot *slot = ::osl::findGlobal(getName().str());
  if (!slot)
    return emitOpError("unknown shader global '") << getName() << "'";
  // Globals are varying, except in reference mode (osl-uniform-reference),
  // which shades one point at a time.
  bool reference = false;
  for (Operation *p = (*this)->getParentOp(); p; p = p->getParentOp())
    reference |= p->hasAttr("osl.reference");
  if (!isVarying(getType()) && !reference)
    return emitOpError("shader globals are varying");
  Type base = getUniformType(getType());
  if ((slot->rows == 3) != isTriple(base) || (slot->rows == 1 && !base.isF32()))
    return emitOpError("global '") << getName() << "' has type "
           << (slot->rows == 3 ? "vector<3xf32>" : "f32");
  return success();
}

// The value may be varying already: a pass that made it so (a loop
// unrolled, a constant if folded) leaves the broadcast an identity, which
// folds away and osl-varying-propagation removes.
LogicalResult BroadcastOp::verify() {
  if (!isVarying(getType()) ||
      getUniformType(getType()) != getUniformType(getValue().getType()))
    return emitOpError("turns a uniform T (or a varying one) into !osl.varying<T>");
  return success();
}

OpFoldResult BroadcastOp::fold(FoldAdaptor) {
  if (getValue().getType() == getType())
    return getValue();
  return {};
}

LogicalResult BatchMaskOp::verify() {
  if (!isVarying(getType()))
    return emitOpError("the batch mask is varying");
  return success();
}

//===----------------------------------------------------------------------===//
// Conversions and components
//===----------------------------------------------------------------------===//

LogicalResult ConvertOp::verify() {
  Type from = getUniformType(getValue().getType());
  Type to = getUniformType(getType());
  bool scalarFrom = from.isF32() || from.isInteger(32) || from.isInteger(1);
  bool ok = (scalarFrom && (to.isF32() || to.isInteger(32) || to.isInteger(1))) ||
            ((from.isF32() || from.isInteger(32)) && isTriple(to));
  if (!ok)
    return emitOpError("cannot convert ") << from << " to " << to;
  return success();
}

LogicalResult ExtractOp::verify() {
  if (!getUniformType(getType()).isF32())
    return emitOpError("result must be f32");
  return success();
}

LogicalResult InsertOp::verify() {
  if (getUniformType(getType()) != getUniformType(getVector().getType()))
    return emitOpError("result must be a triple");
  return success();
}

//===----------------------------------------------------------------------===//
// Library calls
//===----------------------------------------------------------------------===//

LogicalResult PickOp::verify() {
  if (getElements().empty())
    return emitOpError("needs at least one element");
  if (!getUniformType(getIndex().getType()).isInteger(32))
    return emitOpError("the index must be i32");
  Type element = getUniformType(getType());
  bool varying = isVarying(getIndex().getType());
  for (Value e : getElements()) {
    if (getUniformType(e.getType()) != element)
      return emitOpError("every element must be of the result's type");
    varying |= isVarying(e.getType());
  }
  if (!(element.isF32() || element.isInteger(32) || isTriple(element)))
    return emitOpError("elements must be f32, i32 or triples");
  if (varying && !isVarying(getType()))
    return emitOpError("the result must be varying when the index or an element is");
  return success();
}

/// The element a pick reads whatever its index (all are the same value),
/// or at a constant index (a scalar or the same in every lane); null if
/// neither, or if that element's type differs from the result's (a uniform
/// element of a varying pick).
static Value pickedElement(ValueRange elements, Attribute index, Type result) {
  Value chosen;
  if (llvm::all_equal(elements)) {
    chosen = elements.front();
  } else {
    auto splat = dyn_cast_or_null<SplatElementsAttr>(index);
    auto k = dyn_cast_or_null<IntegerAttr>(splat ? splat.getSplatValue<Attribute>() : index);
    if (k && k.getInt() >= 0 && k.getInt() < int64_t(elements.size()))
      chosen = elements[k.getInt()];
  }
  return chosen && chosen.getType() == result ? chosen : Value();
}

OpFoldResult PickOp::fold(FoldAdaptor adaptor) {
  return pickedElement(getElements(), adaptor.getIndex(), getType());
}

OpFoldResult LanePickOp::fold(FoldAdaptor adaptor) {
  return pickedElement(getElements(), adaptor.getIndex(), getType());
}

OpFoldResult CodegenFenceOp::fold(FoldAdaptor adaptor) {
  // Only a constant passes through (the constant itself, not a copy): a
  // fence on a computed value stays.
  if (adaptor.getValue())
    return getValue();
  return {};
}

LogicalResult LanePickOp::verify() {
  if (getElements().empty())
    return emitOpError("needs at least one element");
  for (Value e : getElements())
    if (e.getType() != getType())
      return emitOpError("every element must be of the result's type");
  // Numbers, or one 1-D vector of them (W lanes): what the lowering stores
  // as W-element rows of a stack block.
  auto isLanesOf = [](Type t, auto isElement) {
    auto v = dyn_cast<VectorType>(t);
    return v ? v.getRank() == 1 && !v.isScalable() && isElement(v.getElementType())
             : isElement(t);
  };
  auto number = [](Type t) { return t.isF32() || t.isF64() || t.isInteger(32); };
  auto i32 = [](Type t) { return t.isInteger(32); };
  if (!isLanesOf(getType(), number))
    return emitOpError("the result must be f32, f64 or i32, or one 1-D vector of them");
  Type index = getIndex().getType();
  auto lanes = dyn_cast<VectorType>(index);
  if (!isLanesOf(index, i32) ||
      (lanes && !(isa<VectorType>(getType()) &&
                  lanes.getShape() == cast<VectorType>(getType()).getShape())))
    return emitOpError("the index must be i32, a scalar or one per lane of the result");
  return success();
}

LogicalResult TableReadOp::verify() {
  auto table = getTable();
  Type element = table.getElementType();
  if (table.getType().getRank() != 1 || table.getNumElements() == 0 ||
      !(element.isF32() || element.isInteger(32)))
    return emitOpError("the table must be a non-empty 1-D list of f32 or i32");
  if (!getUniformType(getIndex().getType()).isInteger(32))
    return emitOpError("the index must be i32");
  if (getType() != withUniformity(element, isVarying(getIndex().getType())))
    return emitOpError("the result must be the table's element, varying as the index");
  return success();
}

std::optional<NoiseKind> mlir::osl::noiseKindFromName(StringRef name) {
  return llvm::StringSwitch<std::optional<NoiseKind>>(name)
      .Cases("perlin", "snoise", NoiseKind::perlin)
      .Cases("uperlin", "noise", NoiseKind::uperlin)
      .Cases("cell", "cellnoise", NoiseKind::cell)
      .Cases("hash", "hashnoise", NoiseKind::hash)
      .Case("simplex", NoiseKind::simplex)
      .Case("usimplex", NoiseKind::usimplex)
      .Case("gabor", NoiseKind::gabor)
      .Default(std::nullopt);
}

std::optional<SplineBasis> mlir::osl::splineBasisFromName(StringRef name) {
  if (name == "catmull-rom")
    return SplineBasis::catmullrom;
  if (name == "catmullrom") // not OSL's spelling
    return std::nullopt;
  return symbolizeSplineBasis(name);
}

StringRef mlir::osl::splineBasisName(SplineBasis basis) {
  return basis == SplineBasis::catmullrom ? "catmull-rom" : stringifySplineBasis(basis);
}

/// Whether `derivs` are Dx then Dy of each coordinate of the lookup point
/// of a noise whose domain (uniform types, without periods) is `domain`:
/// the triple, or each float coordinate.
static bool arePointDerivs(ValueRange derivs, ArrayRef<Type> domain) {
  ArrayRef<Type> point = isTriple(domain[0]) ? domain.take_front(1) : domain;
  if (derivs.size() != 2 * point.size())
    return false;
  for (auto [k, d] : llvm::enumerate(derivs))
    if (getUniformType(d.getType()) != point[k % point.size()])
      return false;
  return true;
}

/// Gabor's options and filter derivatives (see the op's description).
/// `domain` holds the uniform types of the coordinates, without periods.
static LogicalResult verifyNoiseOptions(NoiseOp op, ArrayRef<Type> domain) {
  bool gabor = op.getKind() == NoiseKind::gabor;
  bool anyOption = op.getAnisotropic() || op.getDirection() || op.getBandwidth() ||
                   op.getImpulses() || op.getDoFilter();
  if (!gabor && (anyOption || !op.getDerivs().empty()))
    return op.emitOpError("only gabor noise takes options and derivatives");
  struct Option {
    Value value;
    StringRef name;
    bool ok;
  };
  auto is = [](Value v, auto pred) { return !v || pred(getUniformType(v.getType())); };
  Option options[] = {
      {op.getAnisotropic(), "anisotropic", is(op.getAnisotropic(), [](Type t) { return t.isInteger(32); })},
      {op.getDirection(), "direction", is(op.getDirection(), [](Type t) { return isTriple(t); })},
      {op.getBandwidth(), "bandwidth", is(op.getBandwidth(), [](Type t) { return t.isF32(); })},
      {op.getImpulses(), "impulses", is(op.getImpulses(), [](Type t) { return t.isF32(); })},
      {op.getDoFilter(), "do_filter", is(op.getDoFilter(), [](Type t) { return t.isInteger(32); })}};
  for (const Option &o : options) {
    if (!o.ok)
      return op.emitOpError("noise option '")
             << o.name << "' has the wrong type " << o.value.getType();
  }
  if (!op.getDerivs().empty() && !arePointDerivs(op.getDerivs(), domain))
    return op.emitOpError("derivs must be Dx then Dy of each point coordinate");
  return success();
}

/// The domain of a noise's coordinates (their uniform types, periods
/// dropped), checked against the domains noise has; failure reported.
static FailureOr<SmallVector<Type>> verifyNoiseDomain(Operation *op, ValueRange coords,
                                                      bool periodic, Type result) {
  SmallVector<Type> bases;
  for (Value v : coords)
    bases.push_back(getUniformType(v.getType()));
  if (periodic) {
    size_t half = bases.size() / 2;
    if (bases.size() % 2 ||
        !llvm::equal(ArrayRef<Type>(bases).take_front(half),
                     ArrayRef<Type>(bases).drop_front(half)))
      return op->emitOpError("periodic noise takes one period per coordinate, of its type");
    bases.resize(half);
  }
  bool domainOk = (bases.size() == 1 && isFloatLike(bases[0])) ||
                  (bases.size() == 2 && isFloatLike(bases[0]) && bases[1].isF32());
  if (!domainOk)
    return op->emitOpError("domain must be (float), (float, float), (triple) or "
                           "(triple, float)");
  if (!isFloatLike(getUniformType(result)))
    return op->emitOpError("result must be f32 or a triple");
  return bases;
}

LogicalResult NoiseOp::verify() {
  auto domain = verifyNoiseDomain(*this, getCoords(), getPeriodic(), getType());
  if (failed(domain))
    return failure();
  return verifyNoiseOptions(*this, *domain);
}

LogicalResult NoiseByKindOp::verify() {
  auto domain = verifyNoiseDomain(*this, getCoords(), getPeriodic(), getType());
  if (failed(domain))
    return failure();
  if (!getUniformType(getKind().getType()).isInteger(32))
    return emitOpError("kind must be an i32");
  // Gabor filters a 2D, 3D or 4D domain by the point's derivatives.
  bool filtered = domain->size() == 2 || isTriple((*domain)[0]);
  if (filtered ? !arePointDerivs(getDerivs(), *domain) : !getDerivs().empty())
    return emitOpError(filtered ? "derivs must be Dx then Dy of each point coordinate"
                                : "a 1D noise takes no derivs");
  return success();
}

namespace {
/// A noise whose kind is a constant is the noise of that kind.
struct NoiseOfConstantKind : public OpRewritePattern<NoiseByKindOp> {
  using OpRewritePattern::OpRewritePattern;
  LogicalResult matchAndRewrite(NoiseByKindOp op, PatternRewriter &rewriter) const override {
    APInt value;
    if (!matchPattern(op.getKind(), m_ConstantInt(&value)))
      return failure();
    std::optional<NoiseKind> kind = symbolizeNoiseKind(uint32_t(value.getSExtValue()));
    if (!kind || (op.getPeriodic() && (*kind == NoiseKind::simplex ||
                                       *kind == NoiseKind::usimplex)))
      return failure(); // 0: left to the lowering, which knows the zero of every type
    bool gabor = *kind == NoiseKind::gabor;
    rewriter.replaceOpWithNewOp<NoiseOp>(
        op, op.getType(), *kind, op.getCoords(), op.getPeriodic(),
        gabor ? op.getDerivs() : ValueRange(), Value(), Value(), Value(), Value(), Value());
    return success();
  }
};
} // namespace

void NoiseByKindOp::getCanonicalizationPatterns(RewritePatternSet &results,
                                                MLIRContext *context) {
  results.add<NoiseOfConstantKind>(context);
}

LogicalResult TransformOp::verify() {
  if (getFrom().empty() || getTo().empty())
    return emitOpError("space names must not be empty");
  return success();
}

//===----------------------------------------------------------------------===//
// Textures
//===----------------------------------------------------------------------===//

/// Names of the string options of osl.texture, in `choices` order.
static constexpr const char *kTextureChoiceNames[] = {"file",  "swrap",  "twrap",
                                                      "rwrap", "interp", "subimagename"};

LogicalResult TextureOp::verify() {
  auto [coords, derivs] = [&]() -> std::pair<size_t, size_t> {
    switch (getKind()) {
    case TextureKind::texture:
      return {2, 4};
    case TextureKind::texture3d:
      return {3, 9};
    case TextureKind::environment:
      return {3, 6};
    }
    llvm_unreachable("texture kind");
  }();
  if (getCoords().size() != coords || getDerivs().size() != derivs)
    return emitOpError("a ") << stringifyTextureKind(getKind()) << " lookup takes " << coords
                             << " coordinates and " << derivs << " derivatives";
  if (getFloatOptions().size() != 11)
    return emitOpError("needs 11 float options (8 per-point options, then missingcolor)");
  if (getNchannels() != 1 && getNchannels() != 3)
    return emitOpError("nchannels must be 1 or 3");
  Type resultType = getUniformType(getResult().getType());
  if ((getNchannels() == 3) != isTriple(resultType) || !(resultType.isF32() || isTriple(resultType)))
    return emitOpError("result must be f32 for 1 channel, a triple for 3");
  if (!getUniformType(getFirstchannel().getType()).isInteger(32) ||
      !getUniformType(getSubimage().getType()).isInteger(32))
    return emitOpError("firstchannel and subimage must be i32");
  size_t n = std::size(kTextureChoiceNames);
  if (getChoices().size() != n || getCandidates().size() != n)
    return emitOpError("needs ") << n << " string choices and candidate lists";
  for (auto [i, c] : llvm::enumerate(getChoices())) {
    auto list = dyn_cast<ArrayAttr>(getCandidates()[i]);
    if (!list || list.empty() || !llvm::all_of(list, [](Attribute a) { return isa<StringAttr>(a); }))
      return emitOpError("candidates for ") << kTextureChoiceNames[i]
                                            << " must be a non-empty list of strings";
    if (!getUniformType(c.getType()).isInteger(32))
      return emitOpError("choice of ") << kTextureChoiceNames[i] << " must be i32";
  }
  if (getFileHandle() && !getUniformType(getFileHandle().getType()).isInteger(32))
    return emitOpError("fileHandle must be an i32 string handle");
  return success();
}

LogicalResult GetTextureInfoOp::verify() {
  if (getValues().empty())
    return emitOpError("needs at least one value");
  if (getFloats() && getStrings())
    return emitOpError("answers with floats or with strings, not both");
  Type want = getFloats() ? Type(Float32Type::get(getContext()))
                         : Type(IntegerType::get(getContext(), 32));
  for (Value v : getValues())
    if (getUniformType(v.getType()) != want)
      return emitOpError("values must all be ") << want;
  if (!getUniformType(getFound().getType()).isInteger(32))
    return emitOpError("found must be i32");
  if (getFileHandle() && !getUniformType(getFileHandle().getType()).isInteger(32))
    return emitOpError("fileHandle must be an i32 string handle");
  if (!getFileHandle() && (isVarying(getFound().getType()) ||
                           llvm::any_of(getValues(), [](Value v) { return isVarying(v.getType()); })))
    return emitOpError("answers about a file known when compiled are uniform");
  return success();
}

LogicalResult UdimTileOp::verify() {
  if (!getUniformType(getFile().getType()).isInteger(32) ||
      !getUniformType(getResult().getType()).isInteger(32))
    return emitOpError("file and result must be i32 string handles");
  if (!getUniformType(getS().getType()).isF32() || !getUniformType(getT().getType()).isF32())
    return emitOpError("s and t must be f32");
  bool varying = llvm::any_of(getOperands(), [](Value v) { return isVarying(v.getType()); });
  if (varying != isVarying(getResult().getType()))
    return emitOpError("result must be varying exactly when an operand is");
  return success();
}

//===----------------------------------------------------------------------===//
// Strings
//===----------------------------------------------------------------------===//

/// The base type an operand or result of string kind `kind` has.
static Type stringKindType(Builder &b, char kind) {
  switch (kind) {
  case 's':
  case 'i':
    return b.getI32Type();
  case 'f':
    return b.getF32Type();
  case 'k':
    return ClosureType::get(b.getContext());
  default:
    return VectorType::get({3}, b.getF32Type());
  }
}

LogicalResult StringCallOp::verify() {
  int32_t code = ::osl::stringFunctionCode(getCallee());
  if (code < 0)
    return emitOpError("unknown string function '") << getCallee() << "'";
  StringRef kinds = getKinds();
  if (kinds.size() != getArgs().size())
    return emitOpError("needs one kind letter per operand, got '") << kinds << "' for "
                                                                   << getArgs().size();
  if (!::osl::stringOperandsMatch(code, kinds))
    return emitOpError("operand kinds '")
           << kinds << "' do not fit " << getCallee() << "'s '"
           << ::osl::kStringFunctions[code].operands << "'";
  Builder b(getContext());
  for (auto [i, arg] : llvm::enumerate(getArgs()))
    if (getUniformType(arg.getType()) != stringKindType(b, kinds[i]))
      return emitOpError("operand ") << i << " of kind '" << kinds[i] << "' must be "
                                     << stringKindType(b, kinds[i]);
  Type result = stringKindType(b, ::osl::kStringFunctions[code].result);
  if (getUniformType(getResult().getType()) != result)
    return emitOpError("result must be ") << result;
  return success();
}

LogicalResult PrintOp::verify() {
  int32_t code = ::osl::printStreamCode(getStream());
  if (code < 0)
    return emitOpError("unknown print stream '") << getStream() << "'";
  StringRef kinds = getKinds();
  if (kinds.size() != getArgs().size())
    return emitOpError("needs one kind letter per operand, got '") << kinds << "' for "
                                                                   << getArgs().size();
  StringRef leading = ::osl::kPrintStreams[code].operands;
  if (!kinds.starts_with(leading))
    return emitOpError("operand kinds '") << kinds << "' must start with '" << leading
                                          << "' for " << getStream();
  for (char k : kinds.drop_front(leading.size()))
    if (!StringRef("siftk").contains(k))
      return emitOpError("unknown operand kind '") << k << "'";
  Builder b(getContext());
  for (auto [i, arg] : llvm::enumerate(getArgs()))
    if (getUniformType(arg.getType()) != stringKindType(b, kinds[i]))
      return emitOpError("operand ") << i << " of kind '" << kinds[i] << "' must be "
                                     << stringKindType(b, kinds[i]);
  return success();
}

/// A message's operands: one per kind letter (s, i, f, t, k), each of
/// that kind's type.
static LogicalResult verifyMessageOperands(Operation *op, StringRef kinds,
                                           ValueRange values) {
  if (kinds.size() != values.size())
    return op->emitOpError("needs one kind letter per value, got '")
           << kinds << "' for " << values.size();
  Builder b(op->getContext());
  for (auto [i, v] : llvm::enumerate(values)) {
    if (!StringRef("siftk").contains(kinds[i]))
      return op->emitOpError("unknown value kind '") << kinds[i] << "'";
    if (getUniformType(v.getType()) != stringKindType(b, kinds[i]))
      return op->emitOpError("value ") << i << " of kind '" << kinds[i] << "' must be "
                                       << stringKindType(b, kinds[i]);
  }
  return success();
}

LogicalResult SetMessageOp::verify() {
  return verifyMessageOperands(*this, getKinds(), getValues());
}

LogicalResult GetMessageOp::verify() {
  if (failed(verifyMessageOperands(*this, getKinds(), getCurrent())))
    return failure();
  if (getValues().size() != getCurrent().size())
    return emitOpError("needs one result per value");
  if (!isVarying(getFound().getType()) || getUniformType(getFound().getType()) !=
                                              IntegerType::get(getContext(), 32))
    return emitOpError("'found' must be a varying i32");
  for (auto [c, v] : llvm::zip(getCurrent(), getValues()))
    if (!isVarying(v.getType()) || getUniformType(v.getType()) != getUniformType(c.getType()))
      return emitOpError("results must be the values' types, varying");
  return success();
}

LogicalResult PointCloudOp::verify() {
  auto function = ::osl::pointCloudFunction(getFunction());
  if (!function)
    return emitOpError("unknown point-cloud function '") << getFunction() << "'";
  auto arrays = ::osl::parsePointCloudLayout(getLayout());
  if (!arrays)
    return emitOpError("malformed layout '") << getLayout() << "'";
  std::string expected = ::osl::pointCloudInputKinds(*function);
  size_t fixedInputs = expected.size();
  if (getInputs().size() < fixedInputs)
    return emitOpError("needs at least ") << fixedInputs << " inputs";
  if (*function == ::osl::PointCloudFunction::Write) {
    if (!getCurrent().empty())
      return emitOpError("write has no output arrays");
    for (const ::osl::PointCloudArray &a : *arrays) {
      if (a.length != 1)
        return emitOpError("write's attributes must have length 1");
      expected += a.kind;
    }
  } else {
    if (*function == ::osl::PointCloudFunction::Get) {
      if (arrays->size() != 1 || !arrays->front().name.empty())
        return emitOpError("get has one output array, named by an input");
      expected.append(getInputs().size() - fixedInputs, 'i');
    }
    for (const ::osl::PointCloudArray &a : *arrays)
      expected.append(size_t(a.length), a.kind);
  }
  if (getKinds() != expected)
    return emitOpError("operand kinds '") << getKinds() << "' must be '" << expected << "'";
  SmallVector<Value> operands(getInputs());
  llvm::append_range(operands, getCurrent());
  if (failed(verifyMessageOperands(*this, getKinds(), operands)))
    return failure();
  Type i32 = IntegerType::get(getContext(), 32);
  for (Value r : {getStatus(), getWritten()})
    if (!isVarying(r.getType()) || getUniformType(r.getType()) != i32)
      return emitOpError("'status' and 'written' must be varying i32");
  if (getValues().size() != getCurrent().size())
    return emitOpError("needs one result per output element");
  for (auto [c, v] : llvm::zip(getCurrent(), getValues()))
    if (!isVarying(v.getType()) || getUniformType(v.getType()) != getUniformType(c.getType()))
      return emitOpError("results must be the output elements' types, varying");
  return success();
}

LogicalResult FirstLaneOp::verify() {
  if (isVarying(getResult().getType()))
    return emitOpError("result must be uniform");
  if (getUniformType(getValue().getType()) != getResult().getType())
    return emitOpError("result must have the operand's element type");
  return success();
}

//===----------------------------------------------------------------------===//
// Color
//===----------------------------------------------------------------------===//

/// A color op maps one value to one result, varying exactly when its
/// operand is, under a named working color space.
static LogicalResult verifyColorOp(Operation *op, StringRef colorspace) {
  if (colorspace.empty())
    return op->emitOpError("needs a working color space name");
  if (isVarying(op->getOperand(0).getType()) != isVarying(op->getResult(0).getType()))
    return op->emitOpError("result must be varying exactly when the operand is");
  return success();
}

LogicalResult TransformcOp::verify() {
  if (getFrom().empty() || getTo().empty())
    return emitOpError("color space names must not be empty");
  return verifyColorOp(*this, getColorspace());
}
LogicalResult BlackbodyOp::verify() { return verifyColorOp(*this, getColorspace()); }
LogicalResult WavelengthColorOp::verify() { return verifyColorOp(*this, getColorspace()); }
LogicalResult LuminanceOp::verify() { return verifyColorOp(*this, getColorspace()); }

/// Checks shared by spline and splineinverse: a known basis, enough knots,
/// an f32 parameter and an i32 count.
static LogicalResult verifySplineCommon(Operation *op, SplineBasis basis, Value x,
                                        Value count, ValueRange knots) {
  size_t minKnots = basis == SplineBasis::constant ? 1 : basis == SplineBasis::linear ? 2 : 4;
  if (knots.size() < minKnots)
    return op->emitOpError("basis '") << splineBasisName(basis) << "' needs at least "
                                      << minKnots << " knots";
  if (!getUniformType(x.getType()).isF32())
    return op->emitOpError("the spline parameter must be f32");
  if (count && !getUniformType(count.getType()).isInteger(32))
    return op->emitOpError("the knot count must be i32");
  return success();
}

LogicalResult SplineInverseOp::verify() {
  if (failed(verifySplineCommon(*this, getBasis(), getY(), getCount(), getKnots())))
    return failure();
  for (Value k : getKnots())
    if (!getUniformType(k.getType()).isF32())
      return emitOpError("knots must be f32");
  if (!getUniformType(getType()).isF32())
    return emitOpError("result must be f32");
  return success();
}

LogicalResult SplineOp::verify() {
  if (failed(verifySplineCommon(*this, getBasis(), getX(), getCount(), getKnots())))
    return failure();
  Type knot = getUniformType(getKnots().front().getType());
  for (Value k : getKnots())
    if (getUniformType(k.getType()) != knot || !isFloatLike(knot))
      return emitOpError("knots must all be f32 or all triples");
  if (getUniformType(getType()) != knot)
    return emitOpError("result must have the knots' type");
  return success();
}

//===----------------------------------------------------------------------===//
// Derivatives
//===----------------------------------------------------------------------===//

LogicalResult DerivOp::verify() {
  if (!isFloatLike(getUniformType(getValue().getType())))
    return emitOpError("only floats and triples have derivatives");
  return success();
}

//===----------------------------------------------------------------------===//
// Closures
//===----------------------------------------------------------------------===//

Value mlir::osl::buildZero(OpBuilder &b, Location loc, Type type) {
  Type base = getUniformType(type);
  Value zero = isa<ClosureType>(base)
                   ? b.create<ClosureEmptyOp>(loc, base).getResult()
                   : b.create<arith::ConstantOp>(loc, b.getZeroAttr(base)).getResult();
  return isVarying(type) ? b.create<BroadcastOp>(loc, type, zero).getResult() : zero;
}

/// The IR type of a closure parameter of kind `kind` (ClosureCall.h).
static Type closureKindType(Builder &b, char kind) {
  switch (kind) {
  case 'n':
  case 'c': return VectorType::get({3}, b.getF32Type());
  case 'f': return b.getF32Type();
  case 'k': return ClosureType::get(b.getContext());
  default: return b.getI32Type(); // i, s
  }
}

LogicalResult ClosureComponentOp::verify() {
  int32_t id = ::osl::closureId(getName());
  if (id < 0)
    return emitOpError("unknown closure '") << getName() << "'";
  char kinds[::osl::kMaxClosureParams];
  int32_t n = ::osl::closureParamKinds(id, kinds, ::osl::kMaxClosureParams);
  if (int32_t(getArgs().size()) != n)
    return emitOpError("closure '") << getName() << "' takes " << n
                                    << " operands (positional, then keywords), got "
                                    << getArgs().size();
  Builder b(getContext());
  for (auto [i, arg] : llvm::enumerate(getArgs()))
    if (getUniformType(arg.getType()) != closureKindType(b, kinds[i]))
      return emitOpError("operand ") << i << " of kind '" << kinds[i] << "' must be "
                                     << closureKindType(b, kinds[i]);
  return success();
}

// Closure ops follow the uniformity rules of every other op: a varying
// operand makes the result varying once osl-varying-propagation has run
// (linking a varying output into a uniform input leaves it uniform until
// then), so there is nothing to check here.
LogicalResult ClosureMulOp::verify() { return success(); }
LogicalResult ClosureAddOp::verify() { return success(); }

OpFoldResult ClosureAddOp::fold(FoldAdaptor) {
  // empty + c = c, when c already has the result's uniformity.
  for (auto [empty, other] : {std::pair(getLhs(), getRhs()), std::pair(getRhs(), getLhs())})
    if (empty.getDefiningOp<ClosureEmptyOp>() && other.getType() == getType())
      return other;
  return {};
}
