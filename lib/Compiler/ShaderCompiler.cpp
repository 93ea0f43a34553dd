//===- ShaderCompiler.cpp - OSL source to a callable batch kernel ---------===//
#include "OslCompiler/ShaderCompiler.h"
#include "OslCompiler/KernelCache.h"
#include "OslCompiler/LibraryObjects.h"
#include "GlobalsNeeded.h"
#include "GroupInputs.h"
#include "OptimizationWarnings.h"

#include "OslDialect/OslDialect.h"
#include "OslAbi/EntryPoints.h"
#include "OslPipeline/Pipeline.h"
#include "OslRuntime/ThreadPool.h"

#include "mlir/Dialect/ControlFlow/IR/ControlFlow.h"
#include "mlir/IR/Diagnostics.h"
#include "mlir/Parser/Parser.h"
#include "mlir/IR/Verifier.h"
#include "mlir/Pass/PassManager.h"
#include "mlir/Target/LLVMIR/Dialect/Builtin/BuiltinToLLVMIRTranslation.h"
#include "mlir/Target/LLVMIR/Dialect/LLVMIR/LLVMToLLVMIRTranslation.h"
#include "mlir/Target/LLVMIR/Export.h"
#include "mlir/Transforms/Passes.h"
#include "llvm/ADT/StringMap.h"
#include "llvm/ADT/StringSet.h"
#include "llvm/IR/LLVMContext.h"
#include "llvm/Config/llvm-config.h"
#include "llvm/IR/Module.h"
#include "llvm/Support/MemoryBuffer.h"
#include "llvm/Support/SourceMgr.h"

#include <optional>

using namespace osl;

namespace {
/// Prints pass errors with the shader's file:line:col, as the front end does.
mlir::ScopedDiagnosticHandler printErrors(mlir::MLIRContext &context, llvm::raw_ostream &errs) {
  return mlir::ScopedDiagnosticHandler(&context, [&errs](mlir::Diagnostic &d) {
    if (d.getSeverity() == mlir::DiagnosticSeverity::Error) {
      if (auto loc = mlir::dyn_cast<mlir::FileLineColLoc>(d.getLocation()))
        errs << loc.getFilename().getValue() << ":" << loc.getLine() << ":"
             << loc.getColumn();
      else
        d.getLocation().print(errs);
      errs << ": error: " << d.str() << "\n";
    }
    return mlir::success();
  });
}

} // namespace

ShaderCompiler::ShaderCompiler(const CompileOptions &options,
                               llvm::raw_ostream &errs, Stats *stats)
    : options(options), errs(errs), stats(stats),
      context(mlir::MLIRContext::Threading::DISABLED) {
  if (this->options.reference)
    this->options.width = 1;
  if (this->options.width == 0)
    this->options.width = Jit::hostMaxWidth();
  mlir::DialectRegistry registry;
  registry.insert<mlir::osl::OslDialect, mlir::func::FuncDialect,
                  mlir::arith::ArithDialect, mlir::math::MathDialect,
                  mlir::scf::SCFDialect, mlir::vector::VectorDialect,
                  mlir::cf::ControlFlowDialect, mlir::LLVM::LLVMDialect>();
  mlir::registerBuiltinDialectTranslation(registry);
  mlir::registerLLVMDialectTranslation(registry);
  context.appendDialectRegistry(registry);
  context.loadAllAvailableDialects();
}

ShaderCompiler::~ShaderCompiler() = default;

