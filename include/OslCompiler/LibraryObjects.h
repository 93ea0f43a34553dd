//===- LibraryObjects.h - Library functions compiled once -------*- C++ -*-===//
//
// Each library routine (noise of every kind, spline inversion) of a kernel
// is one function named `osl.lib.*` (OslAbi/Library.h), compiled once
// per process and host and kept as an object: in memory for the process,
// and in the kernel cache's directory (under library/) for later runs.
// Every kernel calling the same function (same routine, signature, math and
// host) links the same object, much as OSL's batched backend calls its
// precompiled library.
//
// A routine is keyed by its recipe (what its code is built from,
// OslLanes/LibraryFunctions.h) and looked up while the kernel is converted:
// one found is declared, its code never built, so the lowering, the
// translation and LLVM never see its body (most of a noise-heavy shader's
// compile time). The others are split from the kernel after the lowering,
// each into a module of its own, and compiled on the compile threads beside
// the kernel.
//
//===----------------------------------------------------------------------===//
#ifndef OSLCOMPILER_LIBRARYOBJECTS_H
#define OSLCOMPILER_LIBRARYOBJECTS_H

#include "OslLanes/LibraryFunctions.h"
#include "OslRuntime/Jit.h"

#include "llvm/ADT/StringMap.h"
#include "llvm/IR/LLVMContext.h"
#include "llvm/IR/Module.h"
#include "llvm/Support/Error.h"

#include <memory>
#include <string>
#include <vector>

namespace mlir {
class ModuleOp;
} // namespace mlir

namespace osl {

struct Stats;

/// What decides a library function's object besides its MLIR.
struct LibraryKeyOptions {
  LlvmPipeline pipeline = LlvmPipeline::Kernel;
  /// The math level the rest of the lowering applies (mathLevelName).
  std::string math;
  /// `cacheDir`/library keeps objects between runs; empty: memory only.
  std::string cacheDir;
};

/// A kernel's library functions and where their objects came from.
struct LibraryUse {
  int fromMemory = 0, fromDisk = 0, compiled = 0;
  /// Found in the library built with osl-mlir (prebuiltLibraryDirectory).
  int prebuilt = 0;
  /// The objects the kernel links.
  std::vector<std::shared_ptr<const std::string>> objects;
  /// Functions still defined in the kernel, to compile: their keys by name.
  llvm::StringMap<std::string> toCompile;
  /// Routines asked for by recipe while the kernel was converted: the
  /// object found (null: none), and the counter above its origin adds to
  /// if the kernel still calls the routine when its functions are read.
  struct Found {
    std::shared_ptr<const std::string> object;
    int LibraryUse::*origin = nullptr;
  };
  llvm::StringMap<Found> recipesFound;
};

/// Where the objects compiled when osl-mlir was built are:
/// <prefix>/share/osl-mlir/library beside <prefix>/bin of the running
/// executable (tools/osl-run/library/BuildLibrary.cmake makes them), read,
/// never written; empty when there is none or $OSL_MLIR_NO_PREBUILT_LIBRARY
/// is set (to measure compiling everything).
std::string prebuiltLibraryDirectory();

/// Answers osl-convert-to-vector whether a routine built from a recipe is
/// compiled already (this process, the cache or the prebuilt library has
/// it), adding the object to `use`; the routine is then declared, its code
/// not built. `use` must outlive the compile.
mlir::osl::LibraryObjectAvailable libraryObjectFinder(const LibraryKeyOptions &options,
                                                      LibraryUse &use);

/// For each library function defined in `module` (after
/// osl-inline-library): the object this process, the cache or the
/// prebuilt library already has (the function becomes a declaration), else
/// its key in `toCompile`; added to `use`.
/// The key is the routine's recipe, the compiler's identity, the LLVM
/// version, the host and `options`.
void findLibraryObjects(mlir::ModuleOp module, const LibraryKeyOptions &options, Stats *stats,
                        LibraryUse &use);

/// One function of `LibraryUse::toCompile` alone in an LLVM module of its
/// own context, so that any thread can compile it while the kernel compiles
/// on another.
struct LibraryJob {
  std::string name, key;
  std::unique_ptr<llvm::LLVMContext> context;
  std::unique_ptr<llvm::Module> module;
  /// Set by compileLibraryJob: the object, or why there is none.
  std::shared_ptr<const std::string> object;
  std::string error;
  /// The object came from another compile of this process meanwhile.
  bool reused = false;
};

/// Moves each function of `use.toCompile` out of `kernel` (lowered to the
/// LLVM dialect) into a job of its own, with copies of the globals and
/// declarations it uses, translated to LLVM IR; `kernel` keeps an external
/// declaration.
std::vector<LibraryJob> splitLibraryJobs(mlir::ModuleOp kernel, const LibraryUse &use,
                                         std::string &error);

/// Optimizes and compiles `job` for the host on the calling thread, unless
/// another compile of this process has its object by now. Thread-safe.
void compileLibraryJob(LibraryJob &job, const LibraryKeyOptions &options);

/// Adds the jobs' objects to `use` and keeps them, under their keys, for the
/// process and in the cache. False (with `error`) if a job failed.
bool keepLibraryObjects(std::vector<LibraryJob> &jobs, LibraryUse &use,
                        const LibraryKeyOptions &options, std::string &error);

} // namespace osl

#endif // OSLCOMPILER_LIBRARYOBJECTS_H
