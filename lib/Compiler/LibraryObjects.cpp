//===- LibraryObjects.cpp - Library functions compiled once ---------------===//
#include "OslCompiler/LibraryObjects.h"
#include "IRFingerprint.h"
#include "OslAbi/Library.h"
#include "OslCompiler/KernelCache.h"
#include "OslRuntime/Stats.h"

#include "mlir/Dialect/Func/IR/FuncOps.h"
#include "mlir/IR/BuiltinOps.h"
#include "mlir/IR/SymbolTable.h"
#include "llvm/ADT/SmallPtrSet.h"
#include "llvm/ADT/SmallString.h"
#include "llvm/ADT/StringSet.h"
#include "llvm/Config/llvm-config.h"
#include "llvm/IR/Constants.h"
#include "llvm/IR/InstIterator.h"
#include "llvm/IR/Module.h"
#include "llvm/Support/Path.h"
#include "llvm/Support/raw_ostream.h"
#include "llvm/Transforms/Utils/Cloning.h"

#include <mutex>

using namespace osl;

namespace {

/// Objects compiled or read by this process, by key.
struct ProcessObjects {
  std::mutex mutex;
  llvm::StringMap<std::shared_ptr<const std::string>> byKey;
};

ProcessObjects &processObjects() {
  static ProcessObjects objects;
  return objects;
}

std::string libraryDirectory(const LibraryKeyOptions &options) {
  if (options.cacheDir.empty())
    return "";
  llvm::SmallString<256> path(options.cacheDir);
  llvm::sys::path::append(path, "library");
  return path.str().str();
}

/// The object under `key`: this process's copy, else the cache's (kept in
/// the process from then on); null when neither has it.
std::shared_ptr<const std::string> lookupObject(const std::string &key,
                                                const std::string &directory, LibraryUse &use) {
  ProcessObjects &memory = processObjects();
  {
    std::lock_guard<std::mutex> lock(memory.mutex);
    if (auto it = memory.byKey.find(key); it != memory.byKey.end()) {
      ++use.fromMemory;
      return it->second;
    }
  }
  CachedKernel entry;
  if (directory.empty() || KernelCache(directory).lookup(key, entry) != CacheLookup::Hit)
    return nullptr;
  auto object = std::make_shared<const std::string>(std::move(entry.object));
  ++use.fromDisk;
  std::lock_guard<std::mutex> lock(memory.mutex);
  return memory.byKey.try_emplace(key, object).first->second;
}

/// Everything that decides `func`'s object: the options, the compiler and
/// the IR of the function and of every symbol it references (runtime
/// entry points, constant strings).
std::string objectKey(mlir::func::FuncOp func, mlir::SymbolTable &symbols,
                      IRFingerprint &fingerprint, const LibraryKeyOptions &options) {
  std::string key;
  llvm::raw_string_ostream os(key);
  os << "osl-mlir library 2\ncompiler " << KernelCache::compilerIdentity()
     << "\nllvm " LLVM_VERSION_STRING "\nhost " << Jit::hostDescription() << "\npipeline "
     << int(options.pipeline) << "\nmath " << options.math << "\nfunction "
     << func.getSymName() << " " << fingerprint.of(func) << "\n";
  llvm::StringSet<> referenced;
  if (auto uses = mlir::SymbolTable::getSymbolUses(&func.getBody()))
    for (const mlir::SymbolTable::SymbolUse &use : *uses) {
      llvm::StringRef name = use.getSymbolRef().getRootReference().getValue();
      if (!referenced.insert(name).second)
        continue;
      mlir::Operation *symbol = symbols.lookup(name);
      os << "uses " << name << " " << (symbol ? fingerprint.of(symbol) : "?") << "\n";
    }
  return key;
}

/// The global variables `f` reads, directly or through constant
/// expressions (the noise routines' tables).
std::vector<llvm::GlobalVariable *> globalsRead(llvm::Function &f) {
  std::vector<llvm::GlobalVariable *> found;
  llvm::SmallPtrSet<const llvm::Value *, 16> seen;
  std::vector<const llvm::Value *> work;
  for (llvm::Instruction &inst : llvm::instructions(f))
    for (const llvm::Value *op : inst.operands())
      work.push_back(op);
  while (!work.empty()) {
    const llvm::Value *v = work.back();
    work.pop_back();
    if (!llvm::isa<llvm::Constant>(v) || !seen.insert(v).second)
      continue;
    if (auto *gv = llvm::dyn_cast<llvm::GlobalVariable>(v)) {
      found.push_back(const_cast<llvm::GlobalVariable *>(gv));
      if (gv->hasInitializer())
        work.push_back(gv->getInitializer());
      continue;
    }
    if (auto *c = llvm::dyn_cast<llvm::ConstantExpr>(v))
      for (const llvm::Value *op : c->operands())
        work.push_back(op);
  }
  return found;
}

/// `f` (and the globals it reads) alone in a module, compiled.
llvm::Expected<std::string> compileAlone(llvm::Module &kernel, llvm::Function &f,
                                         LlvmPipeline pipeline) {
  std::vector<llvm::GlobalVariable *> globals = globalsRead(f);
  llvm::SmallPtrSet<const llvm::GlobalValue *, 8> keep(globals.begin(), globals.end());
  keep.insert(&f);
  llvm::ValueToValueMapTy map;
  std::unique_ptr<llvm::Module> alone = llvm::CloneModule(
      kernel, map, [&](const llvm::GlobalValue *gv) { return keep.contains(gv); });
  llvm::Function *copy = alone->getFunction(f.getName());
  copy->setLinkage(llvm::GlobalValue::ExternalLinkage);
  copy->setVisibility(llvm::GlobalValue::DefaultVisibility);
  return Jit::compileObject(*alone, pipeline);
}

} // namespace