mlir::OwningOpRef<mlir::ModuleOp>
ShaderCompiler::parseSource(llvm::StringRef source, llvm::StringRef filename,
                            llvm::ArrayRef<ParamOverride> params, llvm::StringRef layerName,
                            int layerIndex, const LayerConnections &connections) {
  std::string text;
  llvm::raw_string_ostream os(text);
  // Warnings are always collected, so the cache keeps them for runs that
  // show them, and dropped here when hidden.
  FrontendOptions frontend;
  frontend.includePaths = options.includePaths;
  frontend.camera = options.camera;
  frontend.colorSpace = options.colorSpace;
  frontend.defines = options.defines;
  frontend.rayType = options.rayType;
  frontend.userData = options.userData;
  frontend.layerName = layerName.str();
  frontend.layerIndex = layerIndex;
  frontend.groupLayer = !layerName.empty(); // only a group's layers are named here
  frontend.groupName = options.groupName;
  frontend.warningsAsErrors = options.warningsAsErrors;
  frontend.debugNan = options.debugNan;
  frontend.connectedInputs = connections.inputs;
  frontend.connectedOutputs = connections.outputs;
  frontend.connectedArrayLengths = connections.arrayLengths;
  frontend.perGeometryParams = connections.perGeometry;
  frontend.userdataIsConnected = options.userdataIsConnected;
  auto module = parseOslShader(source, filename, context, params, os, frontend);
  if (module && options.optimizationWarnings) {
    std::string layer = layerName.str();
    if (layer.empty())
      module->walk([&](mlir::func::FuncOp f) { layer = f.getSymName().str() + "_0"; });
    tagLayerForWarnings(*module, layer);
  }
  llvm::SmallVector<llvm::StringRef> lines;
  llvm::StringRef(text).split(lines, '\n', -1, /*KeepEmpty=*/false);
  // An indented line continues the diagnostic above it (the candidates
  // listed under an "Ambiguous call" warning): it is hidden, cached and
  // replayed with it.
  bool isWarning = false;
  for (llvm::StringRef line : lines) {
    if (!line.starts_with(" "))
      isWarning = line.contains(": warning: ");
    if (isWarning)
      warnings += (line + "\n").str();
    if (!isWarning || options.showWarnings)
      errs << line << "\n";
  }
  errs.flush();
  return module;
}

bool ShaderCompiler::parse(llvm::StringRef source, llvm::StringRef filename) {
  ScopedTimer timer(stats, "front end");
  if (filename.ends_with(".mlir")) {
    // osl dialect written or edited by hand: the IR is the interface.
    llvm::SourceMgr sourceMgr;
    sourceMgr.AddNewSourceBuffer(
        llvm::MemoryBuffer::getMemBuffer(source, filename), llvm::SMLoc());
    mlir::SourceMgrDiagnosticHandler handler(sourceMgr, &context, errs);
    mlirModule = mlir::parseSourceFile<mlir::ModuleOp>(sourceMgr, &context);
  } else {
    mlirModule = parseSource(source, filename, options.params, "", 0,
                             LayerConnections{{}, options.rendererOutputs, {}, {}});
  }
  if (!mlirModule)
    return false;
  isGroup = false;
  collectOutputs();
  return true;
}

void ShaderCompiler::collectOutputs() {
  // Output rows follow the order of osl.output ops, as in the lowering.
  outputSpecs.clear();
  mlirModule->walk([&](mlir::func::FuncOp f) { shaderName = f.getSymName().str(); });
  mlirModule->walk([&](mlir::osl::OutputOp out) {
    mlir::Type t = mlir::osl::getUniformType(out.getValue().getType());
    int channels = mlir::osl::isTriple(t) ? 3 : 1;
    // An array output is one osl.output per element, in consecutive rows:
    // one image with the elements' channels side by side.
    if (out.getIndex() && !outputSpecs.empty() &&
        outputSpecs.back().name == out.getName())
      outputSpecs.back().channels += channels;
    else
      outputSpecs.push_back({out.getName().str(), channels,
                             mlir::isa<mlir::osl::ClosureType>(t), t.isInteger(32)});
  });
}

