//===- ShaderCompiler.h - OSL source to a callable batch kernel -*- C++ -*-===//
//
// The embedding API: a renderer (or osl-run) hands over OSL source and
// gets a kernel for one width, with the stages visible in between:
//   parse()   front end -> osl dialect         (--emit=mlir prints this)
//   lower()   osl-to-llvm pipeline -> LLVM dialect
//   translate() LLVM dialect -> llvm::Module, optimized for the host (--emit=llvm/asm)
//   load()    ORC JIT -> BatchKernel
//
//===----------------------------------------------------------------------===//
#ifndef OSLCOMPILER_SHADERCOMPILER_H
#define OSLCOMPILER_SHADERCOMPILER_H

#include "OslAbi/GlobalsLayout.h"
#include "OslCompiler/LibraryObjects.h"
#include "OslCompiler/ShaderGroup.h"
#include "OslFrontend/Frontend.h"
#include "OslRuntime/Grid.h"
#include "OslRuntime/Jit.h"
#include "OslRuntime/Stats.h"
#include "OslTransforms/Passes.h"

#include "mlir/IR/MLIRContext.h"
#include "mlir/IR/OwningOpRef.h"
#include "llvm/ADT/STLFunctionalExtras.h"

#include <memory>
#include <string>
#include <vector>

namespace llvm {
class LLVMContext;
class Module;
} // namespace llvm

