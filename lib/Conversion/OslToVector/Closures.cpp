//===- Closures.cpp - Closures as runtime calls -----------------------------===//
//
// A closure is an i32 handle into the shading thread's closure arena
// (OslAbi/Closures.h); each closure op is one runtime call per batch on the
// rows of its operands.
//
//===----------------------------------------------------------------------===//
#include "OslToVector.h"

#include "OslAbi/Closures.h"
#include "mlir/Dialect/Arith/IR/Arith.h"

using namespace mlir;
using namespace mlir::osl;
using namespace mlir::osl::lowering;

namespace {

/// Stores `operands` (converted, with their osl types) as 32-bit rows of a
/// block for a closure entry point, calls `callee` with the block, and reads
/// the result row of handles back. Uniform ops run one lane.
Value callClosureEntry(ConversionPatternRewriter &rewriter, Operation *op, int64_t width,
                       LLVM::LLVMFuncOp callee, ArrayRef<Value> leading, ValueRange converted,
                       ValueRange original) {
  Location loc = op->getLoc();
  bool varying = isVarying(op->getResult(0).getType());
  int64_t lanes = varying ? width : 1;
  Components unpacker{rewriter, loc, width};
  SmallVector<Value> rows;
  for (auto [c, o] : llvm::zip(converted, original))
    for (Value comp : unpacker.unpack(c, o.getType(), varying))
      rows.push_back(comp);
  Value block = entryBlockRows(rewriter, loc, op, int64_t(rows.size() + 1) * lanes);
  for (auto [i, comp] : llvm::enumerate(rows))
    rewriter.create<LLVM::StoreOp>(loc, comp, rowAddress(rewriter, loc, block, i, lanes), 4);
  Value mask = varying ? activeLanes(rewriter, loc, op, width)
                       : rewriter.create<arith::ConstantIntOp>(loc, 1, 1).getResult();
  Type i32 = rewriter.getI32Type();
  SmallVector<Value> args(leading.begin(), leading.end());
  args.append({block, rewriter.create<arith::ConstantIntOp>(loc, lanes, 32),
               maskBits(rewriter, loc, mask)});
  rewriter.create<LLVM::CallOp>(loc, callee, args);
  Type laneType = varying ? Type(VectorType::get({lanes}, i32)) : i32;
  auto load = rewriter.create<LLVM::LoadOp>(
      loc, laneType, rowAddress(rewriter, loc, block, int64_t(rows.size()), lanes), 4);
  load->setAttr(kNoDerivativeAttr, rewriter.getUnitAttr());
  return load.getResult();
}

struct ClosureEmptyLowering : public OslPattern<ClosureEmptyOp> {
  using OslPattern::OslPattern;
  LogicalResult matchAndRewrite(ClosureEmptyOp op, OpAdaptor,
                                ConversionPatternRewriter &rewriter) const override {
    rewriter.replaceOpWithNewOp<arith::ConstantIntOp>(op, 0, 32);
    return success();
  }
};

/// osl.closure_component: osl_rt_closure_component(id, rows, lanes, mask).
struct ClosureComponentLowering : public OslPattern<ClosureComponentOp> {
  using OslPattern::OslPattern;
  LogicalResult matchAndRewrite(ClosureComponentOp op, OpAdaptor adaptor,
                                ConversionPatternRewriter &rewriter) const override {
    Value id = rewriter.create<arith::ConstantIntOp>(op.getLoc(),
                                                     ::osl::closureId(op.getName()), 32);
    rewriter.replaceOp(op, callClosureEntry(rewriter, op, width,
                                            runtimeDeclaration(rewriter, op,
                                                               entry::osl_rt_closure_component),
                                            {id}, adaptor.getArgs(), op.getArgs()));
    return success();
  }
};

/// osl.closure_mul and osl.closure_add: their entry point on the operands' rows.
template <typename Op>
struct ClosureArithLowering : public OslPattern<Op> {
  using OslPattern<Op>::OslPattern;
  LogicalResult matchAndRewrite(Op op, typename Op::Adaptor adaptor,
                                ConversionPatternRewriter &rewriter) const override {
    LLVM::LLVMFuncOp callee =
        std::is_same_v<Op, ClosureMulOp>
            ? runtimeDeclaration(rewriter, op, entry::osl_rt_closure_mul)
            : runtimeDeclaration(rewriter, op, entry::osl_rt_closure_add);
    rewriter.replaceOp(op, callClosureEntry(rewriter, op, this->width, callee, {},
                                            adaptor.getOperands(), op->getOperands()));
    return success();
  }
};

} // namespace

void mlir::osl::lowering::populateClosurePatterns(const VaryingTypeConverter &converter,
                                                  RewritePatternSet &patterns) {
  patterns.add<ClosureArithLowering<ClosureMulOp>, ClosureArithLowering<ClosureAddOp>,
               ClosureEmptyLowering, ClosureComponentLowering>(converter, patterns.getContext());
}
