//===- RuntimeCalls.cpp - osl ops that call the runtime --------------------===//
//
// Each writes its operands' lanes to a stack block of rows, calls its
// runtime entry point (OslAbi/EntryPoints.h; the tables are OslAbi/Strings.h,
// Print.h and Texture.h) for the active lanes, and reads its results back
// from rows.
//
//===----------------------------------------------------------------------===//
#include "OslToVector.h"

#include "OslAbi/PointCloud.h"
#include "OslAbi/Print.h"
#include "OslAbi/Strings.h"
#include "OslAbi/Texture.h"
#include "OslLanes/ConstantTable.h"

#include "mlir/Dialect/Arith/IR/Arith.h"
#include "mlir/Dialect/Func/IR/FuncOps.h"
#include "mlir/Dialect/Vector/IR/VectorOps.h"

using namespace mlir;
using namespace mlir::osl;
using namespace mlir::osl::lowering;

namespace {

/// The kernel's slot for the handle of the constant string at `text` (an
/// osl_string_N global): an internal i32 global, -1 until the first batch
/// asks the intern table.
Value internSlotAddress(OpBuilder &b, Location loc, Operation *op, Value text) {
  auto module = op->getParentOfType<ModuleOp>();
  std::string name = (text.getDefiningOp<LLVM::AddressOfOp>().getGlobalName() + "_handle").str();
  auto slot = module.lookupSymbol<LLVM::GlobalOp>(name);
  if (!slot) {
    OpBuilder::InsertionGuard guard(b);
    b.setInsertionPointToStart(module.getBody());
    slot = b.create<LLVM::GlobalOp>(loc, b.getI32Type(), /*isConstant=*/false,
                                    LLVM::Linkage::Internal, name, b.getI32IntegerAttr(-1));
  }
  return b.create<LLVM::AddressOfOp>(loc, slot);
}

/// osl.string_constant: the handle the runtime's intern table gives the
/// text, asked for once and then kept in the kernel's slot for it.
struct StringConstantLowering : public OslPattern<StringConstantOp> {
  using OslPattern::OslPattern;
  LogicalResult matchAndRewrite(StringConstantOp op, OpAdaptor,
                                ConversionPatternRewriter &rewriter) const override {
    Location loc = op.getLoc();
    LLVM::LLVMFuncOp callee =
        runtimeDeclaration(rewriter, op, entry::osl_rt_string_intern_cached);
    Value text = constantStringAddress(rewriter, loc, op.getValue());
    Value slot = internSlotAddress(rewriter, loc, op, text);
    rewriter.replaceOpWithNewOp<LLVM::CallOp>(op, callee, ValueRange{text, slot});
    return success();
  }
};

/// osl.count_lanes: the number of set lanes goes to the runtime's lane
/// statistics (osl_rt_count_lanes, OslAbi/EntryPoints.h).
struct CountLanesLowering : public OslPattern<CountLanesOp> {
  using OslPattern::OslPattern;
  LogicalResult matchAndRewrite(CountLanesOp op, OpAdaptor adaptor,
                                ConversionPatternRewriter &rewriter) const override {
    Location loc = op.getLoc();
    Type i32 = rewriter.getI32Type();
    LLVM::LLVMFuncOp callee = runtimeDeclaration(rewriter, op, entry::osl_rt_count_lanes);
    Value bits = maskBits(rewriter, loc, adaptor.getMask());
    Value count = rewriter.create<LLVM::CtPopOp>(loc, i32, bits);
    rewriter.create<LLVM::CallOp>(loc, callee, ValueRange{count});
    rewriter.eraseOp(op);
    return success();
  }
};

/// osl.string_call: the operands' lanes go to a block of 32-bit rows
/// (OslAbi/Strings.h), osl_rt_string_call runs the active lanes and
/// the result row is read back. Uniform operands and result: one lane.
struct StringCallLowering : public OslPattern<StringCallOp> {
  using OslPattern::OslPattern;
  LogicalResult matchAndRewrite(StringCallOp op, OpAdaptor adaptor,
                                ConversionPatternRewriter &rewriter) const override {
    Location loc = op.getLoc();
    bool varying = isVarying(op.getType());
    if (varying && op.getCallee() == "getchar" && !isVarying(op.getArgs()[0].getType())) {
      rewriter.replaceOp(op, getcharOfUniformString(rewriter, loc, op, adaptor.getArgs()[0],
                                                    adaptor.getArgs()[1]));
      return success();
    }
    int64_t lanes = varying ? width : 1;
    StringRef kinds = op.getKinds();
    auto [block, resultRow] = operandRows(rewriter, loc, op, op.getArgs(), adaptor.getArgs(),
                                          kinds, width, varying, /*extraRows=*/1);
    Value mask = varying ? activeLanes(rewriter, loc, op, width)
                         : rewriter.create<arith::ConstantIntOp>(loc, 1, 1).getResult();
    LLVM::LLVMFuncOp callee =
        runtimeDeclaration(rewriter, op, entry::osl_rt_string_call);
    SmallVector<Value> args = {
        constantStringAddress(rewriter, loc, callSiteText(loc, op.getCallee())),
        i32Constant(rewriter, loc, ::osl::stringFunctionCode(op.getCallee())),
        constantStringAddress(rewriter, loc, kinds),
        block,
        i32Constant(rewriter, loc, lanes),
        maskBits(rewriter, loc, mask)};
    rewriter.create<LLVM::CallOp>(loc, callee, args);

    Type base = getUniformType(op.getType());
    Type laneType = varying ? Type(VectorType::get({lanes}, base)) : base;
    auto load = rewriter.create<LLVM::LoadOp>(
        loc, laneType, rowAddress(rewriter, loc, block, resultRow, lanes), 4);
    load->setAttr(kNoDerivativeAttr, rewriter.getUnitAttr());
    rewriter.replaceOp(op, load.getResult());
    return success();
  }

private:
  /// getchar(s, i) with one string for the batch (draw_string's text): the
  /// string's bytes are asked for once and each lane's byte gathered, 0
  /// where i is outside the string, as the runtime's getchar answers.
  Value getcharOfUniformString(ConversionPatternRewriter &rewriter, Location loc,
                               StringCallOp op, Value handle, Value index) const {
    Type i32 = rewriter.getI32Type(), i8 = rewriter.getI8Type();
    auto ptr = LLVM::LLVMPointerType::get(rewriter.getContext());
    LLVM::LLVMFuncOp callee = runtimeDeclaration(rewriter, op, entry::osl_rt_string_bytes);
    Value lengthSlot = entryBlockRows(rewriter, loc, op, 1);
    Value bytes =
        rewriter.create<LLVM::CallOp>(loc, callee, ValueRange{handle, lengthSlot}).getResult();
    Value length = rewriter.create<LLVM::LoadOp>(loc, i32, lengthSlot, 4);
    auto lanes = VectorType::get({width}, i32);
    if (!isa<VectorType>(index.getType()))
      index = rewriter.create<vector::SplatOp>(loc, lanes, index);
    Value zero = rewriter.create<arith::ConstantOp>(loc, rewriter.getZeroAttr(lanes));
    Value lengths = rewriter.create<vector::SplatOp>(loc, lanes, length);
    Value inString = rewriter.create<arith::AndIOp>(
        loc, rewriter.create<arith::CmpIOp>(loc, arith::CmpIPredicate::sge, index, zero),
        rewriter.create<arith::CmpIOp>(loc, arith::CmpIPredicate::slt, index, lengths));
    Value read = rewriter.create<arith::AndIOp>(loc, inString, activeLanes(rewriter, loc, op, width));
    Value addrs = rewriter.create<LLVM::GEPOp>(loc, LLVM::getVectorType(ptr, width), i8, bytes,
                                               ValueRange{index});
    auto byteLanes = VectorType::get({width}, i8);
    Value noBytes = rewriter.create<arith::ConstantOp>(loc, rewriter.getZeroAttr(byteLanes));
    Operation *gather = rewriter.create<LLVM::masked_gather>(
        loc, byteLanes, addrs, read, ValueRange{noBytes}, rewriter.getI32IntegerAttr(1));
    gather->setAttr(kNoDerivativeAttr, rewriter.getUnitAttr());
    // A byte is a (signed) char, as the runtime's getchar and OSL's answer it.
    return rewriter.create<arith::ExtSIOp>(loc, lanes, gather->getResult(0));
  }
};

/// osl.print: every active point prints, so the operands always take W
/// lanes; osl_rt_print formats each (OslAbi/Print.h).
struct PrintLowering : public OslPattern<PrintOp> {
  using OslPattern::OslPattern;
  LogicalResult matchAndRewrite(PrintOp op, OpAdaptor adaptor,
                                ConversionPatternRewriter &rewriter) const override {
    Location loc = op.getLoc();
    StringRef kinds = op.getKinds();
    Value block = operandRows(rewriter, loc, op, op.getArgs(), adaptor.getArgs(), kinds,
                              width, /*varying=*/true, /*extraRows=*/0)
                      .first;
    Value mask = sideEffectLanes(rewriter, loc, op, adaptor.getMask(), width);
    LLVM::LLVMFuncOp callee = runtimeDeclaration(rewriter, op, entry::osl_rt_print);
    SmallVector<Value> args = {
        constantStringAddress(rewriter, loc, callSiteText(loc, op.getStream())),
        i32Constant(rewriter, loc, ::osl::printStreamCode(op.getStream())),
        constantStringAddress(rewriter, loc, kinds),
        block,
        i32Constant(rewriter, loc, width),
        maskBits(rewriter, loc, mask)};
    rewriter.create<LLVM::CallOp>(loc, callee, args);
    rewriter.eraseOp(op);
    return success();
  }
};

/// osl.set_message and osl.get_message: the value's rows go to
/// osl_rt_setmessage / osl_rt_getmessage (OslAbi/EntryPoints.h), which
/// keep the batch's messages; getmessage reads the rows back.
template <typename OpTy>
struct MessageLowering : public OslPattern<OpTy> {
  using OslPattern<OpTy>::OslPattern;
  LogicalResult matchAndRewrite(OpTy op, typename OpTy::Adaptor adaptor,
                                ConversionPatternRewriter &rewriter) const override {
    constexpr bool isGet = std::is_same_v<OpTy, GetMessageOp>;
    Location loc = op.getLoc();
    int64_t width = this->width;
    ValueRange original, converted;
    if constexpr (isGet)
      original = op.getCurrent(), converted = adaptor.getCurrent();
    else
      original = op.getValues(), converted = adaptor.getValues();
    auto [rowBlock, foundRow] = operandRows(rewriter, loc, op, original, converted,
                                            op.getKinds(), width, /*varying=*/true,
                                            /*extraRows=*/isGet ? 1 : 0);
    // A plain local: C++17 lambdas cannot capture structured bindings.
    Value block = rowBlock;
    Value mask = sideEffectLanes(rewriter, loc, op, adaptor.getMask(), width);
    Type i32 = rewriter.getI32Type();
    LLVM::LLVMFuncOp callee = isGet ? runtimeDeclaration(rewriter, op, entry::osl_rt_getmessage)
              : runtimeDeclaration(rewriter, op, entry::osl_rt_setmessage);
    SmallVector<Value> args = {constantStringAddress(rewriter, loc, callSiteLine(loc)),
                               constantStringAddress(rewriter, loc, op.getName()),
                               constantStringAddress(rewriter, loc, op.getTypeName()),
                               constantStringAddress(rewriter, loc, op.getKinds()),
                               block,
                               i32Constant(rewriter, loc, width),
                               maskBits(rewriter, loc, mask)};
    rewriter.create<LLVM::CallOp>(loc, callee, args);
    if constexpr (!isGet) {
      rewriter.eraseOp(op);
      return success();
    } else {
      auto loadRow = [&](int64_t row, Type element) {
        return loadResultRow(rewriter, loc, block, row, width, element);
      };
      SmallVector<Value> results = {loadRow(foundRow, i32)};
      Components packer{rewriter, loc, width};
      int64_t row = 0;
      for (auto [k, value] : llvm::enumerate(op.getValues())) {
        Type resultType = this->convert(value.getType());
        char kind = op.getKinds()[k];
        Type element = kind == 'f' || kind == 't' ? Type(rewriter.getF32Type()) : i32;
        SmallVector<Value> rows;
        for (int32_t r = 0; r < ::osl::stringOperandRows(kind); ++r)
          rows.push_back(loadRow(row++, element));
        results.push_back(packer.pack(rows, resultType));
      }
      rewriter.replaceOp(op, results);
      return success();
    }
  }
};

/// osl.pointcloud: inputs and the output arrays' elements go to rows,
/// osl_rt_pointcloud runs the active lanes, and each element comes back
/// from its row where the runtime wrote it (its index below the `written`
/// row), else it stays as it was, derivatives included: OSL zeroes the
/// derivatives of the elements a lookup fills and no others.
struct PointCloudLowering : public OslPattern<PointCloudOp> {
  using OslPattern::OslPattern;
  LogicalResult matchAndRewrite(PointCloudOp op, OpAdaptor adaptor,
                                ConversionPatternRewriter &rewriter) const override {
    Location loc = op.getLoc();
    auto arrays = ::osl::parsePointCloudLayout(op.getLayout());
    if (!arrays)
      return op.emitError("malformed point-cloud layout");
    SmallVector<Value> original(op.getInputs()), converted(adaptor.getInputs());
    llvm::append_range(original, op.getCurrent());
    llvm::append_range(converted, adaptor.getCurrent());
    auto [rowBlock, statusRow] = operandRows(rewriter, loc, op, original, converted,
                                             op.getKinds(), width, /*varying=*/true,
                                             /*extraRows=*/2);
    Value block = rowBlock;
    Value mask = sideEffectLanes(rewriter, loc, op, adaptor.getMask(), width);
    LLVM::LLVMFuncOp callee = runtimeDeclaration(rewriter, op, entry::osl_rt_pointcloud);
    SmallVector<Value> args = {
        i32Constant(rewriter, loc,
                    static_cast<int32_t>(*::osl::pointCloudFunction(op.getFunction()))),
        constantStringAddress(rewriter, loc, op.getLayout()),
        constantStringAddress(rewriter, loc, op.getKinds()),
        block,
        i32Constant(rewriter, loc, width),
        maskBits(rewriter, loc, mask)};
    rewriter.create<LLVM::CallOp>(loc, callee, args);

    Type i32 = rewriter.getI32Type();
    auto loadRow = [&](int64_t row, Type element) {
      return loadResultRow(rewriter, loc, block, row, width, element);
    };
    Value written = loadRow(statusRow + 1, i32);
    SmallVector<Value> results = {loadRow(statusRow, i32), written};
    Components components{rewriter, loc, width};
    int64_t row = 0;
    for (Value input : op.getInputs())
      row += isTriple(getUniformType(input.getType())) ? 3 : 1;
    size_t element = 0;
    for (const ::osl::PointCloudArray &array : *arrays) {
      for (int32_t k = 0; k < array.length && element < op.getCurrent().size(); ++k, ++element) {
        Value current = op.getCurrent()[element];
        Value filled = rewriter.create<arith::CmpIOp>(
            loc, arith::CmpIPredicate::sgt, written,
            lane::broadcast(rewriter, loc, i32Constant(rewriter, loc, k), width));
        SmallVector<Value> rows;
        for (Value was : components.unpack(adaptor.getCurrent()[element], current.getType(),
                                           /*varying=*/true)) {
          Value now = loadRow(row++, cast<VectorType>(was.getType()).getElementType());
          rows.push_back(rewriter.create<arith::SelectOp>(loc, filled, now, was));
        }
        results.push_back(components.pack(rows, convert(op.getValues()[element].getType())));
      }
    }
    rewriter.replaceOp(op, results);
    return success();
  }
};

/// osl.texture: the per-point values go to a block of rows on the stack
/// (OslAbi/Texture.h), osl_rt_texture looks the lanes up, and the
/// results are read back. The options OpenImageIO takes once per call are
/// compile-time candidates picked by a uniform index.
struct TextureLowering : public OslPattern<TextureOp> {
  using OslPattern::OslPattern;
  LogicalResult matchAndRewrite(TextureOp op, OpAdaptor adaptor,
                                ConversionPatternRewriter &rewriter) const override {
    Location loc = op.getLoc();
    for (Value c : op.getChoices())
      if (isVarying(c.getType()))
        return op.emitError("texture options chosen per point must be split into lane "
                            "groups first (osl-lane-group-filter)");
    bool varying = isVarying(op.getResult().getType());
    int64_t lanes = varying ? width : 1;
    MLIRContext *ctx = rewriter.getContext();
    auto ptr = LLVM::LLVMPointerType::get(ctx);
    Type f32 = rewriter.getF32Type(), i32 = rewriter.getI32Type();
    LLVM::LLVMFuncOp callee = runtimeDeclaration(rewriter, op, entry::osl_rt_texture);
    Value block = entryBlockRows(rewriter, loc, op, ::osl::kTextureRows * lanes);
    Components unpacker{rewriter, loc, width};
    auto storeRow = [&](int64_t row, Value original, Value converted) {
      Value v = unpacker.unpack(converted, original.getType(), varying)[0];
      rewriter.create<LLVM::StoreOp>(loc, v, rowAddress(rewriter, loc, block, row, lanes), 4);
    };
    for (auto [i, v] : llvm::enumerate(op.getCoords()))
      storeRow(::osl::kTextureCoordRow + i, v, adaptor.getCoords()[i]);
    for (auto [i, v] : llvm::enumerate(op.getDerivs()))
      storeRow(::osl::kTextureDerivRow + i, v, adaptor.getDerivs()[i]);
    for (auto [i, v] : llvm::enumerate(op.getFloatOptions()))
      storeRow(::osl::kTextureOptionRow + i, v, adaptor.getFloatOptions()[i]);
    storeRow(::osl::kTextureFirstChannelRow, op.getFirstchannel(), adaptor.getFirstchannel());
    if (op.getFileHandle())
      storeRow(::osl::kTextureFileRow, op.getFileHandle(), adaptor.getFileHandle());

    // The uniform options: a string's address, or OpenImageIO's code for it.
    auto candidates = [&](int which) { return cast<ArrayAttr>(op.getCandidates()[which]); };
    auto pick = [&](int which, auto valueOf) {
      Value index = adaptor.getChoices()[which];
      ArrayAttr names = candidates(which);
      Value picked = valueOf(cast<StringAttr>(names[0]).getValue());
      for (unsigned k = 1; k < names.size(); ++k) {
        Value isK = rewriter.create<arith::CmpIOp>(
            loc, arith::CmpIPredicate::eq, index,
            rewriter.create<arith::ConstantIntOp>(loc, k, 32));
        picked = rewriter.create<LLVM::SelectOp>(
            loc, isK, valueOf(cast<StringAttr>(names[k]).getValue()), picked);
      }
      return picked;
    };
    auto stringAddress = [&](StringRef s) { return constantStringAddress(rewriter, loc, s); };
    auto wrapCode = [&](StringRef s) -> Value {
      return rewriter.create<arith::ConstantIntOp>(loc, ::osl::textureWrapCode(s), 32);
    };
    auto interpCode = [&](StringRef s) -> Value {
      return rewriter.create<arith::ConstantIntOp>(loc, ::osl::textureInterpCode(s), 32);
    };
    int32_t kind = op.getKind() == TextureKind::texture     ? ::osl::kTexture2D
                   : op.getKind() == TextureKind::texture3d ? ::osl::kTexture3D
                                                            : ::osl::kTextureEnvironment;
    int32_t flags = (op.getHasMissingColor() ? ::osl::kTextureHasMissingColor : 0) |
                    (op.getHasMissingAlpha() ? ::osl::kTextureHasMissingAlpha : 0) |
                    (op.getWantsErrorMessage() ? ::osl::kTextureWantsErrorMessage : 0);
    auto i32Const = [&](int64_t v) {
      return rewriter.create<arith::ConstantIntOp>(loc, v, 32).getResult();
    };
    Value mask = op.getMask() ? adaptor.getMask()
                 : varying    ? activeLanes(rewriter, loc, op, width)
                              : rewriter.create<arith::CmpIOp>(loc, arith::CmpIPredicate::sgt,
                                                               kernelArg(op, 2), i32Const(0))
                                    .getResult();
    if (varying && !isa<VectorType>(mask.getType()))
      mask = lane::broadcast(rewriter, loc, mask, width);
    SmallVector<Value> args = {stringAddress(callSiteText(loc, "texture()")),
                               op.getFileHandle()
                                   ? rewriter.create<LLVM::ZeroOp>(loc, ptr).getResult()
                                   : pick(0, stringAddress),
                               pick(5, stringAddress),
                               adaptor.getSubimage(),
                               i32Const(kind),
                               i32Const(op.getNchannels()),
                               pick(1, wrapCode),
                               pick(2, wrapCode),
                               pick(3, wrapCode),
                               pick(4, interpCode),
                               i32Const(flags),
                               block,
                               i32Const(lanes),
                               maskBits(rewriter, loc, mask)};
    assert(args[::osl::kTextureFlagsArgument].getDefiningOp<arith::ConstantIntOp>().value() ==
               flags &&
           "kTextureFlagsArgument names the flags");
    rewriter.create<LLVM::CallOp>(loc, callee, args);

    auto loadRow = [&](int64_t row, Type element) {
      Type laneType = varying ? Type(VectorType::get({lanes}, element)) : element;
      auto load = rewriter.create<LLVM::LoadOp>(
          loc, laneType, rowAddress(rewriter, loc, block, row, lanes), 4);
      load->setAttr(kNoDerivativeAttr, rewriter.getUnitAttr());
      return load.getResult();
    };
    // A 2D lookup's channels and alpha have derivatives: osl-derivatives
    // finds their slopes in the rows after the call (kTextureDsRow...).
    auto loadResultRow = [&](int64_t row) {
      Value v = loadRow(row, f32);
      if (op.getKind() == TextureKind::texture) {
        Operation *load = v.getDefiningOp();
        load->removeAttr(kNoDerivativeAttr);
        load->setAttr(kTextureResultRowAttr, rewriter.getI64IntegerAttr(row));
      }
      return v;
    };
    SmallVector<Value> channels;
    for (uint32_t c = 0; c < op.getNchannels(); ++c)
      channels.push_back(loadResultRow(::osl::kTextureResultRow + c));
    Value result = unpacker.pack(channels, convert(op.getResult().getType()));
    // Without "errormessage" the row is not written: the message is "".
    Value error = op.getWantsErrorMessage()
                      ? loadRow(::osl::kTextureErrorRow, i32)
                      : rewriter.create<arith::ConstantOp>(
                                    loc, rewriter.getZeroAttr(
                                             convert(op.getErrorMessage().getType())))
                            .getResult();
    rewriter.replaceOp(op, {result, loadResultRow(::osl::kTextureAlphaRow), error});
    return success();
  }
};

/// gettextureinfo: a uniform runtime call that writes its answer to the
/// stack; about files named at run time, one call for the batch that
/// answers per point (rows of W values).
struct GetTextureInfoLowering : public OslPattern<GetTextureInfoOp> {
  using OslPattern::OslPattern;
  LogicalResult matchAndRewrite(GetTextureInfoOp op, OpAdaptor adaptor,
                                ConversionPatternRewriter &rewriter) const override {
    if (op.getFileHandle())
      return lowerPerPoint(op, adaptor, rewriter);
    Location loc = op.getLoc();
    MLIRContext *ctx = rewriter.getContext();
    auto ptr = LLVM::LLVMPointerType::get(ctx);
    Type i32 = rewriter.getI32Type();
    Type element = op.getFloats() ? Type(rewriter.getF32Type()) : i32;
    int64_t count = op.getValues().size();
    Value data = entryBlockRows(rewriter, loc, op, count);
    LLVM::LLVMFuncOp callee = runtimeDeclaration(rewriter, op, entry::osl_rt_gettextureinfo);
    auto i32Const = [&](int64_t v) {
      return rewriter.create<arith::ConstantIntOp>(loc, v, 32).getResult();
    };
    Value found = rewriter
                      .create<LLVM::CallOp>(loc, callee,
                                            ValueRange{constantStringAddress(rewriter, loc, op.getFile()),
                                                       constantStringAddress(rewriter, loc, op.getName()),
                                                       i32Const(op.getFloats()    ? ::osl::kTextureInfoFloat
                                                                : op.getStrings() ? ::osl::kTextureInfoString
                                                                                  : ::osl::kTextureInfoInt),
                                                       i32Const(count), data})
                      .getResult();
    SmallVector<Value> results = {found};
    for (int64_t k = 0; k < count; ++k) {
      Value addr = rewriter.create<LLVM::GEPOp>(loc, ptr, element, data,
                                                ArrayRef<LLVM::GEPArg>{int32_t(k)});
      auto load = rewriter.create<LLVM::LoadOp>(loc, element, addr, 4);
      load->setAttr(kNoDerivativeAttr, rewriter.getUnitAttr());
      results.push_back(load);
    }
    rewriter.replaceOp(op, results);
    return success();
  }

