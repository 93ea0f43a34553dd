//===- IRGenCheck.cpp - Checking functions no call reaches ----------------===//
//
// Functions are inlined where they are called, so a function no call
// reaches would never be looked at; oslc checks every one. Each such
// top-level function of the user's files is emitted once here, on zero
// arguments, into a scratch function erased afterwards: its errors are
// reported as oslc reports them, and the shader's IR is unchanged.
//
//===----------------------------------------------------------------------===//
#include "IRGen.h"

#include "mlir/Dialect/Func/IR/FuncOps.h"

using namespace osl::frontend;
using namespace mlir;

/// Our versions of OSL's standard headers: their functions are checked by
/// our own tests, not again in every shader that includes them.
static bool isStandardHeader(llvm::StringRef file) {
  return file.starts_with(OSL_MLIR_STDINCLUDE_DIR);
}

bool IRGen::checkUncalledFunctions(const Program &program, ModuleOp module) {
  std::vector<const FunctionDecl *> unchecked;
  for (const auto &fn : program.functions)
    if (!inlinedFunctions.count(fn.get()) &&
        !isStandardHeader(diags.fileName(fn->loc.file)))
      unchecked.push_back(fn.get());
  if (unchecked.empty())
    return true;

  OpBuilder::InsertionGuard guard(b);
  b.setInsertionPointToEnd(module.getBody());
  auto scratch = b.create<func::FuncOp>(loc(program.shader->loc), "osl.check_functions",
                                        b.getFunctionType({}, {}));
  // Globals read in the scratch function are emitted there; the shader's
  // own are put back afterwards.
  Block *savedEntry = entryBlock;
  Operation *savedLastGlobal = lastGlobal;
  llvm::StringMap<Value> savedGlobals = std::move(globalValues);
  globalValues.clear();
  lastGlobal = nullptr;
  entryBlock = scratch.addEntryBlock();
  b.setInsertionPointToStart(entryBlock);
  Scope *savedScope = current;
  // A checked function may assign globals (P, Ci): their values go back.
  std::vector<std::pair<Var *, RValue>> savedRoot;
  for (auto &entry : root->vars)
    savedRoot.push_back({entry.second, entry.second->val});
  size_t savedOps = opCounter.count;
  // The shader's exit and return flags hold values of the shader's body
  // (some since erased): a function checked alone starts with neither.
  Var *savedExit = exitFlag, *savedReturned = shaderReturned;
  shaderReturned = nullptr;
  exitFlag = declareFlag(newScope(root), kExitFlag, program.shader->loc);

  bool ok = true;
  for (const FunctionDecl *fn : unchecked) {
    current = root;
    std::vector<RValue> args;
    for (const Param &p : fn->params) {
      OslType t = p.type;
      if (t.isArray() && t.arrayLen == 0)
        t.arrayLen = 1; // an unsized array parameter: any length does
      args.push_back(zeroValue(t, fn->loc));
    }
    std::vector<std::optional<LValue>> lvalues(args.size());
    Expr call(ExprKind::Call, fn->loc);
    call.name = fn->name;
    // A check that stops without an error report met a valueError: the
    // function needs arguments known when it is called.
    checkingUncalled = true;
    (void)inlineCall({fn, root}, call, args, lvalues);
    checkingUncalled = false;
    opCounter.count = savedOps;
    ok = !diags.hadError();
    if (!ok)
      break;
  }

  current = savedScope;
  exitFlag = savedExit;
  shaderReturned = savedReturned;
  entryBlock = savedEntry;
  lastGlobal = savedLastGlobal;
  globalValues = std::move(savedGlobals);
  for (auto &[var, value] : savedRoot)
    var->val = value;
  scratch->dropAllReferences();
  scratch.erase();
  return ok;
}
