//===- LoweringSupport.cpp - Helpers of osl-convert-to-vector -------------===//
#include "OslToVector.h"

#include "OslAbi/Strings.h"

#include "mlir/Dialect/Arith/IR/Arith.h"
#include "mlir/Dialect/Func/IR/FuncOps.h"

namespace mlir::osl::lowering {

/// The kernel's arguments: globals, outputs, nactive.
Value kernelArg(Operation *op, unsigned i) {
  return op->getParentOfType<func::FuncOp>().getArgument(i);
}

/// Lanes [0, nactive): lane index < nactive.
Value activeLanes(OpBuilder &b, Location loc, Operation *op, int64_t width) {
  auto indexType = VectorType::get({width}, b.getI32Type());
  SmallVector<int32_t> iota(width);
  for (int64_t i = 0; i < width; ++i)
    iota[i] = i;
  Value lanes = b.create<arith::ConstantOp>(
      loc, DenseElementsAttr::get(indexType, ArrayRef<int32_t>(iota)));
  Value n = lane::broadcast(b, loc, kernelArg(op, 2), width);
  return b.create<arith::CmpIOp>(loc, arith::CmpIPredicate::slt, lanes, n);
}

/// Address of row `row` of a structure-of-arrays block of W-float rows.
Value rowAddress(OpBuilder &b, Location loc, Value base, int64_t row,
                 int64_t width) {
  auto ptr = LLVM::LLVMPointerType::get(b.getContext());
  return b.create<LLVM::GEPOp>(loc, ptr, b.getF32Type(), base,
                               ArrayRef<LLVM::GEPArg>{int32_t(row * width)});
}

Value loadResultRow(OpBuilder &b, Location loc, Value base, int64_t row, int64_t width,
                    Type element) {
  auto load = b.create<LLVM::LoadOp>(loc, VectorType::get({width}, element),
                                     rowAddress(b, loc, base, row, width), 4);
  load->setAttr(kNoDerivativeAttr, b.getUnitAttr());
  return load.getResult();
}

/// Declares runtime function `name` in the module once.
LLVM::LLVMFuncOp runtimeDeclaration(OpBuilder &b, Operation *op, StringRef name,
                                    LLVM::LLVMFunctionType type) {
  auto module = op->getParentOfType<ModuleOp>();
  if (auto f = module.lookupSymbol<LLVM::LLVMFuncOp>(name))
    return f;
  OpBuilder::InsertionGuard guard(b);
  b.setInsertionPointToStart(module.getBody());
  return b.create<LLVM::LLVMFuncOp>(op->getLoc(), name, type);
}

/// A stack block of `count` 32-bit values in the function's entry block,
/// so a call inside a loop reuses it.
Value entryBlockRows(OpBuilder &b, Location loc, Operation *op, int64_t count) {
  OpBuilder::InsertionGuard guard(b);
  b.setInsertionPointToStart(&op->getParentOfType<func::FuncOp>().getBody().front());
  Value size = b.create<LLVM::ConstantOp>(loc, b.getI64Type(), b.getI64IntegerAttr(count));
  return b.create<LLVM::AllocaOp>(loc, LLVM::LLVMPointerType::get(b.getContext()),
                                  b.getI32Type(), size, 64);
}

/// A lane mask (i1 or vector<W x i1>) as the bits of an i32, lane i at bit i.
Value maskBits(OpBuilder &b, Location loc, Value mask) {
  Type i32 = b.getI32Type();
  auto vec = dyn_cast<VectorType>(mask.getType());
  if (!vec)
    return b.create<arith::ExtUIOp>(loc, i32, mask);
  Type bits = b.getIntegerType(vec.getNumElements());
  Value packed = b.create<LLVM::BitcastOp>(loc, bits, mask);
  if (vec.getNumElements() == 32)
    return packed;
  return b.create<arith::ExtUIOp>(loc, i32, packed);
}

/// A call's file:line:col for run-time errors, or `fallback`.
std::string callSiteText(Location loc, StringRef fallback) {
  auto fileLoc = dyn_cast<FileLineColLoc>(loc);
  if (!fileLoc)
    return fallback.str();
  return (fileLoc.getFilename().getValue() + ":" + llvm::Twine(fileLoc.getLine()) + ":" +
          llvm::Twine(fileLoc.getColumn()))
      .str();
}

/// Stores the lanes of `original`'s operands (converted: `converted`) as
/// rows of `lanes` 32-bit values in a stack block with `extraRows` more rows
/// after them (OslAbi/Strings.h's layout); returns the block and
/// the index of the first extra row.
std::pair<Value, int64_t> operandRows(OpBuilder &b, Location loc, Operation *op,
                                      ValueRange original, ValueRange converted,
                                      StringRef kinds, int64_t width, bool varying,
                                      int64_t extraRows) {
  int64_t lanes = varying ? width : 1;
  int64_t rows = extraRows;
  for (char k : kinds)
    rows += ::osl::stringOperandRows(k);
  Value block = entryBlockRows(b, loc, op, rows * lanes);
  Components unpacker{b, loc, width};
  int64_t row = 0;
  for (auto [o, c] : llvm::zip(original, converted))
    for (Value comp : unpacker.unpack(c, o.getType(), varying))
      b.create<LLVM::StoreOp>(loc, comp, rowAddress(b, loc, block, row++, lanes), 4);
  return {block, row};
}

Value i32Constant(OpBuilder &b, Location loc, int64_t v) {
  return b.create<arith::ConstantIntOp>(loc, v, 32).getResult();
}

/// The active points of a side-effecting op: the batch's, and its mask's.
Value sideEffectLanes(OpBuilder &b, Location loc, Operation *op, Value inner,
                      int64_t width) {
  Value mask = activeLanes(b, loc, op, width);
  if (!inner)
    return mask;
  if (!isa<VectorType>(inner.getType()))
    inner = lane::broadcast(b, loc, inner, width);
  return b.create<arith::AndIOp>(loc, mask, inner);
}

/// "file:line" of a call, as OSL names the places of messages.
std::string callSiteLine(Location loc) {
  auto fileLoc = dyn_cast<FileLineColLoc>(loc);
  if (!fileLoc)
    return "<unknown>";
  return (fileLoc.getFilename().getValue() + ":" + llvm::Twine(fileLoc.getLine())).str();
}

} // namespace mlir::osl::lowering