bool ShaderCompiler::lower() {
  std::optional<ScopedTimer> timer(std::in_place, stats, "mlir passes");
  // The osl-level passes are verified after each one: their verifiers
  // report the shader's errors. The lowering (most of the passes' time) is
  // verified once at its end unless asked (CompileOptions::verifyEachPass).
  mlir::osl::OslToLLVMPipelineOptions pipeline{options.width, options.reference,
                                               options.countLanes, options.math,
                                               options.inlineLibrary,
                                               options.outlineEveryRoutine,
                                               /*libraryAvailable=*/nullptr};
  // Noise routines compiled before are looked up as the kernel is
  // converted; their code is not built (LibraryObjects.h).
  library = LibraryUse();
  if (splitLibrary)
    pipeline.libraryAvailable = libraryObjectFinder(libraryKeyOptions(), library);
  mlir::PassManager oslLevel(&context);
  mlir::osl::buildOslLevelPipeline(oslLevel, pipeline);
  mlir::PassManager vectorLevel(&context), lowering(&context);
  vectorLevel.enableVerifier(options.verifyEachPass);
  mlir::osl::buildVectorLevelPipeline(vectorLevel, pipeline);
  lowering.enableVerifier(options.verifyEachPass);
  mlir::osl::buildLLVMDialectPipeline(lowering, pipeline);
  // Pass failures report through the context's diagnostics, with the
  // shader's file:line:col locations.
  auto handler = printErrors(context, errs);
  if (isGroup && !specialiseGroup())
    return false;
  if (mlir::failed(oslLevel.run(*mlirModule)))
    return false;
  if (options.optimizationWarnings) {
    // Asked for, so shown even where warnings are hidden (-w); kept for
    // the kernel cache to replay.
    reports = optimizationWarnings(*mlirModule, groupNameOrDefault(options.groupName),
                                   /*errorCalls=*/!options.lazyError);
    errs << reports;
  }
  if (options.reportGlobalsNeeded) {
    std::string needed = globalsNeededReport(*mlirModule);
    errs << needed;
    reports += needed;
  }
  if (mlir::failed(vectorLevel.run(*mlirModule)))
    return false;
  if (splitLibrary) {
    // Known library functions lose their bodies before the rest lowers.
    timer.reset();
    findLibraryObjects(*mlirModule, libraryKeyOptions(), stats, library);
    timer.emplace(stats, "mlir passes");
  }
  return mlir::succeeded(lowering.run(*mlirModule)) &&
         mlir::succeeded(mlir::verify(*mlirModule));
}

LibraryKeyOptions ShaderCompiler::libraryKeyOptions() const {
  return {options.llvmPipeline, mlir::osl::mathLevelName(options.math), options.cacheDir};
}

bool ShaderCompiler::translate() {
  if (splitLibrary) {
    // Each library function still to compile leaves the kernel for a
    // module of its own, compiled beside it (generateCode).
    ScopedTimer timer(stats, "library");
    std::string error;
    libraryJobs = splitLibraryJobs(*mlirModule, library, error);
    if (!error.empty()) {
      errs << "error: " << error << "\n";
      return false;
    }
  }
  {
    ScopedTimer timer(stats, "llvm translate");
    llvmIR.reset(); // an earlier compile's, of the context replaced here
    llvmContext = std::make_unique<llvm::LLVMContext>();
    llvmIR = mlir::translateModuleToLLVMIR(*mlirModule, *llvmContext, shaderName);
    if (!llvmIR) {
      errs << "error: translation to LLVM IR failed\n";
      return false;
    }
  }
  auto created = Jit::create(stats);
  if (!created) {
    errs << "error: " << llvm::toString(created.takeError()) << "\n";
    return false;
  }
  jit = std::move(*created);
  if (llvm::Error e = jit->optimize(*llvmIR, options.llvmPipeline)) {
    errs << "error: " << llvm::toString(std::move(e)) << "\n";
    return false;
  }
  return true;
}

/// The threads that generate code: one per core, the compiling thread one
/// of them. Kept for the process, so each keeps its TargetMachine.
static ThreadPool &codegenThreads() {
  static ThreadPool pool(0);
  return pool;
}

bool ShaderCompiler::generateCode() {
  ScopedTimer timer(stats, "jit codegen");
  LibraryKeyOptions keyOptions = libraryKeyOptions();
  std::string kernelError;
  auto kernel = [&] {
    auto object = Jit::generateObject(*llvmIR);
    if (object)
      kernelObject = std::move(*object);
    else
      kernelError = llvm::toString(object.takeError());
  };
  if (libraryJobs.empty() || options.compileThreads == 1) {
    kernel();
    for (LibraryJob &job : libraryJobs)
      compileLibraryJob(job, keyOptions);
  } else {
    // The kernel first: it is usually the largest.
    codegenThreads().parallelFor(int(libraryJobs.size()) + 1, [&](int task) {
      if (task == 0)
        kernel();
      else
        compileLibraryJob(libraryJobs[size_t(task) - 1], keyOptions);
    });
  }
  timer.stop();
  std::string error;
  ScopedTimer store(stats, "library store");
  bool kept = keepLibraryObjects(libraryJobs, library, keyOptions, error);
  store.stop();
  libraryJobs.clear();
  llvmIR.reset(); // codegen rewrote it; the object is what is left
  llvmContext.reset();
  if (!kernelError.empty() || !kept) {
    errs << "error: " << (kernelError.empty() ? error : kernelError) << "\n";
    return false;
  }
  return true;
}

