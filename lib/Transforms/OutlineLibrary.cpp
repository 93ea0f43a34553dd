//===- OutlineLibrary.cpp - Library regions become kernel functions -------===//
//
// One private function per routine and signature: a kernel calling Perlin
// noise eight times compiles it once, and the JIT reuses its object in
// every kernel that calls the same function. Library regions become such
// functions here; routines built from a recipe are functions already, and
// only the choice of which calls go back in place applies to them.
//
//===----------------------------------------------------------------------===//
#include "OslAbi/Library.h"
#include "OslLanes/LibraryRegion.h"
#include "OslTransforms/Passes.h"

#include "mlir/Dialect/Func/IR/FuncOps.h"
#include "mlir/Dialect/Vector/IR/VectorOps.h"
#include "mlir/IR/IRMapping.h"
#include "mlir/IR/Matchers.h"
#include "mlir/IR/SymbolTable.h"
#include "mlir/Interfaces/LoopLikeInterface.h"
#include "mlir/Transforms/RegionUtils.h"
#include "llvm/ADT/MapVector.h"
#include "llvm/ADT/StringExtras.h"
#include "llvm/ADT/StringMap.h"
#include "llvm/Support/xxhash.h"

namespace mlir::osl {
#define GEN_PASS_DEF_OUTLINELIBRARY
#include "OslTransforms/Passes.h.inc"
} // namespace mlir::osl

using namespace mlir;
using namespace mlir::osl;

namespace {

/// What identifies a region's code: `stable`, a hash of the function type,
/// of the ops' names and of which outside value each use inside reads,
/// is the same in every process (it names the function, and the name is
/// part of the key of the cached object); `exact` also covers the ops'
/// attributes and result types (a builder may specialise on a constant
/// option), for this module only (attributes hash by address).
struct RegionIdentity {
  uint64_t stable;
  llvm::hash_code exact;
};

RegionIdentity identify(scf::ExecuteRegionOp region, FunctionType type,
                        const SetVector<Value> &captured) {
  std::string text;
  llvm::raw_string_ostream os(text);
  os << type;
  DenseMap<Value, int64_t> argOf;
  for (auto [i, v] : llvm::enumerate(captured))
    argOf[v] = int64_t(i);
  llvm::hash_code exact = 0;
  int64_t opIndex = 0;
  region.getRegion().walk([&](Operation *op) {
    os << " " << op->getName().getStringRef();
    for (OpOperand &use : op->getOpOperands())
      if (auto it = argOf.find(use.get()); it != argOf.end())
        os << " " << opIndex << ":" << use.getOperandNumber() << "=" << it->second;
    exact = llvm::hash_combine(exact, op->getAttrDictionary(), op->getNumRegions());
    for (Type t : op->getResultTypes())
      exact = llvm::hash_combine(exact, t);
    ++opIndex;
  });
  uint64_t stable = llvm::xxh3_64bits(text);
  return {stable, llvm::hash_combine(exact, stable)};
}

/// The region's code as the body of a new private function `name`.
func::FuncOp makeFunction(ModuleOp module, scf::ExecuteRegionOp region, StringRef name,
                          FunctionType type, const SetVector<Value> &captured) {
  OpBuilder b = OpBuilder::atBlockEnd(module.getBody());
  auto func = b.create<func::FuncOp>(region.getLoc(), name, type);
  func.setPrivate();
  Block *body = func.addEntryBlock();
  body->getOperations().splice(body->end(), region.getRegion().front().getOperations());
  for (auto [value, arg] : llvm::zip(captured, body->getArguments()))
    replaceAllUsesInRegionWith(value, arg, func.getBody());
  auto yield = cast<scf::YieldOp>(body->getTerminator());
  OpBuilder(yield).create<func::ReturnOp>(yield.getLoc(), yield.getOperands());
  yield.erase();
  return func;
}

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

struct OutlineLibraryPass : public mlir::osl::impl::OutlineLibraryBase<OutlineLibraryPass> {
  using OutlineLibraryBase::OutlineLibraryBase;