LibraryUse osl::findLibraryObjects(mlir::ModuleOp module, const LibraryKeyOptions &options,
                                   Stats *stats) {
  ScopedTimer timer(stats, "library");
  LibraryUse use;
  mlir::SymbolTable symbols(module);
  std::string directory = libraryDirectory(options);
  IRFingerprint fingerprint;
  for (auto func : llvm::make_early_inc_range(module.getOps<mlir::func::FuncOp>())) {
    if (func.isDeclaration() || !func.getSymName().starts_with(abi::kLibrarySymbolPrefix))
      continue;
    std::string key = objectKey(func, symbols, fingerprint, options);
    if (auto object = lookupObject(key, directory, use)) {
      use.objects.push_back(std::move(object));
      // Its callers need only its signature.
      func.eraseBody();
    } else {
      use.toCompile[func.getSymName()] = std::move(key);
    }
  }
  return use;
}

llvm::Error osl::compileLibraryFunctions(llvm::Module &kernel, LibraryUse &use,
                                         const LibraryKeyOptions &options, Stats *stats) {
  ScopedTimer timer(stats, "library");
  std::string directory = libraryDirectory(options);
  ProcessObjects &memory = processObjects();
  std::vector<llvm::Function *> compiled;
  for (llvm::Function &f : kernel) {
    if (f.isDeclaration() || !f.getName().starts_with(abi::kLibrarySymbolPrefix))
      continue;
    auto key = use.toCompile.find(f.getName());
    if (key == use.toCompile.end())
      return llvm::createStringError(llvm::inconvertibleErrorCode(),
                                     "library function '" + f.getName() +
                                         "' has no key (findLibraryObjects did not see it)");
    // Another thread may have compiled it meanwhile: then link that one.
    std::shared_ptr<const std::string> object = lookupObject(key->second, directory, use);
    if (!object) {
      auto built = compileAlone(kernel, f, options.pipeline);
      if (!built)
        return built.takeError();
      object = std::make_shared<const std::string>(std::move(*built));
      ++use.compiled;
      std::string error; // an unwritable cache costs a later run a compile
      if (!directory.empty())
        KernelCache(directory).store(key->second,
                                     CachedKernel{f.getName().str(), {}, *object, {}, "", ""},
                                     error);
      std::lock_guard<std::mutex> lock(memory.mutex);
      memory.byKey.try_emplace(key->second, object);
    }
    use.objects.push_back(std::move(object));
    compiled.push_back(&f);
  }
  // The kernel calls them; the objects define them.
  for (llvm::Function *f : compiled) {
    f->deleteBody();
    f->setLinkage(llvm::GlobalValue::ExternalLinkage);
    f->setVisibility(llvm::GlobalValue::DefaultVisibility);
  }
  use.toCompile.clear();
  return llvm::Error::success();
}
