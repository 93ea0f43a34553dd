//===- LibraryObjects.h - Library functions compiled once -------*- C++ -*-===//
//
// osl-outline-library makes each library routine (noise of every kind) of a
// kernel one function named `osl.lib.*` (OslAbi/Library.h), compiled once
// per process and host and kept as an object: in memory for the process,
// and in the kernel cache's directory (under library/) for later runs.
// Every kernel calling the same function (same routine, signature, math and
// host) links the same object, much as OSL's batched backend calls its
// precompiled library.
//
// The object is looked up as soon as the function exists (right after
// osl-outline-library), keyed by its MLIR: a function whose object is
// already known becomes a declaration there, so the rest of the lowering,
// the translation and LLVM never see its body (most of a noise-heavy
// shader's compile time). The others are compiled alone after translation.
//
//===----------------------------------------------------------------------===//
#ifndef OSLCOMPILER_LIBRARYOBJECTS_H
#define OSLCOMPILER_LIBRARYOBJECTS_H

#include "OslRuntime/Jit.h"

#include "llvm/ADT/StringMap.h"
#include "llvm/Support/Error.h"

#include <memory>
#include <string>
#include <vector>

namespace llvm {
class Module;
} // namespace llvm

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
  /// The objects the kernel links.
  std::vector<std::shared_ptr<const std::string>> objects;
  /// Functions still defined in the kernel, to compile: their keys by name.
  llvm::StringMap<std::string> toCompile;
};

/// For each library function defined in `module` (after
/// osl-outline-library): the object this process or the cache already has
/// (the function becomes a declaration), else its key in `toCompile`.
/// The key is the function's MLIR with the symbols it references, the
/// compiler's identity, the LLVM version, the host and `options`.
LibraryUse findLibraryObjects(mlir::ModuleOp module, const LibraryKeyOptions &options,
                              Stats *stats);

/// Compiles each function of `use.toCompile` defined in `kernel` alone,
/// stores its object under its key (memory and cache) and leaves a
/// declaration in `kernel`.
llvm::Error compileLibraryFunctions(llvm::Module &kernel, LibraryUse &use,
                                    const LibraryKeyOptions &options, Stats *stats);

} // namespace osl

#endif // OSLCOMPILER_LIBRARYOBJECTS_H
