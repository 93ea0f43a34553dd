//===- LibraryFunctions.cpp - Library routines as functions ---------------===//
#include "OslLanes/LibraryFunctions.h"
#include "OslAbi/Library.h"

#include "mlir/Dialect/Vector/IR/VectorOps.h"
#include "mlir/IR/BuiltinOps.h"
#include "mlir/IR/IRMapping.h"
#include "mlir/IR/Matchers.h"
#include "mlir/IR/SymbolTable.h"
#include "llvm/ADT/StringExtras.h"
#include "llvm/Support/xxhash.h"

using namespace mlir;

func::FuncOp mlir::osl::libraryFunction(
    OpBuilder &b, Operation *anchor, StringRef routine, StringRef recipe, FunctionType type,
    bool needCode, function_ref<bool()> compiled,
    function_ref<SmallVector<Value>(OpBuilder &, ValueRange)> build) {
  // Named by the recipe's hash: the same name in every process, and the
  // name of the compiled object's symbol.
  std::string name = ::osl::abi::kLibrarySymbolPrefix + routine.str() + "." +
                     llvm::utohexstr(llvm::xxh3_64bits(recipe), /*LowerCase=*/true, 16);
  auto module = anchor->getParentOfType<ModuleOp>();
  auto func = dyn_cast_or_null<func::FuncOp>(SymbolTable::lookupSymbolIn(module, name));
  OpBuilder::InsertionGuard guard(b);
  bool define = needCode;
  if (!func) {
    b.setInsertionPointToEnd(module.getBody());
    func = b.create<func::FuncOp>(anchor->getLoc(), name, type);
    func.setPrivate();
    func->setAttr(kLibraryRecipeAttr, b.getStringAttr(recipe));
    define = needCode || !compiled();
  }
  if (define && func.isDeclaration()) {
    Block *entry = func.addEntryBlock();
    b.setInsertionPointToStart(entry);
    SmallVector<Value> results = build(b, entry->getArguments());
    b.create<func::ReturnOp>(anchor->getLoc(), results);
  }
  return func;
}

func::FuncOp mlir::osl::libraryCallee(func::CallOp call) {
  auto callee = dyn_cast_or_null<func::FuncOp>(
      SymbolTable::lookupNearestSymbolFrom(call, call.getCalleeAttr()));
  return callee && callee->hasAttr(kLibraryRecipeAttr) ? callee : func::FuncOp();
}

func::ReturnOp mlir::osl::cloneBody(OpBuilder &b, func::FuncOp callee, ValueRange args) {
  IRMapping map;
  map.map(callee.getArguments(), args);
  Operation *last = nullptr;
  for (Operation &op : callee.getBody().front())
    last = b.clone(op, map);
  return cast<func::ReturnOp>(last);
}

SmallVector<Value> mlir::osl::inlineCall(func::CallOp call, func::FuncOp callee) {
  OpBuilder b(call);
  func::ReturnOp copied = cloneBody(b, callee, call.getOperands());
  SmallVector<Value> results(copied.getOperands());
  copied.erase();
  call.replaceAllUsesWith(results);
  call.erase();
  return results;
}

bool mlir::osl::isConstantOperand(Value v) {
  if (auto broadcast = v.getDefiningOp<vector::BroadcastOp>())
    v = broadcast.getSource();
  return matchPattern(v, m_Constant());
}