namespace osl {

struct CachedKernel;

struct CompileOptions {
  /// Lanes per batch: 1, 4, 8 or 16; 0 picks the widest the host supports.
  int width = 0;
  /// 1: the compiling thread generates all code; otherwise the library
  /// functions still to compile are generated beside the kernel, one
  /// thread per core (osl-run's -t).
  int compileThreads = 0;
  std::vector<ParamOverride> params;
  /// Directories searched by #include (after the including file's own).
  std::vector<std::string> includePaths;
  /// oslc's -D NAME[=VALUE] and -U NAME, in order (see osl::preprocess).
  std::vector<std::string> defines;
  /// The ray type raytype() answers 1 for (testshade's --raytype).
  std::string rayType = "camera";
  /// testshade's --userdata (FrontendOptions::userData).
  std::vector<UserDatum> userData;
  /// testshade's --groupname (getattribute "shader:groupname").
  std::string groupName;
  /// oslc's -Werror (warnings are errors) and osl-run's -w (no warnings).
  bool warningsAsErrors = false;
  bool showWarnings = true;
  /// testshade's --debugnan (FrontendOptions::debugNan).
  bool debugNan = false;
  /// Reference mode (osl-run --interpret): one point at a time with
  /// ordinary branches and no masks; implies width 1.
  bool reference = false;
  /// How math functions are computed (osl-run --math=): `Default`
  /// reproduces OSL, `Fast` uses MLIR's approximations, `Precise` is within
  /// 1 ULP. Bit-identical across widths at each level.
  mlir::osl::MathLevel math = mlir::osl::MathLevel::Default;
  /// osl-run --inline-library: noise routines inline in each kernel instead
  /// of functions compiled once and shared (OslCompiler/LibraryObjects.h).
  bool inlineLibrary = false;
  /// osl-run --outline-every-routine: no noise routine inline, however small
  /// (how the prebuilt library is built).
  bool outlineEveryRoutine = false;
  /// The renderer's image (testshade: the -g grid), which fixes the
  /// "screen", "NDC" and "raster" spaces.
  mlir::osl::CameraImage camera;
  /// The working RGB space of the color functions (OSL's "colorspace").
  std::string colorSpace = "Rec709";
  /// LLVM passes before codegen (Jit.h). The kernel pipeline by default:
  /// a fraction of O3's compile time, and it shades as fast (bench/). (Its
  /// NaN payloads could differ between widths, as the differential tester
  /// found on seed 5017; outputs now store one canonical NaN.)
  LlvmPipeline llvmPipeline = LlvmPipeline::Kernel;
  /// Masked blocks count their active lanes (osl_rt_count_lanes, OslAbi/EntryPoints.h).
  bool countLanes = false;
  /// Verify the IR after every lowering pass too (osl-run --verify-each;
  /// the differential tester turns it on). Off, the osl-level passes are
  /// still verified one by one (their verifiers report shader errors) and
  /// the lowering once at its end: verifying after each lowering pass is a
  /// large part of the MLIR passes' time.
  bool verifyEachPass = false;
  /// The outputs the renderer reads (testshade's -o names) of a single
  /// shader: isconnected() answers 2 for them. (A group's are
  /// ShaderGroup::outputs.)
  std::vector<std::string> rendererOutputs;
  /// testshade's --userdata_isconnected: isconnected() answers 1 for a
  /// lockgeom=0 parameter.
  bool userdataIsConnected = false;
  /// Report what is left to run time that OSL would fold (strings made or
  /// read while shading, texture names that are not handles), as OSL's
  /// opt_warnings does (testshade's --options opt_warnings=1).
  bool optimizationWarnings = false;
  /// Report the globals the optimized shader reads ("Need N globals: ..."),
  /// as OSL does with debugging on (testshade -debug).
  bool reportGlobalsNeeded = false;
  /// OSL's lazyerror option (testshade --options lazyerror=0): false runs
  /// a group's layers that call error() in order, so that their errors are
  /// reported even where nothing reads them; opt_warnings then names each
  /// error() call left after optimization.
  bool lazyError = true;
  /// Directory of the persistent kernel cache (KernelCache.h), used by
  /// compile(); empty: no cache.
  std::string cacheDir;
};

/// What isconnected() answers in one layer (FrontendOptions).
struct LayerConnections {
  std::vector<std::string> inputs, outputs;
  /// Parameters the command line makes per-geometry (--param:lockgeom=0).
  std::vector<std::string> perGeometry;
  /// Inputs connected to an array output, and its length.
  std::vector<std::pair<std::string, int>> arrayLengths;
};

/// What compile() did with the kernel cache.
enum class CacheUse {
  Off,     // no cache directory, or the source does not preprocess
  Hit,     // loaded: nothing was compiled
  Miss,    // compiled and stored
  Rebuilt, // the entry was corrupt or stale: compiled and replaced
};

/// What specialisation did to a group (osl-run --stats): operations in
/// the layers as the front end wrote them, and in the one group function
/// after linking, constant parameters, folding and dead-code elimination;
/// layers counted after are those with an operation left.
struct GroupStats {
  int layersBefore = 0, opsBefore = 0;
  int layersAfter = 0, opsAfter = 0;
};

/// One shader compiled for one width. Keeps its JIT alive.
class CompiledShader {
public:
  BatchKernel kernel = nullptr;
  int width = 0;
  std::string name;
  /// Output parameters in kernel row order.
  std::vector<OutputSpec> outputs;

private:
  friend class ShaderCompiler;
  std::unique_ptr<Jit> jit;
};

class ShaderCompiler {
public:
  /// Diagnostics (file:line:col: error: ...) go to `errs`.
  ShaderCompiler(const CompileOptions &options, llvm::raw_ostream &errs, Stats *stats = nullptr);
  ~ShaderCompiler();

  /// Front end; false after printing diagnostics.
  bool parse(llvm::StringRef source, llvm::StringRef filename);
  /// Runs the osl-to-llvm pipeline on the parsed module.
  bool lower();
  /// Translates to LLVM IR and optimizes it for the host.
  bool translate();
  /// JIT-compiles the optimized module into a kernel.
  std::unique_ptr<CompiledShader> load();

  /// All four stages, or, with options.cacheDir, the kernel a previous
  /// compile of the same source and options stored there.
  std::unique_ptr<CompiledShader> compile(llvm::StringRef source, llvm::StringRef filename);

  /// A shader group: every layer through the front end, then linked into
  /// one function (osl-link-group) as `group.optimization` says. Shader
  /// files are read here; false after printing diagnostics.
  bool parseGroup(const ShaderGroup &group);
  /// parseGroup and the other three stages, or the cached kernel.
  std::unique_ptr<CompiledShader> compileGroup(const ShaderGroup &group);
  /// The kernel cache's key for a group: every layer's source, parameters,
  /// connections, entries, requested outputs and the optimization level.
  std::string groupCacheKey(const ShaderGroup &group) const;
  const GroupStats &groupStats() const { return groupCounts; }

