//===- ConstantTable.cpp - Per-lane reads of constant tables --------------===//
#include "OslLanes/ConstantTable.h"
#include "OslLanes/LaneMath.h"

#include "mlir/Dialect/Arith/IR/Arith.h"
#include "mlir/IR/BuiltinOps.h"

using namespace mlir;
using namespace mlir::osl;

LLVM::GlobalOp mlir::osl::getConstantTable(OpBuilder &b, Location loc, StringRef symbol,
                                           ArrayRef<float> table) {
  auto module = b.getInsertionBlock()->getParentOp()->getParentOfType<ModuleOp>();
  if (auto existing = module.lookupSymbol<LLVM::GlobalOp>(symbol))
    return existing;
  OpBuilder::InsertionGuard guard(b);
  b.setInsertionPointToStart(module.getBody());
  auto n = int64_t(table.size());
  auto type = LLVM::LLVMArrayType::get(b.getF32Type(), n);
  auto value = DenseElementsAttr::get(RankedTensorType::get({n}, b.getF32Type()), table);
  return b.create<LLVM::GlobalOp>(loc, type, /*isConstant=*/true, LLVM::Linkage::Internal,
                                  symbol, value, /*alignment=*/64);
}

LLVM::GlobalOp mlir::osl::getConstantTable(OpBuilder &b, Location loc,
                                           DenseElementsAttr table) {
  auto module = b.getInsertionBlock()->getParentOp()->getParentOfType<ModuleOp>();
  unsigned count = 0;
  for (auto g : module.getOps<LLVM::GlobalOp>()) {
    if (!g.getSymName().starts_with("osl_table_"))
      continue;
    ++count;
    if (g.getValueOrNull() == table) // attributes are uniqued
      return g;
  }
  OpBuilder::InsertionGuard guard(b);
  b.setInsertionPointToStart(module.getBody());
  auto type = LLVM::LLVMArrayType::get(table.getElementType(), table.getNumElements());
  return b.create<LLVM::GlobalOp>(loc, type, /*isConstant=*/true, LLVM::Linkage::Internal,
                                  "osl_table_" + std::to_string(count), table,
                                  /*alignment=*/64);
}

Value mlir::osl::lookupConstantTable(OpBuilder &b, Location loc, LLVM::GlobalOp global,
                                     Value index) {
  auto ptr = LLVM::LLVMPointerType::get(b.getContext());
  Value base = b.create<LLVM::AddressOfOp>(loc, global);
  Type element = cast<LLVM::LLVMArrayType>(global.getType()).getElementType();
  auto lanes = dyn_cast<VectorType>(index.getType());
  if (!lanes) {
    Value addr = b.create<LLVM::GEPOp>(loc, ptr, element, base, ValueRange{index});
    Operation *load = b.create<LLVM::LoadOp>(loc, element, addr, /*alignment=*/4);
    load->setAttr(kNoDerivativeAttr, b.getUnitAttr());
    return load->getResult(0);
  }
  int64_t width = lanes.getNumElements();
  Value addrs = b.create<LLVM::GEPOp>(loc, LLVM::getVectorType(ptr, width), element, base,
                                      ValueRange{index});
  auto resultType = VectorType::get({width}, element);
  Value all = b.create<arith::ConstantOp>(
      loc, DenseElementsAttr::get(VectorType::get({width}, b.getI1Type()), true));
  Value zero = b.create<arith::ConstantOp>(loc, b.getZeroAttr(resultType));
  Operation *gather = b.create<LLVM::masked_gather>(loc, resultType, addrs, all,
                                                    ValueRange{zero}, b.getI32IntegerAttr(4));
  gather->setAttr(kNoDerivativeAttr, b.getUnitAttr());
  return gather->getResult(0);
}

Value mlir::osl::constantStringAddress(OpBuilder &b, Location loc, StringRef value) {
  auto module = b.getInsertionBlock()->getParentOp()->getParentOfType<ModuleOp>();
  std::string contents = (value + llvm::Twine('\0')).str();
  LLVM::GlobalOp global;
  unsigned count = 0;
  for (auto g : module.getOps<LLVM::GlobalOp>()) {
    if (!g.getSymName().starts_with("osl_string_"))
      continue;
    ++count;
    if (auto s = dyn_cast_or_null<StringAttr>(g.getValueOrNull()); s && s.getValue() == contents)
      global = g;
  }
  if (!global) {
    OpBuilder::InsertionGuard guard(b);
    b.setInsertionPointToStart(module.getBody());
    auto type = LLVM::LLVMArrayType::get(b.getI8Type(), contents.size());
    global = b.create<LLVM::GlobalOp>(loc, type, /*isConstant=*/true, LLVM::Linkage::Internal,
                                      "osl_string_" + std::to_string(count),
                                      b.getStringAttr(contents));
  }
  return b.create<LLVM::AddressOfOp>(loc, global);
}
