//===- KernelSignature.cpp - The batch kernel: signature, globals, outputs --===//
//
// The shader function becomes void osl_batch(globals, outputs, nactive)
// (OslAbi/GlobalsLayout.h): globals are loaded from their rows, outputs
// stored to theirs for the batch's active points.
//
//===----------------------------------------------------------------------===//
#include "OslToVector.h"

#include "OslAbi/GlobalsLayout.h"
#include "mlir/Dialect/Arith/IR/Arith.h"
#include "mlir/Dialect/Func/IR/FuncOps.h"

using namespace mlir;
using namespace mlir::osl;
using namespace mlir::osl::lowering;

namespace {

/// Lower osl.global to loads of its rows from the globals block.
struct GlobalLowering : public OslPattern<GlobalOp> {
  using OslPattern::OslPattern;
  LogicalResult matchAndRewrite(GlobalOp op, OpAdaptor,
                                ConversionPatternRewriter &rewriter) const override {
    const ::osl::GlobalSlot *slot = ::osl::findGlobal(op.getName().str());
    Location loc = op.getLoc();
    Components lanes{rewriter, loc, width};
    // A uniform global (reference mode, see osl-uniform-reference) is lane 0.
    Type rowType = isVarying(op.getType())
                       ? Type(VectorType::get({width}, rewriter.getF32Type()))
                       : Type(rewriter.getF32Type());
    SmallVector<Value> rows;
    for (int i = 0; i < slot->rows; ++i) {
      Value addr = rowAddress(rewriter, loc, kernelArg(op, 0), slot->row + i, width);
      auto load = rewriter.create<LLVM::LoadOp>(loc, rowType, addr, 4);
      // osl-derivatives finds the derivative rows of what it loads.
      load->setAttr("osl.global_row", rewriter.getI64IntegerAttr(slot->row + i));
      rows.push_back(load);
    }
    rewriter.replaceOp(op, lanes.pack(rows, convert(op.getType())));
    return success();
  }
};

/// Lower osl.output to masked stores of its rows: lanes past nactive are
/// never written. Rows are floats: an int output's row holds its ints' bits
/// (a float holds ints exactly only up to 2^24; hash() values are printed
/// and written to int TIFFs whole), a closure's its handles' bits.
struct OutputLowering : public OslPattern<OutputOp> {
  OutputLowering(const VaryingTypeConverter &converter, MLIRContext *ctx,
                 const llvm::DenseMap<Operation *, int64_t> &firstRow)
      : OslPattern(converter, ctx), firstRow(firstRow) {}
  LogicalResult matchAndRewrite(OutputOp op, OpAdaptor adaptor,
                                ConversionPatternRewriter &rewriter) const override {
    Location loc = op.getLoc();
    Components lanes{rewriter, loc, width};
    SmallVector<Value> rows =
        lanes.unpack(adaptor.getValue(), op.getValue().getType(), /*varying=*/true);
    bool unconditional = isa<func::FuncOp>(op->getParentOp());
    Value mask = unconditional ? Value() : activeLanes(rewriter, loc, op, width);
    bool closure = isa<ClosureType>(getUniformType(op.getValue().getType()));
    auto floatRow = VectorType::get({width}, rewriter.getF32Type());
    for (auto [i, row] : llvm::enumerate(rows)) {
      Value value = row;
      if (auto element = dyn_cast<IntegerType>(getElementTypeOrSelf(row.getType()))) {
        if (element.getWidth() < 32)
          value = rewriter.create<arith::ExtSIOp>(
              loc, VectorType::get({width}, rewriter.getI32Type()), value);
        value = rewriter.create<LLVM::BitcastOp>(loc, floatRow, value);
      } else if (closure) {
        value = rewriter.create<LLVM::BitcastOp>(loc, floatRow, row);
      } else {
        value = lane::convert(rewriter, loc, row, rewriter.getF32Type());
      }
      // One NaN for every NaN: scalar and vector code (and LLVM's folds at
      // each width) may leave different NaN payloads, and the widths must
      // agree bit for bit. A NaN's payload is visible nowhere else; its
      // sign is x86's default NaN's, negative, as testshade's outputs show
      // (-nan from inf - inf).
      if (!closure && isa<FloatType>(getElementTypeOrSelf(row.getType()))) {
        Value nan = lane::constant(rewriter, loc, value.getType(),
                                   -std::numeric_limits<double>::quiet_NaN());
        Value isNan =
            rewriter.create<arith::CmpFOp>(loc, arith::CmpFPredicate::UNO, value, value);
        value = rewriter.create<arith::SelectOp>(loc, isNan, nan, value);
      }
      Value addr = rowAddress(rewriter, loc, kernelArg(op, 1),
                              firstRow.lookup(op) + i, width);
      // The caller owns whole rows and reads only the active lanes, so an
      // output written once at the end of the shader stores every lane:
      // a plain store forwards to the caller's next load of the row, where
      // a masked store makes that load wait until the store has retired.
      if (unconditional)
        rewriter.create<LLVM::StoreOp>(loc, value, addr, 4);
      else
        rewriter.create<LLVM::MaskedStoreOp>(loc, value, addr, mask, 4);
    }
    rewriter.eraseOp(op);
    return success();
  }
  const llvm::DenseMap<Operation *, int64_t> &firstRow;
};

} // namespace

void mlir::osl::lowering::populateKernelPatterns(
    const VaryingTypeConverter &converter, RewritePatternSet &patterns,
    const llvm::DenseMap<Operation *, int64_t> &outputRow) {
  patterns.add<GlobalLowering>(converter, patterns.getContext());
  patterns.add<OutputLowering>(converter, patterns.getContext(), outputRow);
}

/// Gives the shader function the batch-kernel signature.
void mlir::osl::lowering::makeKernelSignature(func::FuncOp func) {
  MLIRContext *ctx = func.getContext();
  auto ptr = LLVM::LLVMPointerType::get(ctx);
  auto i32 = IntegerType::get(ctx, 32);
  func->setAttr("osl.shader_name", StringAttr::get(ctx, func.getSymName()));
  func.setSymName("osl_batch");
  func.setType(FunctionType::get(ctx, {ptr, ptr, i32}, {}));
  Location loc = func.getLoc();
  func.getBody().front().addArguments({ptr, ptr, i32}, {loc, loc, loc});
}


void mlir::osl::lowering::resetMessagesOnEntry(ModuleOp module, func::FuncOp kernel) {
  if (!module.lookupSymbol(entry::osl_rt_setmessage.name) &&
      !module.lookupSymbol(entry::osl_rt_getmessage.name))
    return;
  OpBuilder b(module.getContext());
  b.setInsertionPointToStart(&kernel.getBody().front());
  LLVM::LLVMFuncOp reset = runtimeDeclaration(b, kernel, entry::osl_rt_message_reset);
  b.create<LLVM::CallOp>(kernel.getLoc(), reset, ValueRange{});
}
