//===- OslToVector.h - osl-convert-to-vector's shared pieces ----*- C++ -*-===//
//
// The type converter (varying values as vectors of W lanes, triples as
// vector<3 x W>), the lane packing helpers, the pattern base, and the
// helpers of the patterns that call the runtime (stack blocks of rows,
// lane masks as bits, call sites), and the populate function of each file
// of patterns.
//
//===----------------------------------------------------------------------===//
#ifndef OSLCONVERSION_OSLTOVECTOR_H
#define OSLCONVERSION_OSLTOVECTOR_H

#include "OslAbi/EntryPoints.h"
#include "OslDialect/OslDialect.h"
#include "OslLanes/LaneMath.h"
#include "OslLanes/LibraryFunctions.h"

#include "mlir/Dialect/Func/IR/FuncOps.h"
#include "mlir/Dialect/LLVMIR/LLVMDialect.h"
#include "mlir/IR/BuiltinOps.h"
#include "mlir/Dialect/Vector/IR/VectorOps.h"
#include "mlir/Transforms/DialectConversion.h"

#include <string>
#include <type_traits>
#include <utility>

namespace mlir::osl::lowering {

/// The runtime entry points (osl_rt_texture, ...), named as in C.
namespace entry = ::osl::abi::entry;

class VaryingTypeConverter : public TypeConverter {
public:
  explicit VaryingTypeConverter(int64_t width) : width(width) {
    addConversion([](Type t) { return t; });
    // A closure is an i32 handle into the closure arena (OslAbi/Closures.h).
    addConversion([](ClosureType t) -> Type { return IntegerType::get(t.getContext(), 32); });
    addConversion([width](VaryingType t) -> Type {
      Type e = t.getElementType();
      if (isTriple(e))
        return VectorType::get({3, width}, Float32Type::get(t.getContext()));
      if (isa<ClosureType>(e))
        e = IntegerType::get(t.getContext(), 32);
      return VectorType::get({width}, e);
    });
    auto cast = [](OpBuilder &b, Type type, ValueRange inputs,
                   Location loc) -> std::optional<Value> {
      return b.create<UnrealizedConversionCastOp>(loc, type, inputs).getResult(0);
    };
    addSourceMaterialization(cast);
    addTargetMaterialization(cast);
    addArgumentMaterialization(cast);
  }
  int64_t width;
};

/// Splits converted values into per-component lane values and back.
struct Components {
  OpBuilder &b;
  Location loc;
  int64_t width;

  /// Components of `value` (converted) whose osl type is `oslType`, made
  /// varying (broadcast) when `varying` is set.
  SmallVector<Value> unpack(Value value, Type oslType, bool varying) {
    SmallVector<Value> comps;
    if (isTriple(getUniformType(oslType)))
      for (int64_t i = 0; i < 3; ++i)
        comps.push_back(b.create<vector::ExtractOp>(loc, value, ArrayRef<int64_t>{i}));
    else
      comps.push_back(value);
    if (varying && !isVarying(oslType))
      for (Value &c : comps)
        c = lane::broadcast(b, loc, c, width);
    return comps;
  }

  /// unpack() for each operand of an op.
  SmallVector<SmallVector<Value>> unpackAll(ValueRange converted,
                                            ValueRange original, bool varying) {
    SmallVector<SmallVector<Value>> all;
    for (auto [c, o] : llvm::zip(converted, original))
      all.push_back(unpack(c, o.getType(), varying));
    return all;
  }