  /// The kernel cache's key for `source` under this compiler's options:
  /// everything the kernel depends on. Empty if the source does not
  /// preprocess.
  std::string cacheKey(llvm::StringRef source, llvm::StringRef filename) const;
  CacheUse cacheUse() const { return cacheUsed; }

  /// For --emit: lower() and translate() leave the library functions in
  /// the module, optimized with the kernel, instead of compiling them apart.
  void keepLibraryInModule() { splitLibrary = false; }
  /// Where the last compile found the library functions' objects.
  const LibraryUse &libraryUse() const { return library; }

  mlir::ModuleOp module() { return mlirModule.get(); }
  llvm::Module *llvmModule() { return llvmIR.get(); }
  int width() const { return options.width; }
  const std::vector<OutputSpec> &outputs() const { return outputSpecs; }

private:
  std::unique_ptr<CompiledShader> compileStages(llvm::StringRef source, llvm::StringRef filename);
  /// The cache around `stages` (compileStages or a group's).
  std::unique_ptr<CompiledShader>
  compileCached(const std::string &key,
                llvm::function_ref<std::unique_ptr<CompiledShader>()> stages);
  /// The lines of every cache key that come from the options.
  std::string optionsKey() const;
  void collectOutputs();
  /// Bind, fold and count a linked group (GroupStats).
  bool specialiseGroup();
  /// The front end on one source: its diagnostics go to `errs`, and its
  /// warnings are also kept in `warnings` for the kernel cache to replay.
  mlir::OwningOpRef<mlir::ModuleOp> parseSource(llvm::StringRef source, llvm::StringRef filename,
                                                llvm::ArrayRef<ParamOverride> params,
                                                llvm::StringRef layerName = "", int layerIndex = 0,
                                                const LayerConnections &connections = {});
  std::unique_ptr<CompiledShader> loadObject(const CachedKernel &entry);
  /// What load() and loadObject() share: the runtime's symbols, the
  /// library objects and the kernel's object go into `target`, which the
  /// shader then owns.
  std::unique_ptr<CompiledShader> linkKernel(std::unique_ptr<Jit> target,
                                       llvm::ArrayRef<llvm::StringRef> libraries,
                                       llvm::StringRef object, const std::string &name,
                                       const std::vector<OutputSpec> &outputs,
                                       bool reportLookupError);
  bool defineRuntimeSymbols(Jit &target);
  LibraryKeyOptions libraryKeyOptions() const;
  /// The kernel's and the library jobs' code, generated side by side on
  /// the codegen threads; false after printing the error.
  bool generateCode();

  CompileOptions options;
  CacheUse cacheUsed = CacheUse::Off;
  /// Compile the library functions apart (LibraryObjects.h).
  bool splitLibrary = true;
  /// The library functions the kernel calls: their objects and where
  /// they came from.
  LibraryUse library;
  /// Those still to compile (translate), compiled beside the kernel.
  std::vector<LibraryJob> libraryJobs;
  /// The kernel's object code (generateCode), linked and cached.
  std::string kernelObject;
  llvm::raw_ostream &errs;
  /// What the front end warned of in this compile.
  std::string warnings;
  /// The optimization warnings asked for (CompileOptions::optimizationWarnings).
  std::string reports;
  Stats *stats;
  mlir::MLIRContext context;
  mlir::OwningOpRef<mlir::ModuleOp> mlirModule;
  std::unique_ptr<llvm::LLVMContext> llvmContext;
  std::unique_ptr<llvm::Module> llvmIR;
  std::unique_ptr<Jit> jit;
  std::vector<OutputSpec> outputSpecs;
  std::string shaderName;
  bool isGroup = false;
  GroupStats groupCounts;
};

} // namespace osl

#endif // OSLCOMPILER_SHADERCOMPILER_H
