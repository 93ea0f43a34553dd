//===- TokenParser.h - The parser's token cursor and types -----*- C++ -*-===//
//
// What both the expression parser and the declaration/statement parser
// stand on: the token stream, error reporting, nesting limits, and type
// names (OSL's keywords and the structs defined so far).
//
//===----------------------------------------------------------------------===//
#ifndef OSLFRONTEND_TOKENPARSER_H
#define OSLFRONTEND_TOKENPARSER_H

#include "Parser.h"

#include "llvm/ADT/StringMap.h"
#include "llvm/ADT/StringSwitch.h"

#include <algorithm>

namespace osl::frontend {

inline bool isShaderTypeKeyword(llvm::StringRef s) {
  return s == "shader" || s == "surface" || s == "displacement" || s == "volume" ||
         s == "light";
}

/// Type names: the keywords that start a declaration.
inline bool lookupTypeName(llvm::StringRef s, BaseType &base) {
  auto r = llvm::StringSwitch<int>(s)
               .Case("int", int(BaseType::Int))
               .Case("float", int(BaseType::Float))
               .Case("point", int(BaseType::Point))
               .Case("vector", int(BaseType::Vector))
               .Case("normal", int(BaseType::Normal))
               .Case("color", int(BaseType::Color))
               .Case("string", int(BaseType::String))
               .Case("void", int(BaseType::Void))
               .Case("matrix", int(BaseType::Matrix))
               .Case("closure", int(BaseType::Closure))
               .Default(-1);
  if (r < 0)
    return false;
  base = BaseType(r);
  return true;
}

inline bool isReserved(llvm::StringRef s) {
  BaseType b;
  return lookupTypeName(s, b) ||
         llvm::StringSwitch<bool>(s)
             .Cases("if", "else", "for", "while", "do", "break", "continue", true)
             .Cases("return", "struct", "output", "uniform", "varying", true)
             .Cases("and", "or", "not", "illuminate", "illuminance", "gather", true)
             .Default(false);
}

class TokenParser {
public:
  TokenParser(const std::vector<Token> &toks, Diagnostics &diags) : toks(toks), diags(diags) {}

protected:
  // --- tokens ----------------------------------------------------------------
  const Token &cur() const { return toks[pos]; }
  const Token &peek(size_t k) const {
    return toks[std::min(pos + k, toks.size() - 1)];
  }
  void advance() {
    if (!cur().is(TokKind::Eof))
      ++pos;
  }
  bool acceptPunct(llvm::StringRef p) {
    if (!cur().isPunct(p))
      return false;
    advance();
    return true;
  }
  bool acceptIdent(llvm::StringRef s) {
    if (!cur().isIdent(s))
      return false;
    advance();
    return true;
  }
  void error(SrcLoc loc, const llvm::Twine &msg) { diags.error(loc, msg); }
  void errorExpected(const llvm::Twine &what) {
    error(cur().loc, "expected " + what + ", found " + describeToken(cur()));
  }
  bool expectPunct(llvm::StringRef p, llvm::StringRef context = "") {
    if (acceptPunct(p))
      return true;
    if (context.empty())
      errorExpected("'" + p + "'");
    else
      errorExpected("'" + p + "' " + context);
    return false;
  }

  /// Sets the height of a new node from its children; false (after an
  /// error) if the expression is too deep, e.g. a chain of thousands of
  /// binary operators.
  bool finish(Expr &e) {
    unsigned h = 0;
    for (const ExprPtr &a : e.args)
      h = std::max(h, a->height);
    e.height = h + 1;
    if (e.height > kMaxNesting * 2) {
      error(e.loc, "expression is too complex (nested too deeply)");
      return false;
    }
    return true;
  }

  /// RAII nesting counter.
  struct Nest {
    TokenParser &p;
    bool ok;
    Nest(TokenParser &p) : p(p), ok(++p.depth <= kMaxNesting) {
      if (!ok)
        p.error(p.cur().loc, "nesting is too deep");
    }
    ~Nest() { --p.depth; }
  };

  // --- types -------------------------------------------------------------------
  bool isTypeStart() const {
    const Token &t = cur();
    BaseType b;
    return t.is(TokKind::Ident) &&
           (lookupTypeName(t.text, b) || structTypes.count(t.text) || t.text == "uniform" ||
            t.text == "varying");
  }

  bool parseType(OslType &type) {
    while (cur().isIdent("uniform") || cur().isIdent("varying"))
      advance();
    if (cur().is(TokKind::Ident)) {
      auto it = structTypes.find(cur().text);
      if (it != structTypes.end()) {
        advance();
        type = OslType::ofStruct(it->second);
        return true;
      }
    }
    BaseType base;
    if (!cur().is(TokKind::Ident) || !lookupTypeName(cur().text, base)) {
      errorExpected("a type name");
      return false;
    }
    advance();
    if (base == BaseType::Closure) {
      if (!acceptIdent("color")) {
        errorExpected("'color' after 'closure'");
        return false;
      }
    }
    type = OslType(base);
    return true;
  }

  const std::vector<Token> &toks;
  Diagnostics &diags;
  size_t pos = 0;
  unsigned depth = 0;
  /// Structs defined so far: their names are type names from then on.
  llvm::StringMap<const StructDecl *> structTypes;
};

} // namespace osl::frontend

#endif // OSLFRONTEND_TOKENPARSER_H
