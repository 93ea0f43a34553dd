//===- InlineLibrary.cpp - Which library calls go back in place ----------===//
//
// Library routines (noise of every kind, spline inversion) are private
// functions built from a recipe, one per routine and signature, which the
// JIT compiles once and keeps as objects across shaders. A small one costs
// less copied in place than called; this pass decides where.
//
//===----------------------------------------------------------------------===//
#include "OslLanes/LibraryFunctions.h"
#include "OslTransforms/Passes.h"

#include "mlir/Dialect/Func/IR/FuncOps.h"
#include "mlir/IR/SymbolTable.h"
#include "mlir/Interfaces/LoopLikeInterface.h"
#include "llvm/ADT/MapVector.h"

namespace mlir::osl {
#define GEN_PASS_DEF_INLINELIBRARY
#include "OslTransforms/Passes.h.inc"
} // namespace mlir::osl

using namespace mlir;
using namespace mlir::osl;

namespace {

/// The ops of `func`'s body, or nothing when it has a loop or branch (a
/// region inside).
std::optional<unsigned> straightLineOps(func::FuncOp func) {
  unsigned ops = 0;
  WalkResult walk = func.getBody().walk([&](Operation *op) {
    if (op->getNumRegions() > 0)
      return WalkResult::interrupt();
    ++ops;
    return WalkResult::advance();
  });
  if (walk.wasInterrupted())
    return std::nullopt;
  return ops;
}

/// Whether `call` passes a constant (or lanes of one): a copy of the
/// callee would fold it.
bool passesConstant(func::CallOp call) {
  return llvm::any_of(call.getOperands(), isConstantOperand);
}

/// Whether `call` runs in a loop, where the spills around it repeat.
bool insideLoop(func::CallOp call) {
  return call->getParentOfType<LoopLikeOpInterface>() != nullptr;
}

struct InlineLibraryPass : public mlir::osl::impl::InlineLibraryBase<InlineLibraryPass> {
  using InlineLibraryBase::InlineLibraryBase;

  void runOnOperation() override {
    ModuleOp module = getOperation();
    SymbolTable symbols(module);
    SmallVector<func::FuncOp> libraryFunctions;
    for (auto func : module.getOps<func::FuncOp>())
      if (func->hasAttr(kLibraryRecipeAttr))
        libraryFunctions.push_back(func);
    if (!keepCalls)
      inlineEveryCall(module, symbols);
    else
      inlineWhereItGains(module, symbols);
    // Routines no call is left to: inlined at each, or each copied in
    // place by osl-derivatives.
    eraseUncalled(module, symbols, libraryFunctions);
  }

  /// Every call of a routine with code, in a kernel, is replaced by the
  /// code; until none is left, since a routine's code may call others
  /// (noise_by_kind calls each kind's), whose calls come in place with it.
  /// (A routine compiled before has no code here: its calls stay.)
  void inlineEveryCall(ModuleOp module, SymbolTable &symbols) {
    for (;;) {
      SmallVector<std::pair<func::CallOp, func::FuncOp>> inKernels;
      module.walk([&](func::CallOp call) {
        auto callee = symbols.lookup<func::FuncOp>(call.getCallee());
        auto caller = call->getParentOfType<func::FuncOp>();
        if (callee && callee->hasAttr(kLibraryRecipeAttr) && !callee.isDeclaration() &&
            !caller->hasAttr(kLibraryRecipeAttr))
          inKernels.push_back({call, callee});
      });
      if (inKernels.empty())
        return;
      for (auto [call, callee] : inKernels)
        inlineCall(call, callee);
    }
  }

  /// A small straight-line function goes back in place: a call clobbers
  /// every vector register, the caller's spills around it cost more than
  /// a hash, and constant arguments fold. Bounded for compile time: its
  /// copies (ops times calls) by inline-ops, and all copies by one budget
  /// per kernel, cheapest first, so a shader calling many different
  /// routines once each keeps the bigger ones as calls. Calls their site
  /// keeps (osl.keep_call) stay.
  void inlineWhereItGains(ModuleOp module, SymbolTable &symbols) {
    llvm::MapVector<func::FuncOp, SmallVector<func::CallOp>> callsOf;
    module.walk([&](func::CallOp call) {
      auto callee = symbols.lookup<func::FuncOp>(call.getCallee());
      if (callee && callee->hasAttr(kLibraryRecipeAttr) && !callee.isDeclaration() &&
          !call->hasAttr(kKeepCallAttr))
        callsOf[callee].push_back(call);
    });
    struct Candidate {
      func::FuncOp func;
      uint64_t cost;
    };
    SmallVector<Candidate> candidates;
    for (auto &[func, calls] : callsOf) {
      std::optional<unsigned> ops = straightLineOps(func);
      // A bigger body is worth its copies only where they fold or where
      // the call repeats: every copy costs the kernel's codegen time,
      // which the prebuilt library's call does not (measured: 1D and 2D
      // Perlin noise shaded as fast called as inline and compiled a third
      // faster; a cell noise called in a loop shaded 14% slower).
      if (ops && (*ops <= inlineAlwaysOps || llvm::any_of(calls, passesConstant) ||
                  llvm::any_of(calls, insideLoop)))
        candidates.push_back({func, uint64_t(*ops) * calls.size()});
    }
    // Stable: equal costs keep the order of first call, the same in every run.
    std::stable_sort(candidates.begin(), candidates.end(),
                     [](const Candidate &a, const Candidate &b) { return a.cost < b.cost; });
    uint64_t budget = inlineBudget;
    for (const Candidate &c : candidates) {
      if (c.cost > inlineOps || c.cost > budget)
        break;
      budget -= c.cost;
      for (func::CallOp call : callsOf[c.func])
        inlineCall(call, c.func);
    }
  }

  /// Erases those of `funcs` no call is left to (one walk a round), again
  /// while erasing one leaves others uncalled (calls between routines). A
  /// routine compiled before lists the routines its object calls
  /// (osl.library_callees): they stay, to be linked beside it.
  static void eraseUncalled(ModuleOp module, SymbolTable &symbols,
                            ArrayRef<func::FuncOp> funcs) {
    SmallVector<func::FuncOp> left(funcs);
    for (bool erased = true; erased;) {
      erased = false;
      DenseSet<StringAttr> called;
      module.walk([&](func::CallOp call) { called.insert(call.getCalleeAttr().getAttr()); });
      for (auto func : module.getOps<func::FuncOp>())
        if (auto callees = func->getAttrOfType<ArrayAttr>(kLibraryCalleesAttr))
          for (auto callee : callees.getAsRange<FlatSymbolRefAttr>())
            called.insert(callee.getAttr());
      for (func::FuncOp &func : left)
        if (func && !called.contains(func.getSymNameAttr())) {
          symbols.erase(func);
          func = nullptr;
          erased = true;
        }
    }
  }
};

} // namespace