/// The runtime entry points kernels call, bound by name from the ABI's list.
bool ShaderCompiler::defineRuntimeSymbols(Jit &target) {
  std::vector<std::pair<llvm::StringRef, void *>> symbols;
  ::osl::abi::forEachEntryPointAddress(
      [&](const char *name, void *address) { symbols.emplace_back(name, address); });
  if (llvm::Error e = target.defineSymbols(symbols)) {
    errs << "error: " << llvm::toString(std::move(e)) << "\n";
    return false;
  }
  return true;
}

/// The library functions' objects a kernel calls, handed to its JIT.
static bool addLibraryObjects(Jit &target, llvm::ArrayRef<llvm::StringRef> objects,
                              llvm::raw_ostream &errs) {
  for (llvm::StringRef object : objects)
    if (llvm::Error e = target.addObject(llvm::MemoryBuffer::getMemBufferCopy(object))) {
      errs << "error: " << llvm::toString(std::move(e)) << "\n";
      return false;
    }
  return true;
}

std::unique_ptr<CompiledShader> ShaderCompiler::load() {
  if (!generateCode())
    return nullptr;
  std::vector<llvm::StringRef> libraries;
  for (const auto &object : library.objects)
    libraries.push_back(*object);
  return linkKernel(std::move(jit), libraries, kernelObject, shaderName, outputSpecs,
              /*reportLookupError=*/true);
}

std::unique_ptr<CompiledShader>
ShaderCompiler::linkKernel(std::unique_ptr<Jit> target, llvm::ArrayRef<llvm::StringRef> libraries,
                     llvm::StringRef object, const std::string &name,
                     const std::vector<OutputSpec> &outputs, bool reportLookupError) {
  if (!defineRuntimeSymbols(*target) || !addLibraryObjects(*target, libraries, errs))
    return nullptr;
  if (llvm::Error e = target->addObject(llvm::MemoryBuffer::getMemBufferCopy(object))) {
    errs << "error: " << llvm::toString(std::move(e)) << "\n";
    return nullptr;
  }
  auto symbol = target->lookup("osl_batch");
  if (!symbol) {
    if (reportLookupError)
      errs << "error: " << llvm::toString(symbol.takeError()) << "\n";
    else
      llvm::consumeError(symbol.takeError());
    return nullptr;
  }
  auto shader = std::make_unique<CompiledShader>();
  shader->kernel = reinterpret_cast<BatchKernel>(*symbol);
  shader->width = options.width;
  shader->name = name;
  shader->outputs = outputs;
  shader->jit = std::move(target);
  return shader;
}

std::unique_ptr<CompiledShader> ShaderCompiler::compileStages(llvm::StringRef source,
                                                              llvm::StringRef filename) {
  if (!parse(source, filename) || !lower() || !translate())
    return nullptr;
  return load();
}

std::unique_ptr<CompiledShader> ShaderCompiler::loadObject(const CachedKernel &entry) {
  auto created = Jit::create(stats);
  if (!created) {
    errs << "error: " << llvm::toString(created.takeError()) << "\n";
    return nullptr;
  }
  std::vector<llvm::StringRef> libraries(entry.libraries.begin(), entry.libraries.end());
  // A cached object whose entry point is missing is compiled again
  // (silently; other failures print their error first).
  return linkKernel(std::move(*created), libraries, entry.object, entry.shaderName, entry.outputs,
              /*reportLookupError=*/false);
}

std::string ShaderCompiler::cacheKey(llvm::StringRef source, llvm::StringRef filename) const {
  std::string text = filename.ends_with(".mlir")
                         ? (filename + "\n" + source).str()
                         : preprocessedFingerprint(source, filename, options.includePaths,
                                                   options.defines);
  if (text.empty())
    return "";
  std::string key = optionsKey();
  llvm::raw_string_ostream os(key);
  for (const ParamOverride &p : options.params)
    os << "param " << p.name.size() << ":" << p.name << " " << p.value.size() << ":" << p.value
       << "\n";
  os << "source" << text;
  return key;
}

