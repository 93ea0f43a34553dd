//===- LibraryObjects.cpp - Library functions compiled once ---------------===//
#include "OslCompiler/LibraryObjects.h"
#include "OslAbi/Library.h"
#include "OslCompiler/KernelCache.h"
#include "OslRuntime/Stats.h"
#include "OslLanes/LibraryFunctions.h"

#include "mlir/Dialect/Func/IR/FuncOps.h"
#include "mlir/Dialect/LLVMIR/LLVMDialect.h"
#include "mlir/IR/BuiltinOps.h"
#include "mlir/IR/SymbolTable.h"
#include "mlir/Target/LLVMIR/Export.h"
#include "llvm/ADT/SetVector.h"
#include "llvm/ADT/SmallPtrSet.h"
#include "llvm/ADT/SmallString.h"
#include "llvm/ADT/StringSet.h"
#include "llvm/Config/llvm-config.h"
#include "llvm/Support/FileSystem.h"
#include "llvm/Support/Path.h"
#include "llvm/Support/raw_ostream.h"

#include <cstdlib>
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

} // namespace

std::string osl::prebuiltLibraryDirectory() {
  static const std::string directory = []() -> std::string {
    if (const char *off = std::getenv("OSL_MLIR_NO_PREBUILT_LIBRARY"); off && *off)
      return "";
    // The main executable's: <prefix>/bin/osl-run finds <prefix>/share.
    std::string exe = llvm::sys::fs::getMainExecutable(
        nullptr, reinterpret_cast<void *>(&osl::prebuiltLibraryDirectory));
    if (exe.empty())
      return "";
    llvm::SmallString<256> path(llvm::sys::path::parent_path(llvm::sys::path::parent_path(exe)));
    llvm::sys::path::append(path, "share", "osl-mlir", "library");
    return llvm::sys::fs::is_directory(path) ? path.str().str() : "";
  }();
  return directory;
}

namespace {

/// The object under `key` in the cache `directory`, if it has it.
std::shared_ptr<const std::string> readObject(const std::string &key,
                                              const std::string &directory) {
  CachedKernel entry;
  if (directory.empty() || KernelCache(directory).lookup(key, entry) != CacheLookup::Hit)
    return nullptr;
  return std::make_shared<const std::string>(std::move(entry.object));
}

/// The object under `key`: this process's copy, else the cache's, else the
/// prebuilt library's (kept in the process from then on); null when none
/// has it.
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
  std::shared_ptr<const std::string> object = readObject(key, directory);
  if (object) {
    ++use.fromDisk;
  } else if ((object = readObject(key, prebuiltLibraryDirectory()))) {
    ++use.prebuilt;
  } else {
    return nullptr;
  }
  std::lock_guard<std::mutex> lock(memory.mutex);
  return memory.byKey.try_emplace(key, object).first->second;
}

/// The key's first lines: what decides every library object besides its
/// code.
void keyHeader(llvm::raw_ostream &os, llvm::StringRef version,
               const LibraryKeyOptions &options) {
  os << "osl-mlir library " << version << "\ncompiler " << KernelCache::compilerIdentity()
     << "\nllvm " LLVM_VERSION_STRING "\nhost " << Jit::hostDescription() << "\npipeline "
     << int(options.pipeline) << "\nmath " << options.math << "\n";
}

/// The key of a routine built from `recipe` (OslLanes/LibraryFunctions.h): its
/// code is decided by the recipe and the compiler, so the recipe stands for
/// it, and it can be found before its code is built.
std::string recipeKey(llvm::StringRef recipe, const LibraryKeyOptions &options) {
  std::string key;
  llvm::raw_string_ostream os(key);
  keyHeader(os, "recipe 1", options);
  os << "recipe " << recipe << "\n";
  return key;
}

/// A copy of the lowered library function `func` in a module of its own:
/// with copies of the globals it reads (the noise tables) and declarations
/// of the functions it calls, the function itself external.
mlir::OwningOpRef<mlir::ModuleOp> moduleAlone(mlir::LLVM::LLVMFuncOp func, mlir::ModuleOp kernel,
                                              mlir::SymbolTable &symbols) {
  // The symbols it uses, and the symbols those use (a global's initializer).
  llvm::SetVector<mlir::Operation *> used;
  llvm::SmallVector<mlir::Operation *> work{func};
  while (!work.empty()) {
    mlir::Operation *op = work.pop_back_val();
    auto uses = mlir::SymbolTable::getSymbolUses(op);
    if (!uses)
      continue;
    for (const mlir::SymbolTable::SymbolUse &use : *uses)
      if (mlir::Operation *symbol = symbols.lookup(use.getSymbolRef().getRootReference()))
        if (symbol != func.getOperation() && used.insert(symbol))
          work.push_back(symbol);
  }
  mlir::OpBuilder b(func.getContext());
  mlir::OwningOpRef<mlir::ModuleOp> alone = mlir::ModuleOp::create(func.getLoc());
  for (mlir::NamedAttribute attr : kernel->getAttrs())
    if (attr.getName() != mlir::SymbolTable::getSymbolAttrName())
      (*alone)->setAttr(attr.getName(), attr.getValue());
  b.setInsertionPointToEnd(alone->getBody());
  for (mlir::Operation &op : kernel.getBody()->getOperations()) {
    if (!used.contains(&op))
      continue;
    mlir::Operation *copy = b.clone(op);
    if (auto callee = mlir::dyn_cast<mlir::LLVM::LLVMFuncOp>(copy))
      if (!callee.isExternal()) {
        callee.eraseBody();
        callee.setLinkage(mlir::LLVM::Linkage::External);
      }
  }
  auto copy = mlir::cast<mlir::LLVM::LLVMFuncOp>(b.clone(*func));
  copy.setLinkage(mlir::LLVM::Linkage::External);
  copy.setVisibility_(mlir::LLVM::Visibility::Default);
  return alone;
}

} // namespace

