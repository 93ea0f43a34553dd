//===- ShaderSearch.cpp - Finding a shader's source by its name -------------===//
//
// oslc names its output after the shader it declares, not after the source
// file, so renderers (and OSL's own tests) name shaders whose files are
// named otherwise: raytype-envmap.osl declares `surface raytype_envmap`.
//
//===----------------------------------------------------------------------===//
#include "OslFrontend/Frontend.h"

#include "llvm/ADT/STLExtras.h"
#include "llvm/Support/FileSystem.h"
#include "llvm/Support/MemoryBuffer.h"
#include "llvm/Support/Path.h"
#include "llvm/Support/Regex.h"

#include <algorithm>

namespace osl {

namespace {

/// Whether `source` declares a shader named `name` (a shader type keyword,
/// the name, then its metadata or parameter list).
bool declaresShader(llvm::StringRef source, llvm::StringRef name) {
  llvm::Regex declaration("(^|[^A-Za-z0-9_])(shader|surface|displacement|volume|light)"
                          "[[:space:]]+" +
                          llvm::Regex::escape(name) + "[[:space:]]*(\\(|\\[\\[)");
  return declaration.match(source);
}

} // namespace

std::string findShaderSource(llvm::StringRef name, llvm::ArrayRef<std::string> dirs) {
  for (const std::string &dir : dirs) {
    llvm::SmallString<256> candidate(dir);
    llvm::sys::path::append(candidate, name + ".osl");
    if (llvm::sys::fs::is_regular_file(candidate))
      return std::string(candidate);
  }
  for (const std::string &dir : dirs) {
    std::vector<std::string> sources;
    std::error_code ec;
    for (llvm::sys::fs::directory_iterator it(dir, ec), end; it != end && !ec;
         it.increment(ec))
      if (llvm::sys::path::extension(it->path()) == ".osl")
        sources.push_back(it->path());
    llvm::sort(sources); // the same answer whatever order the directory lists
    for (const std::string &path : sources) {
      auto buffer = llvm::MemoryBuffer::getFile(path);
      if (buffer && declaresShader((*buffer)->getBuffer(), name))
        return path;
    }
  }
  return "";
}

} // namespace osl