std::string ShaderCompiler::optionsKey() const {
  std::string key;
  llvm::raw_string_ostream os(key);
  // Every option the kernel depends on, one per line.
  os << "osl-mlir kernel 1\ncompiler " << KernelCache::compilerIdentity()
     << "\nllvm " LLVM_VERSION_STRING "\nhost " << Jit::hostDescription()
     << "\nwidth " << options.width << "\nreference " << options.reference
     << "\ncount lanes " << options.countLanes
     << "\nmath " << mlir::osl::mathLevelName(options.math)
     << "\ninline library " << options.inlineLibrary
     << "\noutline every routine " << options.outlineEveryRoutine << "\nllvm pipeline "
     << int(options.llvmPipeline)
     << "\ncolorspace " << options.colorSpace << "\nraytype " << options.rayType
     << "\ngroup name " << options.groupName
     << "\nuserdata is connected " << options.userdataIsConnected
     << "\noptimization warnings " << options.optimizationWarnings
     << "\nreport globals needed " << options.reportGlobalsNeeded
     << "\nlazy error " << options.lazyError;
  for (const std::string &o : options.rendererOutputs)
    os << "\nrenderer output " << o.size() << ":" << o;
  for (const UserDatum &d : options.userData)
    os << "\nuserdata " << d.type << " " << d.name << " " << d.value;
  os
     // -Werror decides whether a shader with warnings compiles at all.
     << "\nwerror " << options.warningsAsErrors << "\ndebugnan " << options.debugNan
     << "\ncamera " << options.camera.xres << " "
     << options.camera.yres << "\n";
  return key;
}

std::unique_ptr<CompiledShader> ShaderCompiler::compile(llvm::StringRef source,
                                                        llvm::StringRef filename) {
  cacheUsed = CacheUse::Off;
  std::string key;
  if (!options.cacheDir.empty()) {
    ScopedTimer timer(stats, "kernel cache");
    key = cacheKey(source, filename);
  }
  if (key.empty())
    return compileStages(source, filename);
  return compileCached(key, [&] { return compileStages(source, filename); });
}

std::unique_ptr<CompiledShader>
ShaderCompiler::compileCached(const std::string &key,
                              llvm::function_ref<std::unique_ptr<CompiledShader>()> stages) {
  KernelCache cache(options.cacheDir);
  CachedKernel entry;
  CacheLookup found;
  {
    ScopedTimer timer(stats, "kernel cache");
    found = cache.lookup(key, entry);
  }
  if (found == CacheLookup::Hit) {
    if (auto shader = loadObject(entry)) {
      cacheUsed = CacheUse::Hit;
      // The same warnings as the compile that stored it.
      if (options.showWarnings)
        errs << entry.warnings;
      errs << entry.reports;
      return shader;
    }
    found = CacheLookup::Corrupt; // a well-formed file the linker refused
  }
  cacheUsed = found == CacheLookup::Miss ? CacheUse::Miss : CacheUse::Rebuilt;
  std::unique_ptr<CompiledShader> shader = stages();
  if (!shader || kernelObject.empty())
    return shader;
  ScopedTimer timer(stats, "kernel cache");
  std::string error;
  CachedKernel stored{shader->name, shader->outputs, kernelObject,
                      {}, warnings, reports};
  for (const auto &object : library.objects)
    stored.libraries.push_back(*object);
  // A cache that cannot be written costs the next run a compile, nothing
  // more: say so and go on.
  if (!cache.store(key, stored, error))
    errs << "warning: kernel cache: " << error << "\n";
  return shader;
}

//===----------------------------------------------------------------------===//
// Shader groups
//===----------------------------------------------------------------------===//

