//===- LibraryObjects.cpp - Library functions compiled once ---------------===//
#include "OslCompiler/LibraryObjects.h"
#include "OslAbi/Library.h"
#include "OslCompiler/KernelCache.h"
#include "OslRuntime/Stats.h"

#include "llvm/ADT/SmallPtrSet.h"
#include "llvm/ADT/SmallString.h"
#include "llvm/ADT/StringMap.h"
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

std::string objectKey(llvm::Function &f, const std::vector<llvm::GlobalVariable *> &globals,
                      LlvmPipeline pipeline) {
  std::string key;
  llvm::raw_string_ostream os(key);
  os << "osl-mlir library 1\nllvm " LLVM_VERSION_STRING "\nhost " << Jit::hostDescription()
     << "\npipeline " << int(pipeline) << "\n";
  for (llvm::GlobalVariable *g : globals)
    os << *g << "\n";
  os << f;
  return key;
}

/// `f` (and the globals it reads) alone in a module, compiled.
llvm::Expected<std::string> compileAlone(llvm::Module &kernel, llvm::Function &f,
                                         const std::vector<llvm::GlobalVariable *> &globals,
                                         LlvmPipeline pipeline) {
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

llvm::Expected<LibraryUse> osl::splitLibraryFunctions(llvm::Module &kernel,
                                                      LlvmPipeline pipeline,
                                                      const std::string &cacheDir,
                                                      Stats *stats) {
  ScopedTimer timer(stats, "library");
  LibraryUse use;
  std::vector<llvm::Function *> library;
  for (llvm::Function &f : kernel)
    if (!f.isDeclaration() && f.getName().starts_with(abi::kLibrarySymbolPrefix))
      library.push_back(&f);
  if (library.empty())
    return use;
  std::string directory;
  if (!cacheDir.empty()) {
    llvm::SmallString<256> path(cacheDir);
    llvm::sys::path::append(path, "library");
    directory = path.str().str();
  }
  KernelCache disk(directory);
  ProcessObjects &memory = processObjects();
  for (llvm::Function *f : library) {
    std::vector<llvm::GlobalVariable *> globals = globalsRead(*f);
    std::string key = objectKey(*f, globals, pipeline);
    std::shared_ptr<const std::string> object;
    {
      std::lock_guard<std::mutex> lock(memory.mutex);
      if (auto it = memory.byKey.find(key); it != memory.byKey.end())
        object = it->second;
    }
    if (object) {
      ++use.fromMemory;
    } else {
      CachedKernel entry;
      if (!directory.empty() && disk.lookup(key, entry) == CacheLookup::Hit) {
        object = std::make_shared<const std::string>(std::move(entry.object));
        ++use.fromDisk;
      } else {
        auto compiled = compileAlone(kernel, *f, globals, pipeline);
        if (!compiled)
          return compiled.takeError();
        object = std::make_shared<const std::string>(std::move(*compiled));
        ++use.compiled;
        std::string error; // an unwritable cache costs a later run a compile
        if (!directory.empty())
          disk.store(key, CachedKernel{f->getName().str(), {}, *object, {}, "", ""}, error);
      }
      std::lock_guard<std::mutex> lock(memory.mutex);
      memory.byKey.try_emplace(key, object);
    }
    use.objects.push_back(object);
  }
  // The kernel calls them; the objects define them.
  for (llvm::Function *f : library) {
    f->deleteBody();
    f->setLinkage(llvm::GlobalValue::ExternalLinkage);
    f->setVisibility(llvm::GlobalValue::DefaultVisibility);
  }
  return use;
}