std::vector<LibraryJob> osl::splitLibraryJobs(mlir::ModuleOp kernel, const LibraryUse &use,
                                              std::string &error) {
  std::vector<LibraryJob> jobs;
  mlir::SymbolTable symbols(kernel);
  for (const auto &entry : use.toCompile) {
    auto func = symbols.lookup<mlir::LLVM::LLVMFuncOp>(entry.getKey());
    if (!func || func.isExternal())
      continue; // the lowering dropped it: nothing calls it
    LibraryJob job;
    job.name = entry.getKey().str();
    job.key = entry.getValue();
    job.context = std::make_unique<llvm::LLVMContext>();
    mlir::OwningOpRef<mlir::ModuleOp> alone = moduleAlone(func, kernel, symbols);
    job.module = mlir::translateModuleToLLVMIR(*alone, *job.context, job.name);
    if (!job.module) {
      error = "translation of library function '" + job.name + "' to LLVM IR failed";
      return {};
    }
    // The kernel calls it; the job's object defines it.
    func.eraseBody();
    func.setLinkage(mlir::LLVM::Linkage::External);
    func.setVisibility_(mlir::LLVM::Visibility::Default);
    jobs.push_back(std::move(job));
  }
  return jobs;
}

void osl::compileLibraryJob(LibraryJob &job, const LibraryKeyOptions &options) {
  {
    // Another compile of this process may have made it meanwhile.
    ProcessObjects &memory = processObjects();
    std::lock_guard<std::mutex> lock(memory.mutex);
    if (auto it = memory.byKey.find(job.key); it != memory.byKey.end()) {
      job.object = it->second;
      job.reused = true;
      return;
    }
  }
  auto built = Jit::compileObject(*job.module, options.pipeline);
  if (!built) {
    job.error = llvm::toString(built.takeError());
    return;
  }
  job.object = std::make_shared<const std::string>(std::move(*built));
}

bool osl::keepLibraryObjects(std::vector<LibraryJob> &jobs, LibraryUse &use,
                             const LibraryKeyOptions &options, std::string &error) {
  std::string directory = libraryDirectory(options);
  ProcessObjects &memory = processObjects();
  for (LibraryJob &job : jobs) {
    if (!job.object) {
      error = "library function '" + job.name + "': " + job.error;
      return false;
    }
    if (job.reused) {
      ++use.fromMemory;
    } else {
      ++use.compiled;
      std::string ignored; // an unwritable cache costs a later run a compile
      if (!directory.empty())
        KernelCache(directory).store(job.key, CachedKernel{job.name, {}, *job.object, {}, "", ""},
                                     ignored);
      std::lock_guard<std::mutex> lock(memory.mutex);
      job.object = memory.byKey.try_emplace(job.key, job.object).first->second;
    }
    use.objects.push_back(job.object);
  }
  use.toCompile.clear();
  return true;
}

mlir::osl::LibraryObjectAvailable osl::libraryObjectFinder(const LibraryKeyOptions &options,
                                                          LibraryUse &use) {
  return [options, &use](llvm::StringRef recipe) {
    auto [it, isNew] = use.recipesFound.try_emplace(recipe);
    if (isNew) {
      // Counted once the kernel is known to call it (findLibraryObjects):
      // a routine differentiated by its dual is not.
      LibraryUse counted;
      it->second.object =
          lookupObject(recipeKey(recipe, options), libraryDirectory(options), counted);
      it->second.origin = counted.prebuilt     ? &LibraryUse::prebuilt
                          : counted.fromDisk   ? &LibraryUse::fromDisk
                                               : &LibraryUse::fromMemory;
    }
    return it->second.object != nullptr;
  };
}

void osl::findLibraryObjects(mlir::ModuleOp module, const LibraryKeyOptions &options,
                             Stats *stats, LibraryUse &use) {
  ScopedTimer timer(stats, "library");
  std::string directory = libraryDirectory(options);
  for (auto func : llvm::make_early_inc_range(module.getOps<mlir::func::FuncOp>())) {
    if (!func.getSymName().starts_with(abi::kLibrarySymbolPrefix))
      continue;
    auto recipe = func->getAttrOfType<mlir::StringAttr>(mlir::osl::kLibraryRecipeAttr);
    // A routine found while the kernel was converted (a declaration, or
    // defined for a call that needed its code): that object.
    auto found = recipe ? use.recipesFound.find(recipe.getValue()) : use.recipesFound.end();
    if (found != use.recipesFound.end() && found->second.object) {
      if (llvm::find(use.objects, found->second.object) == use.objects.end()) {
        use.objects.push_back(found->second.object);
        ++(use.*found->second.origin);
      }
      if (!func.isDeclaration())
        func.eraseBody();
      continue;
    }
    // (A function without a recipe is hand-written IR: it stays in the
    // kernel.)
    if (func.isDeclaration() || !recipe)
      continue;
    std::string key = recipeKey(recipe.getValue(), options);
    if (auto object = lookupObject(key, directory, use)) {
      use.objects.push_back(std::move(object));
      // Its callers need only its signature.
      func.eraseBody();
    } else {
      use.toCompile[func.getSymName()] = std::move(key);
    }
  }
}
