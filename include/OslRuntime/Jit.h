//===- Jit.h - Host JIT for compiled shader kernels ------------*- C++ -*-===//
//
// Everything after the compiler has produced an llvm::Module: O3 with the
// host's cost model, ORC JIT to the host CPU, symbol lookup, and assembly
// for --emit=asm. The optimizer must see the host TargetMachine: without it
// the vectorizer and cost model assume a generic x86-64 and the kernels lose
// AVX-512 / AVX2.
//
//===----------------------------------------------------------------------===//
#ifndef OSLRUNTIME_JIT_H
#define OSLRUNTIME_JIT_H

#include "llvm/ADT/ArrayRef.h"
#include "llvm/ADT/StringRef.h"
#include "llvm/Support/Error.h"

#include <memory>
#include <string>
#include <utility>

namespace llvm {
class LLVMContext;
class MemoryBuffer;
class Module;
class TargetMachine;
namespace orc {
class LLJIT;
} // namespace orc
} // namespace llvm

namespace osl {

struct Stats;

/// The LLVM passes run on a kernel before codegen.
enum class LlvmPipeline {
  /// What MLIR's lowering leaves to do: SROA, CSE, CFG cleanup, LICM (the
  /// MLIR canonicalizer has simplified the arithmetic, so instcombine
  /// would only cost time). The kernel arrives vectorized and inlined, so O3's
  /// vectorizers, inliner and unrollers mostly cost compile time (the
  /// default of CompileOptions).
  Kernel,
  /// LLVM's full O3 pipeline.
  O3,
};

class Jit {
public:
  /// A JIT for the host CPU (JITTargetMachineBuilder::detectHost, codegen
  /// level Aggressive) that resolves undefined symbols in the current
  /// process (libm, the runtime library if exported). When `stats` is set,
  /// each step adds its time there; it must outlive the Jit.
  static llvm::Expected<std::unique_ptr<Jit>> create(Stats *stats = nullptr);
  ~Jit();

  /// The host TargetMachine of the thread that created this Jit, for
  /// optimizers that need host costs (e.g. mlir::makeOptimizingTransformer);
  /// use it on that thread only.
  llvm::TargetMachine &targetMachine() { return *tm; }

  /// Verifies `module`, sets its triple and DataLayout (and host
  /// target-cpu/target-features on each definition lacking them), then runs
  /// `pipeline` with the host TargetMachine.
  llvm::Error optimize(llvm::Module &module, LlvmPipeline pipeline = LlvmPipeline::O3);

  /// `module` optimized like a kernel (optimize) and compiled for the host:
  /// an object file for addObject, e.g. a library function compiled once
  /// for many kernels.
  static llvm::Expected<std::string> compileObject(llvm::Module &module,
                                                   LlvmPipeline pipeline);
  /// Host code for `module`, optimized already (optimize), as an object
  /// file, on the calling thread's machine: any thread may compile a module
  /// whose context no other thread uses.
  static llvm::Expected<std::string> generateObject(llvm::Module &module);

  /// Hands `module` to the JIT; code is generated at the first lookup of
  /// one of its symbols. Sets the JIT's DataLayout if the module has none.
  llvm::Error addModule(std::unique_ptr<llvm::Module> module,
                        std::unique_ptr<llvm::LLVMContext> context);

  /// Hands over an object file compiled for the same host (generateObject,
  /// compileObject, or the kernel cache); it is linked at the first lookup.
  llvm::Error addObject(std::unique_ptr<llvm::MemoryBuffer> object);

  /// Defines host functions or data by address, for runtime entry points
  /// that are not exported from the executable.
  llvm::Error defineSymbols(llvm::ArrayRef<std::pair<llvm::StringRef, void *>>
                                symbols);

  /// Address of a JIT'd (or defined) symbol by its IR name; generates code
  /// for the module holding it on first use.
  llvm::Expected<void *> lookup(llvm::StringRef name);

  /// Host assembly for `module`, for --emit=asm. Works on a clone, so the
  /// module can still be optimized or JIT'd afterwards.
  static llvm::Expected<std::string> emitAssembly(llvm::Module &module,
                                                  Stats *stats = nullptr);

  /// Turns LLVM's machine scheduler off for the process (unless LLVM's
  /// command line set it): it spreads a long block's live ranges (a noise
  /// body is one block of ~700 vector instructions), and the register
  /// allocator then spends most of codegen evicting and spilling; without
  /// it Perlin noise's function compiles in 60% of the time with fewer
  /// spills, and kernels shade as fast or faster (bench/RESULTS.md). A
  /// process-wide LLVM option, so the tools call it at start, before any
  /// thread compiles; a program embedding osl-mlir beside other LLVM users
  /// chooses.
  static void disableMachineScheduler();

  /// Widest batch the host runs in vector registers: 16 with AVX-512F, 8
  /// with AVX2, else 4.
  static int hostMaxWidth();

  /// The host as code generation sees it: triple, CPU name and the features
  /// it has. Object code made for one description runs on another only if
  /// they are equal (the kernel cache's key holds it).
  static std::string hostDescription();

private:
  Jit() = default;

  Stats *stats = nullptr;
  /// The creating thread's machine (owned by that thread).
  llvm::TargetMachine *tm = nullptr;
  std::unique_ptr<llvm::orc::LLJIT> lljit;
};

} // namespace osl

#endif // OSLRUNTIME_JIT_H
