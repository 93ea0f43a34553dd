//===- Dependencies.cpp - oslc's make dependencies ------------------------===//
#include "Dependencies.h"

#include "OslFrontend/Frontend.h"

#include "llvm/Support/FileSystem.h"
#include "llvm/Support/Path.h"
#include "llvm/Support/raw_ostream.h"

using namespace osl;

bool osl::emitDependencies(const RunOptions &options, llvm::StringRef source,
                           std::string &error) {
  const RunOptions::Dependencies &d = options.dependencies;
  if (!d.print && !d.write)
    return true;
  // A source that does not preprocess: -M reports why; after a compile
  // (-MD) the compiler has.
  std::string ignored;
  llvm::raw_string_ostream quiet(ignored);
  llvm::raw_ostream &errs = d.print ? static_cast<llvm::raw_ostream &>(llvm::errs()) : quiet;
  auto files = includedFiles(source, options.shaderPath, errs,
                             options.compile.includePaths, options.compile.defines);
  if (!files)
    return !d.print;
  std::string stem = llvm::sys::path::stem(options.shaderPath).str();
  // make's rule: "target: source \" and one continuation line per header.
  std::string rule = (d.target.empty() ? stem + ".oso" : d.target) + ": " + options.shaderPath;
  for (const IncludedFile &f : *files)
    if (d.standardHeaders || !f.standard)
      rule += " \\\n  " + f.path;
  rule += "\n";
  if (d.print)
    llvm::outs() << rule;
  if (d.write) {
    std::string path = d.file.empty() ? stem + ".d" : d.file;
    std::error_code ec;
    llvm::raw_fd_ostream file(path, ec, llvm::sys::fs::OF_Text);
    if (ec) {
      error = "cannot write '" + path + "': " + ec.message();
      return false;
    }
    file << rule;
  }
  return true;
}
