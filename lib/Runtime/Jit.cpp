//===- Jit.cpp - Host JIT for compiled shader kernels ----------------------===//

#include "OslRuntime/Jit.h"
#include "MaskPhis.h"
#include "OslRuntime/Stats.h"

#include "llvm/ExecutionEngine/Orc/CompileUtils.h"
#include "llvm/ExecutionEngine/Orc/ExecutionUtils.h"
#include "llvm/ExecutionEngine/Orc/JITTargetMachineBuilder.h"
#include "llvm/ExecutionEngine/Orc/LLJIT.h"
#include "llvm/ExecutionEngine/Orc/ThreadSafeModule.h"
#include "llvm/IR/LegacyPassManager.h"
#include "llvm/IR/Module.h"
#include "llvm/IR/Verifier.h"
#include "llvm/Passes/PassBuilder.h"
#include "llvm/Support/CommandLine.h"
#include "llvm/Support/MemoryBuffer.h"
#include "llvm/Support/TargetSelect.h"
#include "llvm/Support/raw_ostream.h"
#include "llvm/Target/TargetMachine.h"
#include "llvm/TargetParser/Host.h"
#include "llvm/Transforms/Utils/Cloning.h"

#include <algorithm>
#include <mutex>
#include <optional>
#include <vector>

namespace osl {

namespace {

void initializeNativeTargetOnce() {
  static std::once_flag once;
  std::call_once(once, [] {
    llvm::InitializeNativeTarget();
    llvm::InitializeNativeTargetAsmPrinter();
  });
}

/// The host CPU with all its features at the highest codegen level. The
/// default FP contraction (fuse only where the IR allows it) is kept: the
/// compiler, not the JIT, decides where FMA is allowed, since testshade's
/// references are computed without it.
llvm::Expected<llvm::orc::JITTargetMachineBuilder> hostBuilder() {
  initializeNativeTargetOnce();
  // The host does not change while the process runs: detect it once
  // (reading the CPU's name and features is a measurable part of a
  // compile that takes milliseconds).
  static const std::optional<llvm::orc::JITTargetMachineBuilder> host =
      []() -> std::optional<llvm::orc::JITTargetMachineBuilder> {
    auto builder = llvm::orc::JITTargetMachineBuilder::detectHost();
    if (!builder) {
      llvm::consumeError(builder.takeError());
      return std::nullopt;
    }
    builder->setCodeGenOptLevel(llvm::CodeGenOptLevel::Aggressive);
    return std::move(*builder);
  }();
  if (!host)
    return llvm::createStringError(llvm::inconvertibleErrorCode(),
                                   "the host CPU is not a target this LLVM supports");
  return *host;
}

/// Makes `module` target `tm` and tags definitions with the host CPU so
/// per-function subtarget queries (TTI, inlining compatibility, codegen)
/// agree with the TargetMachine even when the module is printed or
/// compiled elsewhere, and with an aligned frame (below).
void retarget(llvm::Module &module, llvm::TargetMachine &tm) {
  module.setTargetTriple(tm.getTargetTriple().str());
  module.setDataLayout(tm.createDataLayout());
  for (llvm::Function &f : module) {
    if (f.isDeclaration())
      continue;
    if (!f.hasFnAttribute("target-cpu"))
      f.addFnAttr("target-cpu", tm.getTargetCPU());
    if (!f.hasFnAttribute("target-features"))
      f.addFnAttr("target-features", tm.getTargetFeatureString());
    // Realign the frame so vector spill slots sit on their own cache lines.
    // Otherwise LLVM spills 64-byte registers with unaligned moves at
    // offsets from whatever stack pointer the caller passes; the marble
    // kernel ran 10-25% slower when those split cache lines (measured at
    // width 16), so its speed depended on the caller's frame.
    f.addFnAttr("stackrealign");
  }
}

llvm::Error verify(llvm::Module &module) {
  std::string message;
  llvm::raw_string_ostream os(message);
  if (llvm::verifyModule(module, &os))
    return llvm::createStringError(llvm::inconvertibleErrorCode(),
                                   "invalid LLVM module: " + os.str());
  return llvm::Error::success();
}

/// A new TargetMachine for the host.
llvm::Expected<std::unique_ptr<llvm::TargetMachine>> createHostMachine() {
  auto builder = hostBuilder();
  if (!builder)
    return builder.takeError();
  return builder->createTargetMachine();
}

/// This thread's host TargetMachine. Creating one (and its subtarget's
/// lowering tables) costs a few ms, more than codegen of a small kernel, so
/// each thread makes one and every compile on that thread reuses it;
/// TargetMachines are not shared between threads.
llvm::Expected<llvm::TargetMachine &> threadTargetMachine() {
  thread_local std::unique_ptr<llvm::TargetMachine> machine;
  if (!machine) {
    auto tm = createHostMachine();
    if (!tm)
      return tm.takeError();
    machine = std::move(*tm);
  }
  return *machine;
}

/// LLJIT's compile step on the calling thread's TargetMachine (LLJIT
/// compiles on the thread that looks a symbol up).
class ThreadMachineCompiler : public llvm::orc::IRCompileLayer::IRCompiler {
public:
  explicit ThreadMachineCompiler(llvm::TargetMachine &tm)
      : IRCompiler(llvm::orc::irManglingOptionsFromTargetOptions(tm.Options)) {}
  llvm::Expected<std::unique_ptr<llvm::MemoryBuffer>>
  operator()(llvm::Module &module) override {
    auto tm = threadTargetMachine();
    if (!tm)
      return tm.takeError();
    return llvm::orc::SimpleCompiler(*tm)(module);
  }
};

} // namespace

Jit::~Jit() = default;

llvm::Expected<std::unique_ptr<Jit>> Jit::create(Stats *stats) {
  ScopedTimer timer(stats, "jit setup");
  auto builder = hostBuilder();
  if (!builder)
    return builder.takeError();

  std::unique_ptr<Jit> jit(new Jit());
  jit->stats = stats;
  // The optimizer's cost model and codegen use the calling thread's
  // machine; this one is for targetMachine().
  auto tm = threadTargetMachine();
  if (!tm)
    return tm.takeError();
  jit->tm = &*tm;

  llvm::orc::LLJITBuilder lljitBuilder;
  lljitBuilder.setJITTargetMachineBuilder(std::move(*builder));
  lljitBuilder.setCompileFunctionCreator(
      [](llvm::orc::JITTargetMachineBuilder)
          -> llvm::Expected<std::unique_ptr<llvm::orc::IRCompileLayer::IRCompiler>> {
        auto tm = threadTargetMachine();
        if (!tm)
          return tm.takeError();
        return std::make_unique<ThreadMachineCompiler>(*tm);
      });
  auto lljit = lljitBuilder.create();
  if (!lljit)
    return lljit.takeError();
  jit->lljit = std::move(*lljit);

  // Kernels call libm and the runtime library's C entry points; resolve
  // anything the JIT'd code leaves undefined in this process.
  auto generator =
      llvm::orc::DynamicLibrarySearchGenerator::GetForCurrentProcess(
          jit->lljit->getDataLayout().getGlobalPrefix());
  if (!generator)
    return generator.takeError();
  jit->lljit->getMainJITDylib().addGenerator(std::move(*generator));
  return jit;
}

/// Verifies `module`, retargets it to the calling thread's host machine and
/// runs `pipeline`.
static llvm::Error optimizeForHost(llvm::Module &module, LlvmPipeline pipeline) {
  auto tm = threadTargetMachine();
  if (!tm)
    return tm.takeError();
  retarget(module, *tm);
  if (llvm::Error err = verify(module))
    return err;

  llvm::LoopAnalysisManager lam;
  llvm::FunctionAnalysisManager fam;
  llvm::CGSCCAnalysisManager cgam;
  llvm::ModuleAnalysisManager mam;
  llvm::PassBuilder builder(&*tm);
  builder.registerModuleAnalyses(mam);
  builder.registerCGSCCAnalyses(cgam);
  builder.registerFunctionAnalyses(fam);
  builder.registerLoopAnalyses(lam);
  builder.crossRegisterProxies(lam, fam, cgam, mam);
  llvm::ModulePassManager mpm;
  if (pipeline == LlvmPipeline::O3) {
    mpm = builder.buildPerModuleDefaultPipeline(llvm::OptimizationLevel::O3);
  } else {
    // Allocas of runtime-call blocks to registers where possible, then
    // clean-ups of the lowering's output; LICM hoists uniform work out of
    // loops the front end could not prove invariant. No instcombine: the
    // MLIR canonicalizer has already simplified the arithmetic, and on the
    // perf shaders it changed neither the code's size nor its speed while
    // taking 2.7 of marble's 3.2 ms here (measured).
    if (llvm::Error err = builder.parsePassPipeline(
            mpm, "function(sroa,early-cse,simplifycfg,loop-mssa(licm))"))
      return err;
  }
  mpm.run(module, mam);
  // AVX-512 keeps masks in its mask registers; other x86 targets want them
  // as full-width lanes across loop back edges (MaskPhis.h).
  if (tm->getTargetTriple().isX86() &&
      !tm->getTargetFeatureString().contains("+avx512f"))
    for (llvm::Function &f : module)
      if (!f.isDeclaration())
        widenMaskPhis(f);
  return llvm::Error::success();
}

llvm::Error Jit::optimize(llvm::Module &module, LlvmPipeline pipeline) {
  ScopedTimer timer(stats, "llvm opt");
  return optimizeForHost(module, pipeline);
}

llvm::Expected<std::string> Jit::compileObject(llvm::Module &module, LlvmPipeline pipeline) {
  if (llvm::Error err = optimizeForHost(module, pipeline))
    return std::move(err);
  return generateObject(module);
}

llvm::Expected<std::string> Jit::generateObject(llvm::Module &module) {
  auto tm = threadTargetMachine();
  if (!tm)
    return tm.takeError();
  auto object = llvm::orc::SimpleCompiler(*tm)(module);
  if (!object)
    return object.takeError();
  return (*object)->getBuffer().str();
}

llvm::Error Jit::addModule(std::unique_ptr<llvm::Module> module,
                           std::unique_ptr<llvm::LLVMContext> context) {
  ScopedTimer timer(stats, "jit add");
  if (module->getDataLayout().isDefault())
    module->setDataLayout(lljit->getDataLayout());
  if (module->getTargetTriple().empty())
    module->setTargetTriple(lljit->getTargetTriple().str());
  return lljit->addIRModule(
      llvm::orc::ThreadSafeModule(std::move(module), std::move(context)));
}

llvm::Error Jit::addObject(std::unique_ptr<llvm::MemoryBuffer> object) {
  ScopedTimer timer(stats, "jit add");
  return lljit->addObjectFile(std::move(object));
}

llvm::Error
Jit::defineSymbols(llvm::ArrayRef<std::pair<llvm::StringRef, void *>> symbols) {
  llvm::orc::SymbolMap map;
  for (const auto &[name, address] : symbols)
    map[lljit->mangleAndIntern(name)] = llvm::orc::ExecutorSymbolDef(
        llvm::orc::ExecutorAddr::fromPtr(address),
        llvm::JITSymbolFlags::Exported | llvm::JITSymbolFlags::Callable);
  return lljit->getMainJITDylib().define(
      llvm::orc::absoluteSymbols(std::move(map)));
}

llvm::Expected<void *> Jit::lookup(llvm::StringRef name) {
  // Linking happens here, on first lookup, and codegen of the IR modules
  // added with addModule (the kernels' objects are generated beforehand).
  ScopedTimer timer(stats, "jit link");
  auto address = lljit->lookup(name);
  if (!address)
    return address.takeError();
  return address->toPtr<void *>();
}

llvm::Expected<std::string> Jit::emitAssembly(llvm::Module &module,
                                              Stats *stats) {
  ScopedTimer timer(stats, "emit asm");
  auto tm = createHostMachine();
  if (!tm)
    return tm.takeError();

  // Codegen rewrites the IR it compiles; keep the caller's module intact.
  std::unique_ptr<llvm::Module> clone = llvm::CloneModule(module);
  retarget(*clone, **tm);
  if (llvm::Error err = verify(*clone))
    return std::move(err);

  llvm::SmallString<0> text;
  llvm::raw_svector_ostream os(text);
  llvm::legacy::PassManager pm;
  if ((*tm)->addPassesToEmitFile(pm, os, nullptr,
                                 llvm::CodeGenFileType::AssemblyFile))
    return llvm::createStringError(llvm::inconvertibleErrorCode(),
                                   "host target cannot emit assembly");
  pm.run(*clone);
  return std::string(text.str());
}

int Jit::hostMaxWidth() {
  static const int width = [] {
    llvm::StringMap<bool> features = llvm::sys::getHostCPUFeatures();
    auto has = [&](llvm::StringRef name) { return features.lookup(name); };
    if (has("avx512f"))
      return 16;
    if (has("avx2"))
      return 8;
    return 4;
  }();
  return width;
}

std::string Jit::hostDescription() {
  // Once per process: every cached object's key has it, and the CPUID
  // queries behind it trap to the hypervisor on a virtual machine (48
  // library keys took 8 ms of a compile before).
  static const std::string description = [] {
    std::string text = llvm::sys::getProcessTriple() + " " + llvm::sys::getHostCPUName().str();
    // StringMap iterates in hash order; sort so equal hosts give equal text.
    std::vector<std::string> features;
    for (const auto &f : llvm::sys::getHostCPUFeatures())
      features.push_back((f.getValue() ? "+" : "-") + f.getKey().str());
    std::sort(features.begin(), features.end());
    for (const std::string &f : features)
      text += " " + f;
    return text;
  }();
  return description;
}

void Jit::disableMachineScheduler() {
  llvm::cl::Option *option = llvm::cl::getRegisteredOptions().lookup("enable-misched");
  if (option && option->getNumOccurrences() == 0)
    option->addOccurrence(0, "enable-misched", "false");
}

} // namespace osl