namespace {
int countOps(mlir::Operation *root) {
  int n = 0;
  root->walk([&](mlir::Operation *op) {
    if (!mlir::isa<mlir::func::FuncOp, mlir::func::ReturnOp, mlir::ModuleOp>(op))
      ++n;
  });
  return n;
}

/// A connection's parameter name without an element or component index.
std::string connectedName(llvm::StringRef name) { return name.split('[').first.str(); }

/// Layer `index`'s connected inputs and outputs: those connections name,
/// and the group outputs the renderer reads (ShaderGroup::outputs: the
/// root layer's by name, another layer's as LAYER.NAME).
/// The lengths of each parsed layer's array outputs, by layer and output.
using OutputLengths = llvm::StringMap<llvm::StringMap<int>>;

LayerConnections connectionsOf(const ShaderGroup &group, size_t index,
                               const OutputLengths &outputLengths) {
  LayerConnections c;
  const std::string &layer = group.layers[index].name;
  c.perGeometry = group.layers[index].userdata;
  for (const GroupConnection &k : group.connections) {
    if (k.toLayer == layer) {
      c.inputs.push_back(connectedName(k.toInput));
      auto from = outputLengths.find(k.fromLayer);
      if (from != outputLengths.end())
        if (auto length = from->second.find(k.fromOutput); length != from->second.end())
          c.arrayLengths.push_back({k.toInput, length->second});
    }
    if (k.fromLayer == layer)
      c.outputs.push_back(connectedName(k.fromOutput));
  }
  bool root = index + 1 == group.layers.size();
  for (llvm::StringRef output : group.outputs) {
    auto [prefix, rest] = output.split('.');
    if (!rest.empty() && group.findLayer(prefix.str()))
      output = prefix == layer ? rest : llvm::StringRef();
    else if (!root)
      output = llvm::StringRef();
    if (!output.empty())
      c.outputs.push_back(connectedName(output));
  }
  return c;
}
} // namespace

bool ShaderCompiler::parseGroup(const ShaderGroup &group) {
  ScopedTimer timer(stats, "front end");
  std::string error;
  if (!group.validate(error)) {
    errs << "error: " << error << "\n";
    return false;
  }
  mlirModule = mlir::ModuleOp::create(mlir::UnknownLoc::get(&context));
  mlir::OpBuilder b(&context);
  groupCounts = GroupStats();
  groupCounts.layersBefore = int(group.layers.size());
  OutputLengths outputLengths;
  for (size_t layerIndex = 0; layerIndex < group.layers.size(); ++layerIndex) {
    const auto &layer = group.layers[layerIndex];
    auto buffer = llvm::MemoryBuffer::getFile(layer.shaderPath, /*IsText=*/true);
    if (!buffer) {
      errs << "error: layer '" << layer.name << "': cannot read '" << layer.shaderPath
           << "': " << buffer.getError().message() << "\n";
      return false;
    }
    auto parsed = parseSource((*buffer)->getBuffer(), layer.shaderPath, layer.params, layer.name,
                              int(layerIndex), connectionsOf(group, layerIndex, outputLengths));
    if (!parsed) {
      errs << "note: in layer '" << layer.name << "'\n";
      return false;
    }
    parsed->walk([&](mlir::osl::OutputOp out) {
      if (std::optional<int64_t> element = out.getIndex()) {
        int &length = outputLengths[layer.name][out.getName()];
        length = std::max(length, int(*element) + 1);
      }
    });
    auto funcs = llvm::to_vector(parsed->getOps<mlir::func::FuncOp>());
    if (funcs.size() != 1) {
      errs << "error: layer '" << layer.name << "': expected one shader in '"
           << layer.shaderPath << "'\n";
      return false;
    }
    mlir::func::FuncOp func = funcs.front();
    std::string shader = func.getSymName().str();
    func.setSymName("layer." + layer.name);
    func->setAttr("osl.layer", b.getStringAttr(layer.name));
    func->setAttr("osl.layer_shader", b.getStringAttr(shader));
    // Its place among the entries: OSL runs them in the order given.
    if (auto it = llvm::find(group.entries, layer.name); it != group.entries.end())
      func->setAttr("osl.entry", b.getI64IntegerAttr(it - group.entries.begin()));
    const auto &named = group.namedEntries.empty() ? group.entries : group.namedEntries;
    if (llvm::is_contained(named, layer.name))
      func->setAttr("osl.entry_named", b.getUnitAttr());
    groupCounts.opsBefore += countOps(func);
    if (!markGroupInputs(func, layer, group, shader, errs))
      return false;
    for (mlir::Operation &op : llvm::make_early_inc_range(*parsed->getBody())) {
      op.remove();
      mlirModule->getBody()->push_back(&op);
    }
  }
  if (group.runsNoLayer)
    (*mlirModule)->setAttr("osl.no_entries", b.getUnitAttr());
  if (!group.outputs.empty())
    (*mlirModule)->setAttr("osl.group_outputs", b.getStrArrayAttr(llvm::to_vector(
                                                    llvm::map_range(group.outputs, [](auto &s) {
                                                      return llvm::StringRef(s);
                                                    }))));
  mlir::PassManager pm(&context);
  mlir::osl::LinkShaderGroupOptions link;
  link.lazy = group.optimization == GroupOptimization::O2;
  link.opaqueParams = group.optimization == GroupOptimization::O0;
  link.lazyGlobals = group.lazyGlobals;
  link.lazyError = options.lazyError;
  link.traceLayers = group.traceLayers;
  pm.addPass(mlir::osl::createLinkShaderGroup(link));
  auto handler = printErrors(context, errs);
  if (mlir::failed(pm.run(*mlirModule)))
    return false;
  isGroup = true;
  mlirModule->walk([&](mlir::func::FuncOp f) { shaderName = f.getSymName().str(); });
  collectOutputs();
  return true;
}