  void runOnOperation() override {
    ModuleOp module = getOperation();
    SmallVector<scf::ExecuteRegionOp> regions;
    module.walk([&](scf::ExecuteRegionOp r) {
      if (r->hasAttr(kLibraryAttr))
        regions.push_back(r);
    });
    SymbolTable symbols(module);
    // Library functions built from a recipe, with their calls (those a
    // call site keeps as calls aside).
    SmallVector<func::FuncOp> recipeFunctions;
    for (auto func : module.getOps<func::FuncOp>())
      if (func->hasAttr(kLibraryRecipeAttr))
        recipeFunctions.push_back(func);
    llvm::MapVector<func::FuncOp, SmallVector<func::CallOp>> recipeCalls;
    module.walk([&](func::CallOp call) {
      auto callee = symbols.lookup<func::FuncOp>(call.getCallee());
      if (callee && callee->hasAttr(kLibraryRecipeAttr) && !call->hasAttr(kKeepCallAttr))
        recipeCalls[callee].push_back(call);
    });
    // Erases those of `funcs` no call is left to (one walk a round), again
    // while erasing one leaves others uncalled (calls between routines).
    auto eraseUncalled = [&](ArrayRef<func::FuncOp> funcs) {
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
    };
    if (!outline) {
      for (scf::ExecuteRegionOp region : regions)
        inlineLibraryRegion(region);
      // (A routine compiled before has no code here: its calls stay.) Until
      // none is left: a routine's code may call others (noise_by_kind
      // calls each kind's), whose calls come in place with it.
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
          break;
        for (auto [call, callee] : inKernels)
          inlineCall(call, callee);
      }
      eraseUncalled(recipeFunctions);
      return;
    }
    // Functions by their regions' exact hash; a hash only narrows the
    // search: a body is reused when it is equivalent op for op.
    DenseMap<llvm::hash_code, SmallVector<func::FuncOp, 1>> byCode;
    llvm::StringMap<int> namesUsed;
    llvm::MapVector<func::FuncOp, SmallVector<func::CallOp>> callsOf;
    for (scf::ExecuteRegionOp region : regions) {
      SetVector<Value> captured;
      getUsedValuesDefinedAbove(region.getRegion(), captured);
      SmallVector<Type> argTypes;
      for (Value v : captured)
        argTypes.push_back(v.getType());
      auto type = FunctionType::get(&getContext(), argTypes, region.getResultTypes());
      RegionIdentity id = identify(region, type, captured);
      func::FuncOp candidate = makeFunction(module, region, "", type, captured);
      func::FuncOp func;
      for (func::FuncOp existing : byCode[id.exact])
        if (OperationEquivalence::isRegionEquivalentTo(&existing.getBody(),
                                                       &candidate.getBody(),
                                                       OperationEquivalence::IgnoreLocations)) {
          func = existing;
          break;
        }
      if (func) {
        candidate.erase();
      } else {
        std::string name = ::osl::abi::kLibrarySymbolPrefix +
                           region->getAttrOfType<StringAttr>(kLibraryAttr).getValue().str() +
                           "." + llvm::utohexstr(id.stable, /*LowerCase=*/true, 16);
        // Another body under the same stable identity: numbered in order
        // of appearance, so the names stay the same from run to run.
        if (int n = namesUsed[name]++)
          name += "." + std::to_string(n);
        candidate.setSymName(name);
        symbols.insert(candidate);
        byCode[id.exact].push_back(candidate);
        func = candidate;
      }
      OpBuilder b(region);
      auto call = b.create<func::CallOp>(region.getLoc(), func, captured.getArrayRef());
      region.replaceAllUsesWith(call.getResults());
      region.erase();
      callsOf[func].push_back(call);
    }
    for (auto &[func, calls] : recipeCalls)
      if (!func.isDeclaration())
        llvm::append_range(callsOf[func], calls);
    // A small straight-line function goes back in place: a call clobbers
    // every vector register, the caller's spills around it cost more than
    // a hash, and constant arguments fold. Bounded for compile time: its
    // copies (ops times calls) by inline-ops, and all copies by one
    // budget per kernel, cheapest first, so a shader calling many
    // different routines once each keeps the bigger ones as calls.
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
    SmallVector<func::FuncOp> inlinedEverywhere;
    for (const Candidate &c : candidates) {
      if (c.cost > inlineOps || c.cost > budget)
        break;
      budget -= c.cost;
      for (func::CallOp call : callsOf[c.func])
        inlineCall(call, c.func);
      if (!c.func->hasAttr(kLibraryRecipeAttr))
        inlinedEverywhere.push_back(c.func);
    }
    // And routines no call is left to: inlined at each, or each copied in
    // place by osl-derivatives.
    llvm::append_range(inlinedEverywhere, recipeFunctions);
    eraseUncalled(inlinedEverywhere);
  }
};

} // namespace
