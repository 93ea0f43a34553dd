//===- Preprocessor.h - A small C-style preprocessor ------------*- C++ -*-===//
//
// Supports what shaders commonly use: #include "file" and <file> (searched
// next to the including file and in -I directories; stdosl.h is built in),
// object-like and function-like #define, #undef,
// #if/#elif/#else/#endif with defined(), #ifdef/#ifndef, #pragma (ignored)
// and #error. Stringizing (#) and pasting (##) are reported unsupported.
//
//===----------------------------------------------------------------------===//
#ifndef OSLFRONTEND_PREPROCESSOR_H
#define OSLFRONTEND_PREPROCESSOR_H

#include "Lexer.h"

#include "llvm/ADT/ArrayRef.h"

namespace osl::frontend {

/// Expands `raw` (from lex()) into the token stream the parser reads.
/// Returns false after reporting an error.
/// `defines` are oslc's -D and -U, in order: "NAME", "NAME=VALUE", or
/// "-NAME" (undefine).
bool preprocess(const std::vector<Token> &raw, Diagnostics &diags,
                std::vector<Token> &out, llvm::ArrayRef<std::string> includePaths = {},
                llvm::ArrayRef<std::string> defines = {});

/// lex() then preprocess(): the tokens of `source` (file 0 of `diags`).
bool lexAndPreprocess(llvm::StringRef source, Diagnostics &diags, std::vector<Token> &out,
                      llvm::ArrayRef<std::string> includePaths = {},
                      llvm::ArrayRef<std::string> defines = {});

} // namespace osl::frontend

#endif // OSLFRONTEND_PREPROCESSOR_H
