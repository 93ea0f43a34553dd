//===- LibraryObjects.h - Library functions compiled once -------*- C++ -*-===//
//
// osl-outline-library makes each library routine (noise of every kind) of a
// kernel one function named `osl.lib.*` (OslAbi/Library.h). Before the
// kernel is optimized, those definitions move out of its LLVM module into
// modules of their own, each compiled once per process and host and kept
// as an object: in memory for the process, and in the kernel cache's
// directory (under library/) for later runs. Every kernel calling the same
// function (same routine, signature, math and host) links the same object,
// so a shader's compile time no longer pays LLVM codegen of each noise it
// calls, much as OSL's batched backend calls its precompiled library.
//
//===----------------------------------------------------------------------===//
#ifndef OSLCOMPILER_LIBRARYOBJECTS_H
#define OSLCOMPILER_LIBRARYOBJECTS_H

#include "OslRuntime/Jit.h"

#include "llvm/Support/Error.h"

#include <memory>
#include <string>
#include <vector>

namespace llvm {
class Module;
} // namespace llvm

namespace osl {

struct Stats;

/// Where a kernel's library objects came from.
struct LibraryUse {
  int fromMemory = 0, fromDisk = 0, compiled = 0;
  /// The objects, in the order of the functions in the kernel.
  std::vector<std::shared_ptr<const std::string>> objects;
};

/// Replaces each library function defined in `kernel` by a declaration and
/// returns its object: this process's copy, the one stored under
/// `cacheDir`/library (when `cacheDir` is not empty; a bad file is
/// recompiled), or a new compile with `pipeline` (then stored in both).
/// The key of an object is the function's LLVM IR, the globals it reads,
/// the LLVM version, the host and `pipeline`.
llvm::Expected<LibraryUse> splitLibraryFunctions(llvm::Module &kernel, LlvmPipeline pipeline,
                                                 const std::string &cacheDir, Stats *stats);

} // namespace osl

#endif // OSLCOMPILER_LIBRARYOBJECTS_H
