//===- IncludedFiles.cpp - The headers a shader includes ------------------===//
#include "OslFrontend/Frontend.h"

#include "Preprocessor.h"

#include "llvm/ADT/StringSet.h"

using namespace osl::frontend;

std::optional<std::vector<osl::IncludedFile>>
osl::includedFiles(llvm::StringRef source, llvm::StringRef filename, llvm::raw_ostream &errs,
                   llvm::ArrayRef<std::string> includePaths,
                   llvm::ArrayRef<std::string> defines) {
  Diagnostics diags(filename, errs);
  std::vector<Token> tokens;
  if (!lexAndPreprocess(source, diags, tokens, includePaths, defines))
    return std::nullopt;
  // The preprocessor registers each file it reads, the main one first.
  llvm::StringRef standardDir = OSL_MLIR_STDINCLUDE_DIR;
  llvm::StringSet<> seen;
  std::vector<IncludedFile> files;
  for (unsigned f = 1; f < diags.fileCount(); ++f) {
    if (diags.isFileNameOnly(f)) // a #line directive's name
      continue;
    llvm::StringRef path = diags.fileName(f);
    if (seen.insert(path).second)
      files.push_back({path.str(), path.starts_with(standardDir)});
  }
  return files;
}