  LogicalResult lowerPerPoint(GetTextureInfoOp op, OpAdaptor adaptor,
                              ConversionPatternRewriter &rewriter) const {
    Location loc = op.getLoc();
    Type i32 = rewriter.getI32Type();
    Type element = op.getFloats() ? Type(rewriter.getF32Type()) : i32;
    bool varying = isVarying(op.getFound().getType());
    int64_t lanes = varying ? width : 1;
    int64_t count = op.getValues().size();
    // Rows: the handles, whether found, then the values.
    Value block = entryBlockRows(rewriter, loc, op, (2 + count) * lanes);
    Components unpacker{rewriter, loc, width};
    Value handles = unpacker.unpack(adaptor.getFileHandle(), op.getFileHandle().getType(),
                                    varying)[0];
    rewriter.create<LLVM::StoreOp>(loc, handles, rowAddress(rewriter, loc, block, 0, lanes), 4);
    auto i32Const = [&](int64_t v) {
      return rewriter.create<arith::ConstantIntOp>(loc, v, 32).getResult();
    };
    LLVM::LLVMFuncOp callee =
        runtimeDeclaration(rewriter, op, entry::osl_rt_gettextureinfo_lanes);
    // The batch's points (lanes past its end name nothing).
    Value mask = varying ? activeLanes(rewriter, loc, op, width)
                         : rewriter.create<arith::CmpIOp>(loc, arith::CmpIPredicate::sgt,
                                                          kernelArg(op, 2), i32Const(0))
                               .getResult();
    rewriter.create<LLVM::CallOp>(
        loc, callee,
        ValueRange{rowAddress(rewriter, loc, block, 0, lanes),
                   constantStringAddress(rewriter, loc, op.getName()),
                   i32Const(op.getFloats()    ? ::osl::kTextureInfoFloat
                            : op.getStrings() ? ::osl::kTextureInfoString
                                              : ::osl::kTextureInfoInt),
                   i32Const(count), rowAddress(rewriter, loc, block, 2, lanes),
                   rowAddress(rewriter, loc, block, 1, lanes), i32Const(lanes),
                   maskBits(rewriter, loc, mask)});
    auto loadRow = [&](int64_t row, Type type) {
      Type laneType = varying ? Type(VectorType::get({lanes}, type)) : type;
      auto load = rewriter.create<LLVM::LoadOp>(loc, laneType,
                                                rowAddress(rewriter, loc, block, row, lanes), 4);
      load->setAttr(kNoDerivativeAttr, rewriter.getUnitAttr());
      return load.getResult();
    };
    SmallVector<Value> results = {loadRow(1, i32)};
    for (int64_t k = 0; k < count; ++k)
      results.push_back(loadRow(2 + k, element));
    rewriter.replaceOp(op, results);
    return success();
  }
};

/// osl.udim_tile: rows of the file handles, s and t, and the tiles the
/// runtime writes.
struct UdimTileLowering : public OslPattern<UdimTileOp> {
  using OslPattern::OslPattern;
  LogicalResult matchAndRewrite(UdimTileOp op, OpAdaptor adaptor,
                                ConversionPatternRewriter &rewriter) const override {
    Location loc = op.getLoc();
    bool varying = isVarying(op.getType());
    int64_t lanes = varying ? width : 1;
    Value block = entryBlockRows(rewriter, loc, op, 4 * lanes);
    Components unpacker{rewriter, loc, width};
    auto storeRow = [&](int64_t row, Value converted, Value original) {
      Value v = unpacker.unpack(converted, original.getType(), varying)[0];
      rewriter.create<LLVM::StoreOp>(loc, v, rowAddress(rewriter, loc, block, row, lanes), 4);
    };
    storeRow(0, adaptor.getFile(), op.getFile());
    storeRow(1, adaptor.getS(), op.getS());
    storeRow(2, adaptor.getT(), op.getT());
    Value mask = varying ? activeLanes(rewriter, loc, op, width)
                         : rewriter.create<arith::CmpIOp>(
                                   loc, arith::CmpIPredicate::sgt, kernelArg(op, 2),
                                   rewriter.create<arith::ConstantIntOp>(loc, 0, 32))
                               .getResult();
    LLVM::LLVMFuncOp callee = runtimeDeclaration(rewriter, op, entry::osl_rt_udim_tile_lanes);
    rewriter.create<LLVM::CallOp>(
        loc, callee,
        ValueRange{rowAddress(rewriter, loc, block, 0, lanes),
                   rowAddress(rewriter, loc, block, 1, lanes),
                   rowAddress(rewriter, loc, block, 2, lanes),
                   rowAddress(rewriter, loc, block, 3, lanes),
                   rewriter.create<arith::ConstantIntOp>(loc, lanes, 32),
                   maskBits(rewriter, loc, mask)});
    Type i32 = rewriter.getI32Type();
    Type laneType = varying ? Type(VectorType::get({lanes}, i32)) : i32;
    auto load = rewriter.create<LLVM::LoadOp>(loc, laneType,
                                              rowAddress(rewriter, loc, block, 3, lanes), 4);
    load->setAttr(kNoDerivativeAttr, rewriter.getUnitAttr());
    rewriter.replaceOp(op, load.getResult());
    return success();
  }
};

} // namespace

void mlir::osl::lowering::populateRuntimeCallPatterns(const VaryingTypeConverter &converter,
                                                      RewritePatternSet &patterns) {
  patterns.add<CountLanesLowering, MessageLowering<SetMessageOp>, MessageLowering<GetMessageOp>,
               PointCloudLowering,
               TextureLowering, GetTextureInfoLowering, UdimTileLowering, StringConstantLowering,
               StringCallLowering, PrintLowering>(converter, patterns.getContext());
}