  Value pack(ArrayRef<Value> comps, Type convertedType) {
    if (comps.size() == 1)
      return comps.front();
    Value acc = lane::constant(b, loc, convertedType, 0);
    for (auto [i, c] : llvm::enumerate(comps))
      acc = b.create<vector::InsertOp>(loc, c, acc, ArrayRef<int64_t>{int64_t(i)});
    return acc;
  }
};

using LaneFn = Value (*)(OpBuilder &, Location, ValueRange);

/// Base for osl patterns: access to the width and lane helpers.
template <typename OpTy>
struct OslPattern : public OpConversionPattern<OpTy> {
  OslPattern(const VaryingTypeConverter &converter, MLIRContext *ctx)
      : OpConversionPattern<OpTy>(converter, ctx), width(converter.width) {}
  Type convert(Type t) const { return this->getTypeConverter()->convertType(t); }
  int64_t width;
};

/// The kernel's arguments: globals, outputs, nactive.
Value kernelArg(Operation *op, unsigned i);
/// Lanes [0, nactive): lane index < nactive.
Value activeLanes(OpBuilder &b, Location loc, Operation *op, int64_t width);
/// Address of row `row` of a structure-of-arrays block of W-float rows.
Value rowAddress(OpBuilder &b, Location loc, Value base, int64_t row, int64_t width);
/// Row `row` of a block the runtime wrote, as `width` lanes of `element`: a
/// value with no derivatives.
Value loadResultRow(OpBuilder &b, Location loc, Value base, int64_t row, int64_t width,
                    Type element);
/// The LLVM type of a C type of the kernel ABI (OslAbi/EntryPoints.h).
template <typename T> Type abiType(MLIRContext *ctx) {
  if constexpr (std::is_pointer_v<T>)
    return LLVM::LLVMPointerType::get(ctx);
  else if constexpr (std::is_same_v<T, float>)
    return Float32Type::get(ctx);
  else if constexpr (std::is_same_v<T, void>)
    return LLVM::LLVMVoidType::get(ctx);
  else {
    static_assert(std::is_integral_v<T>, "the kernel ABI passes pointers, ints and floats");
    return IntegerType::get(ctx, unsigned(sizeof(T) * 8));
  }
}

template <typename Result, typename... Params>
LLVM::LLVMFunctionType abiFunctionType(MLIRContext *ctx, Result (*)(Params...)) {
  return LLVM::LLVMFunctionType::get(abiType<Result>(ctx), {abiType<Params>(ctx)...});
}

/// Declares runtime function `name` in the module once.
LLVM::LLVMFuncOp runtimeDeclaration(OpBuilder &b, Operation *op, StringRef name,
                                    LLVM::LLVMFunctionType type);

/// Declares runtime entry point `entry` in the module once, with the LLVM
/// type of its C declaration.
template <typename Fn>
LLVM::LLVMFuncOp runtimeDeclaration(OpBuilder &b, Operation *op,
                                    ::osl::abi::EntryPoint<Fn> entry) {
  return runtimeDeclaration(b, op, entry.name,
                            abiFunctionType(b.getContext(), static_cast<Fn *>(nullptr)));
}
/// A stack block of `count` 32-bit values in the function's entry block,
/// so a call inside a loop reuses it.
Value entryBlockRows(OpBuilder &b, Location loc, Operation *op, int64_t count);
/// A lane mask (i1 or vector<W x i1>) as the bits of an i32, lane i at bit i.
Value maskBits(OpBuilder &b, Location loc, Value mask);
/// A call's file:line:col for run-time errors, or `fallback`.
std::string callSiteText(Location loc, StringRef fallback);
/// "file:line" of a call, as OSL names the places of messages.
std::string callSiteLine(Location loc);
Value i32Constant(OpBuilder &b, Location loc, int64_t v);
/// Stores the lanes of `original`'s operands (converted: `converted`) as
/// rows of `lanes` 32-bit values in a stack block with `extraRows` more rows
/// after them (OslAbi/Strings.h's layout); returns the block and
/// the index of the first extra row.
std::pair<Value, int64_t> operandRows(OpBuilder &b, Location loc, Operation *op,
                                      ValueRange original, ValueRange converted,
                                      StringRef kinds, int64_t width, bool varying,
                                      int64_t extraRows);
/// The active points of a side-effecting op: the batch's, and its mask's.
Value sideEffectLanes(OpBuilder &b, Location loc, Operation *op, Value inner, int64_t width);

//===----------------------------------------------------------------------===//
// The patterns, one function per file
//===----------------------------------------------------------------------===//

/// Globals loaded from their rows, outputs stored to theirs (`outputRow`:
/// each osl.output's first row) (KernelSignature.cpp).
void populateKernelPatterns(const VaryingTypeConverter &converter, RewritePatternSet &patterns,
                            const llvm::DenseMap<Operation *, int64_t> &outputRow);
/// Gives the shader function the batch-kernel signature.
void makeKernelSignature(func::FuncOp func);
/// A kernel that passes messages starts each batch without any.
void resetMessagesOnEntry(ModuleOp module, func::FuncOp kernel);

/// Arithmetic, math, comparisons, conversions, element access, masks and
/// derivative requests (`referenceMode`: every value is uniform, keep
/// their derivatives) (LaneOps.cpp).
void populateLaneOpPatterns(const VaryingTypeConverter &converter, RewritePatternSet &patterns,
                            bool referenceMode);

/// Reports spline/splineinverse calls whose knot count is a constant out of
/// range; failure when there are any.
LogicalResult checkSplineKnotCounts(Operation *root);

/// Geometry, hashes, transforms, colors and splines through their lane
/// builders (LibraryCalls.cpp).
void populateLibraryCallPatterns(const VaryingTypeConverter &converter,
                                 RewritePatternSet &patterns);

/// What decides whether a library routine's code is built (NoiseCalls.cpp):
/// the noises and splineinverses a derivative request depends on (their
/// code is differentiated), and which compiled routines are at hand.
struct LibraryRoutineNeeds {
  LibraryRoutineNeeds(Operation *root, LibraryObjectAvailable available, bool referenceMode);
  /// Whether the routine of `recipe`, kept as a call, needs its code: when
  /// nothing compiled is at hand, or when a derivative goes through it
  /// (`differentiated`) that its compiled dual cannot serve
  /// (osl-derivatives builds the dual from the code, or copies the code in
  /// place along z).
  bool needCode(StringRef recipe, bool differentiated) const;
  DenseSet<Operation *> derivativeOf;
  /// Whether derivatives go through routines' code in place rather than
  /// dual routines (osl-derivatives): along z, or in reference mode.
  bool inPlaceDerivatives = false;
  LibraryObjectAvailable available;
};

/// Noise as calls of a library function per recipe (NoiseCalls.cpp).
void populateNoisePatterns(const VaryingTypeConverter &converter, RewritePatternSet &patterns,
                           const LibraryRoutineNeeds &needs);

/// splineinverse as calls of a library function per recipe (LibraryCalls.cpp).
void populateSplineInversePatterns(const VaryingTypeConverter &converter,
                                   RewritePatternSet &patterns, const LibraryRoutineNeeds &needs);

/// Closure construction, products and sums (Closures.cpp).
void populateClosurePatterns(const VaryingTypeConverter &converter,
                             RewritePatternSet &patterns);

/// The ops that call the runtime: string constants and calls, printing,
/// messages, lane counting, texture lookups and gettextureinfo
/// (RuntimeCalls.cpp).
void populateRuntimeCallPatterns(const VaryingTypeConverter &converter,
                                 RewritePatternSet &patterns);

} // namespace mlir::osl::lowering

#endif // OSLCONVERSION_OSLTOVECTOR_H