bool ShaderCompiler::specialiseGroup() {
  // Constant parameters folded through the whole group (the pipeline
  // starts with the same binding, then finds nothing left to do); done here
  // so that the layers left can be counted while ops still carry their layer.
  mlir::PassManager pm(&context);
  mlir::OpPassManager &fn = pm.nest<mlir::func::FuncOp>();
  fn.addPass(mlir::osl::createBindParams());
  fn.addPass(mlir::osl::createFoldConstants());
  fn.addPass(mlir::createCanonicalizerPass());
  fn.addPass(mlir::createCSEPass());
  if (mlir::failed(pm.run(*mlirModule)))
    return false;
  llvm::StringSet<> layersLeft;
  int ops = 0;
  mlirModule->walk([&](mlir::func::FuncOp f) {
    ops += countOps(f);
    f.walk([&](mlir::Operation *op) {
      auto layer = op->getAttrOfType<mlir::StringAttr>("osl.from_layer");
      if (!layer)
        return;
      if (!mlir::isa<mlir::arith::ConstantOp>(op))
        layersLeft.insert(layer.getValue());
      op->removeAttr("osl.from_layer");
    });
  });
  groupCounts.opsAfter = ops;
  groupCounts.layersAfter = int(layersLeft.size());
  return true;
}

std::string ShaderCompiler::groupCacheKey(const ShaderGroup &group) const {
  std::string key = optionsKey();
  llvm::raw_string_ostream os(key);
  auto field = [&](const std::string &s) { os << " " << s.size() << ":" << s; };
  os << "group O" << int(group.optimization) << " lazyglobals " << group.lazyGlobals
     << " tracelayers " << group.traceLayers << "\n";
  for (const GroupLayer &layer : group.layers) {
    auto buffer = llvm::MemoryBuffer::getFile(layer.shaderPath, /*IsText=*/true);
    if (!buffer)
      return ""; // compiling reports it
    std::string text =
        preprocessedFingerprint((*buffer)->getBuffer(), layer.shaderPath,
                                options.includePaths, options.defines);
    if (text.empty())
      return "";
    os << "layer";
    field(layer.name);
    for (const ParamOverride &p : layer.params) {
      os << "\nparam";
      field(p.name);
      field(p.value);
    }
    for (const std::string &u : layer.userdata) {
      os << "\nuserdata";
      field(u);
    }
    os << "\nsource";
    field(text);
    os << "\n";
  }
  for (const GroupConnection &c : group.connections) {
    os << "connect";
    for (const std::string *s : {&c.fromLayer, &c.fromOutput, &c.toLayer, &c.toInput})
      field(*s);
    os << "\n";
  }
  for (const std::string &e : group.entries) {
    os << "entry";
    field(e);
    os << "\n";
  }
  if (group.runsNoLayer)
    os << "no layer runs\n";
  for (const std::string &e : group.namedEntries) {
    os << "named entry";
    field(e);
    os << "\n";
  }
  for (const std::string &o : group.outputs) {
    os << "output";
    field(o);
    os << "\n";
  }
  return key;
}

std::unique_ptr<CompiledShader> ShaderCompiler::compileGroup(const ShaderGroup &group) {
  cacheUsed = CacheUse::Off;
  auto stages = [&]() -> std::unique_ptr<CompiledShader> {
    if (!parseGroup(group) || !lower() || !translate())
      return nullptr;
    return load();
  };
  std::string key;
  if (!options.cacheDir.empty()) {
    ScopedTimer timer(stats, "kernel cache");
    key = groupCacheKey(group);
  }
  if (key.empty())
    return stages();
  return compileCached(key, stages);
}
