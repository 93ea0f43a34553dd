//===- KernelCache.h - Compiled kernels kept on disk between runs -*- C++ -*-===//
//
// A second run of the same shader with the same options on the same machine
// and compiler loads the object code the first run produced instead of
// compiling. An entry is one file named by a hash of its key; the file
// holds the whole key, the shader's output layout, the object code and a
// checksum of all of it. An entry whose checksum or key does not match
// (truncated, corrupted, a hash collision) is reported as Corrupt and never
// reaches the JIT; the caller compiles and overwrites it.
//
//===----------------------------------------------------------------------===//
#ifndef OSLCOMPILER_KERNELCACHE_H
#define OSLCOMPILER_KERNELCACHE_H

#include "OslRuntime/Grid.h"

#include "llvm/ADT/StringRef.h"

#include <string>
#include <vector>

namespace osl {

/// What a cache entry holds besides its key.
struct CachedKernel {
  std::string shaderName;
  std::vector<OutputSpec> outputs;
  /// A relocatable object file for the host, defining osl_batch.
  std::string object;
  /// The objects of the library functions it calls (LibraryObjects.h).
  std::vector<std::string> libraries;
  /// The front end's warnings when it was compiled, printed again on a hit.
  std::string warnings;
  /// Reports asked for (optimization warnings), printed again on a hit
  /// even where warnings are hidden.
  std::string reports;
};

enum class CacheLookup { Hit, Miss, Corrupt };

class KernelCache {
public:
  explicit KernelCache(std::string directory) : directory(std::move(directory)) {}

  /// $OSL_MLIR_CACHE_DIR, else $XDG_CACHE_HOME/osl-mlir, else
  /// $HOME/.cache/osl-mlir; empty when none of them is set.
  static std::string defaultDirectory();

  /// Identifies the compiler that makes the entries: the file holding this
  /// code (executable or shared library) by path, size and modification
  /// time, so a rebuilt compiler never reads an older one's entries.
  static std::string compilerIdentity();

  CacheLookup lookup(llvm::StringRef key, CachedKernel &entry) const;

  /// Writes the entry atomically (a temporary file renamed into place), so
  /// a concurrent reader sees the old entry, the new one or none. Creates
  /// the directory. False with `error` set if it cannot.
  bool store(llvm::StringRef key, const CachedKernel &entry, std::string &error) const;

  /// The file an entry with `key` lives in.
  std::string pathFor(llvm::StringRef key) const;

private:
  std::string directory;
};

} // namespace osl

#endif // OSLCOMPILER_KERNELCACHE_H
