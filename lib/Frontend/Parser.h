//===- Parser.h - OSL tokens to a syntax tree -------------------*- C++ -*-===//
#ifndef OSLFRONTEND_PARSER_H
#define OSLFRONTEND_PARSER_H

#include "Ast.h"
#include "Lexer.h"

namespace osl::frontend {

/// Parses preprocessed tokens into `program`. Returns false after
/// reporting an error.
bool parseProgram(const std::vector<Token> &tokens, Diagnostics &diags,
                  Program &program);

/// Nesting deeper than this (statements or expressions) is an error, so
/// hostile input cannot exhaust the stack.
constexpr unsigned kMaxNesting = 256;

} // namespace osl::frontend

#endif // OSLFRONTEND_PARSER_H
