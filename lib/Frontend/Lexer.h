//===- Lexer.h - OSL tokens -------------------------------------*- C++ -*-===//
#ifndef OSLFRONTEND_LEXER_H
#define OSLFRONTEND_LEXER_H

#include "Diagnostics.h"

#include "llvm/ADT/StringRef.h"

#include <string>
#include <vector>

namespace osl::frontend {

/// Invalid: a character, or a string literal left open, that is no token:
/// its text is as written, an error only if the token is compiled (an
/// `#if 0` block may hold any text, as in C); invalidTokenMessage says why.
enum class TokKind { Eof, Ident, Int, Float, String, Punct, Invalid };

struct Token {
  TokKind kind = TokKind::Eof;
  /// Identifier or punctuator spelling; a string literal's value (escapes
  /// resolved); a number's spelling.
  std::string text;
  SrcLoc loc;
  /// First token on its (logical) line: preprocessor directives start so.
  bool startOfLine = false;
  /// Whitespace or a comment precedes the token (function-like macros
  /// need `NAME(` without a space).
  bool spaceBefore = false;

  bool is(TokKind k) const { return kind == k; }
  bool isPunct(llvm::StringRef p) const { return kind == TokKind::Punct && text == p; }
  bool isIdent(llvm::StringRef name) const {
    return kind == TokKind::Ident && text == name;
  }
};

struct Token;
/// Why an Invalid token is no token.
std::string invalidTokenMessage(const Token &t);

/// Splits source text into tokens (no preprocessing). Returns false after
/// reporting an error. The token list always ends with an Eof token.
/// `file` is the SrcLoc::file of the tokens.
bool lex(llvm::StringRef source, Diagnostics &diags, std::vector<Token> &out,
         unsigned file = 0);

/// Describes a token for "unexpected token" messages: 'x', end of file...
std::string describeToken(const Token &tok);

} // namespace osl::frontend

#endif // OSLFRONTEND_LEXER_H
