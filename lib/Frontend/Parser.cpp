//===- Parser.cpp - OSL tokens to a syntax tree ------------------------------===//
//
// Declarations (structs, shaders, functions, parameters and their
// metadata) and statements; expressions are ExprParser's.
//
//===----------------------------------------------------------------------===//
#include "ExprParser.h"

#include <map>

using namespace osl::frontend;

namespace {

class Parser : public ExprParser {
public:
  using ExprParser::ExprParser;

  bool parseProgram(Program &program) {
    // Each name's first prototype: where its definition becomes callable.
    std::map<std::string, int> prototypePositions;
    while (!cur().is(TokKind::Eof)) {
      const Token &t = cur();
      if (t.isIdent("struct")) {
        if (!parseStruct(program))
          return false;
        continue;
      }
      if (t.is(TokKind::Ident) && isShaderTypeKeyword(t.text) &&
          peek(1).is(TokKind::Ident)) {
        if (program.shader) {
          error(t.loc, "only one shader per file is supported (first one is '" +
                           program.shader->name + "')");
          return false;
        }
        program.shader = parseShader();
        if (!program.shader)
          return false;
        program.shader->functionsBefore = program.functions.size();
        continue;
      }
      if (isTypeStart()) {
        OslType type;
        if (!parseType(type))
          return false;
        if (!cur().is(TokKind::Ident) || isReserved(cur().text)) {
          errorExpected("a function name");
          return false;
        }
        auto fn = parseFunctionRest(type);
        if (!fn)
          return false;
        int position = int(program.functions.size());
        if (fn->body) {
          fn->order = position;
          auto prototype = prototypePositions.find(fn->name);
          fn->visibleFrom = prototype == prototypePositions.end() ? position : prototype->second;
          program.functions.push_back(std::move(fn));
        } else {
          // The first one counts; seen from uses after it, even in the
          // function defined right after it (whose order is `position`).
          prototypePositions.emplace(fn->name, position - 1);
        }
        continue;
      }
      error(t.loc, "expected a function or shader declaration, found " +
                       describeToken(t));
      return false;
    }
    if (!program.shader) {
      error(cur().loc, "no shader declaration found (expected e.g. 'shader name(...) { ... }')");
      return false;
    }
    return true;
  }

private:
  /// `struct Name { type field [N], ...; ... };` at file scope.
  bool parseStruct(Program &program) {
    advance(); // struct
    if (!cur().is(TokKind::Ident) || isReserved(cur().text)) {
      errorExpected("a struct name");
      return false;
    }
    auto decl = std::make_unique<StructDecl>();
    decl->name = cur().text;
    decl->loc = cur().loc;
    if (structTypes.count(decl->name)) {
      error(decl->loc, "struct '" + decl->name + "' is already defined");
      return false;
    }
    advance();
    if (!expectPunct("{", "after the struct name"))
      return false;
    while (!cur().isPunct("}")) {
      if (cur().is(TokKind::Eof) || !isTypeStart()) {
        errorExpected("a field type or '}'");
        return false;
      }
      OslType type;
      if (!parseType(type))
        return false;
      while (true) {
        if (!cur().is(TokKind::Ident) || isReserved(cur().text)) {
          errorExpected("a field name");
          return false;
        }
        StructField f;
        f.name = cur().text;
        f.loc = cur().loc;
        advance();
        if (decl->fieldIndex(f.name) >= 0) {
          error(f.loc, "struct '" + decl->name + "' already has a field '" + f.name + "'");
          return false;
        }
        int len;
        if (!parseArraySuffix(len, false))
          return false;
        f.type = type;
        f.type.arrayLen = len;
        decl->fields.push_back(std::move(f));
        if (!acceptPunct(","))
          break;
      }
      if (!expectPunct(";", "after a struct field"))
        return false;
    }
    advance(); // }
    if (decl->fields.empty()) {
      error(decl->loc, "struct '" + decl->name + "' has no fields");
      return false;
    }
    if (!expectPunct(";", "after the struct definition"))
      return false;
    structTypes[decl->name] = decl.get();
    program.structs.push_back(std::move(decl));
    return true;
  }

  /// A parameter's name and optional array suffix, after its type.
  bool parseParamName(Param &p) {
    if (!cur().is(TokKind::Ident) || isReserved(cur().text)) {
      errorExpected("a parameter name");
      return false;
    }
    p.name = cur().text;
    p.loc = cur().loc;
    advance();
    int len;
    if (!parseArraySuffix(len, true))
      return false;
    p.type.arrayLen = len;
    return true;
  }

  /// `[N]` or `[]` after a declared name; `allowUnsized` for function
  /// parameters (and initialized arrays, whose length comes from the list).
  bool parseArraySuffix(int &arrayLen, bool allowUnsized) {
    arrayLen = -1;
    if (!cur().isPunct("["))
      return true;
    SrcLoc loc = cur().loc;
    advance();
    if (cur().isPunct("]")) {
      if (!allowUnsized) {
        error(loc, "array size required here");
        return false;
      }
      advance();
      arrayLen = 0;
      return true;
    }
    if (!cur().is(TokKind::Int)) {
      errorExpected("an integer array size");
      return false;
    }
    long long n;
    if (llvm::StringRef(cur().text).getAsInteger(0, n) || n <= 0 || n > 4096) {
      error(cur().loc, "array size must be between 1 and 4096, got " + cur().text);
      return false;
    }
    advance();
    arrayLen = int(n);
    return expectPunct("]", "after array size");
  }

  // --- metadata ----------------------------------------------------------------
  /// `[[ type name = value, ... ]]`, kept in `out` where it is given
  /// (shaders and their parameters), else dropped.
  bool parseMetadata(std::vector<Metadatum> *out = nullptr) {
    while (cur().isPunct("[") && peek(1).isPunct("[")) {
      advance();
      advance();
      while (!(cur().isPunct("]") && peek(1).isPunct("]"))) {
        Metadatum m;
        if (!parseType(m.type))
          return false;
        if (!cur().is(TokKind::Ident)) {
          errorExpected("a metadata name");
          return false;
        }
        m.name = cur().text;
        advance();
        int len;
        if (!parseArraySuffix(len, true))
          return false;
        m.type.arrayLen = len;
        if (!expectPunct("=", "in metadata"))
          return false;
        m.value = parseInitializer();
        if (!m.value)
          return false;
        if (out)
          out->push_back(std::move(m));
        if (!acceptPunct(",")) {
          if (!(cur().isPunct("]") && peek(1).isPunct("]"))) {
            errorExpected("',' or ']]' in metadata");
            return false;
          }
        }
      }
      advance();
      advance();
    }
    return true;
  }

  // --- declarations ------------------------------------------------------------
  std::unique_ptr<ShaderDecl> parseShader() {
    auto shader = std::make_unique<ShaderDecl>();
    shader->shaderType = cur().text;
    advance();
    if (!cur().is(TokKind::Ident) || isReserved(cur().text)) {
      errorExpected("a shader name");
      return nullptr;
    }
    shader->name = cur().text;
    shader->loc = cur().loc;
    advance();
    if (!parseMetadata(&shader->metadata))
      return nullptr;
    if (!expectPunct("(", "after the shader name"))
      return nullptr;
    if (!cur().isPunct(")")) {
      while (true) {
        Param p;
        if (acceptIdent("output"))
          p.isOutput = true;
        if (!isTypeStart()) {
          errorExpected("a shader parameter type");
          return nullptr;
        }
        if (!parseType(p.type))
          return nullptr;
        if (!parseParamName(p))
          return nullptr;
        if (!cur().isPunct("=")) {
          error(cur().loc, "shader parameter '" + p.name + "' needs a default value");
          return nullptr;
        }
        advance();
        p.init = parseInitializer(/*emptyAllowed=*/true);
        if (!p.init)
          return nullptr;
        if (!parseMetadata(&p.metadata))
          return nullptr;
        shader->params.push_back(std::move(p));
        // oslc takes a trailing comma after the last parameter.
        if (acceptPunct(",") && !cur().isPunct(")"))
          continue;
        if (cur().isPunct(")"))
          break;
        errorExpected("',' or ')' after shader parameter");
        return nullptr;
      }
    }
    advance(); // ')'
    // The shader's metadata may also follow its parameters (oslc's grammar).
    if (!parseMetadata(&shader->metadata))
      return nullptr;
    if (!cur().isPunct("{")) {
      errorExpected("'{' to begin the shader body");
      return nullptr;
    }
    shader->body = parseBlock();
    if (!shader->body)
      return nullptr;
    return shader;
  }

  /// After `type`: `name ( params ) { body }`.
  std::unique_ptr<FunctionDecl> parseFunctionRest(OslType returnType) {
    auto fn = std::make_unique<FunctionDecl>();
    fn->returnType = returnType;
    fn->name = cur().text;
    fn->loc = cur().loc;
    advance();
    if (!expectPunct("(", "after the function name"))
      return nullptr;
    if (!cur().isPunct(")")) {
      while (true) {
        Param p;
        if (acceptIdent("output"))
          p.isOutput = true;
        if (!isTypeStart()) {
          if (cur().is(TokKind::Ident) && peek(1).is(TokKind::Ident))
            error(cur().loc, "unknown type name '" + cur().text + "'");
          else
            errorExpected("a parameter type");
          return nullptr;
        }
        if (!parseType(p.type))
          return nullptr;
        if (!parseParamName(p))
          return nullptr;
        if (cur().isPunct("=")) {
          error(cur().loc, "default values for function parameters are not supported");
          return nullptr;
        }
        fn->params.push_back(std::move(p));
        if (acceptPunct(",") && !cur().isPunct(")"))
          continue;
        if (cur().isPunct(")"))
          break;
        errorExpected("',' or ')' after function parameter");
        return nullptr;
      }
    }
    advance(); // ')'
    if (!parseMetadata())
      return nullptr;
    // A declaration without a body (a prototype): the definition, which
    // calls find by name, comes elsewhere; body stays null.
    if (acceptPunct(";"))
      return fn;
    if (!cur().isPunct("{")) {
      errorExpected("'{' to begin the body of '" + fn->name + "'");
      return nullptr;
    }
    fn->body = parseBlock();
    if (!fn->body)
      return nullptr;
    return fn;
  }

  // --- statements --------------------------------------------------------------
  StmtPtr parseBlock() {
    auto block = std::make_unique<Stmt>(StmtKind::Block, cur().loc);
    advance(); // '{'
    while (!cur().isPunct("}")) {
      if (cur().is(TokKind::Eof)) {
        error(cur().loc, "expected '}' to close the block opened at line " +
                             llvm::Twine(block->loc.line) + ", found end of file");
        return nullptr;
      }
      StmtPtr s = parseStatement();
      if (!s)
        return nullptr;
      block->body.push_back(std::move(s));
    }
    advance();
    return block;
  }

  StmtPtr parseStatement() {
    Nest nest(*this);
    if (!nest.ok)
      return nullptr;
    const Token &t = cur();
    SrcLoc loc = t.loc;
    if (t.isPunct("{"))
      return parseBlock();
    if (t.isPunct(";")) {
      advance();
      return std::make_unique<Stmt>(StmtKind::Empty, loc);
    }
    if (t.isIdent("if"))
      return parseIf(loc);
    if (t.isIdent("while"))
      return parseWhile(loc);
    if (t.isIdent("do"))
      return parseDoWhile(loc);
    if (t.isIdent("for"))
      return parseFor(loc);
    if (t.isIdent("break") || t.isIdent("continue")) {
      auto s = std::make_unique<Stmt>(
          t.text == "break" ? StmtKind::Break : StmtKind::Continue, loc);
      std::string word = t.text;
      advance();
      if (!expectPunct(";", ("after '" + word + "'").c_str()))
        return nullptr;
      return s;
    }
    if (t.isIdent("return")) {
      advance();
      auto s = std::make_unique<Stmt>(StmtKind::Return, loc);
      if (!cur().isPunct(";"))
        if (!(s->expr = parseExpression()))
          return nullptr;
      if (!expectPunct(";", "after 'return'"))
        return nullptr;
      return s;
    }
    if (t.isIdent("struct")) {
      error(loc, "structs must be defined outside functions and shaders");
      return nullptr;
    }
    if (t.isIdent("else")) {
      error(loc, "'else' without a matching 'if'");
      return nullptr;
    }
    if (t.isIdent("illuminance") || t.isIdent("illuminate") || t.isIdent("gather")) {
      error(loc, "'" + t.text + "' is not supported");
      return nullptr;
    }
    if (isTypeStart())
      return parseDeclarationOrFunction(loc);
    // `Name name ...`: a declaration with an unknown type (e.g. a struct).
    if (t.is(TokKind::Ident) && !isReserved(t.text) && peek(1).is(TokKind::Ident) &&
        !isReserved(peek(1).text)) {
      error(loc, "unknown type name '" + t.text + "'");
      return nullptr;
    }
    auto s = std::make_unique<Stmt>(StmtKind::ExprStmt, loc);
    if (!(s->expr = parseExpression()))
      return nullptr;
    if (!expectPunct(";", "after expression"))
      return nullptr;
    return s;
  }

  /// `if (cond) stmt [else stmt]`, at `if`.
  StmtPtr parseIf(SrcLoc loc) {
    advance();
    auto s = std::make_unique<Stmt>(StmtKind::If, loc);
    if (!expectPunct("(", "after 'if'"))
      return nullptr;
    if (!(s->expr = parseExpression()))
      return nullptr;
    if (!expectPunct(")", "after the 'if' condition"))
      return nullptr;
    if (!(s->thenStmt = parseStatement()))
      return nullptr;
    if (acceptIdent("else"))
      if (!(s->elseStmt = parseStatement()))
        return nullptr;
    return s;
  }

  /// `while (cond) stmt`, at `while`.
  StmtPtr parseWhile(SrcLoc loc) {
    advance();
    auto s = std::make_unique<Stmt>(StmtKind::While, loc);
    if (!expectPunct("(", "after 'while'"))
      return nullptr;
    if (!(s->expr = parseExpression()))
      return nullptr;
    if (!expectPunct(")", "after the 'while' condition"))
      return nullptr;
    if (!(s->thenStmt = parseStatement()))
      return nullptr;
    return s;
  }

  /// `do stmt while (cond);`, at `do`.
  StmtPtr parseDoWhile(SrcLoc loc) {
    advance();
    auto s = std::make_unique<Stmt>(StmtKind::DoWhile, loc);
    if (!(s->thenStmt = parseStatement()))
      return nullptr;
    if (!acceptIdent("while")) {
      errorExpected("'while' after the body of 'do'");
      return nullptr;
    }
    if (!expectPunct("(", "after 'while'"))
      return nullptr;
    if (!(s->expr = parseExpression()))
      return nullptr;
    if (!expectPunct(")", "after the 'while' condition") ||
        !expectPunct(";", "after 'do ... while (...)'"))
      return nullptr;
    return s;
  }

  /// `for (init; cond; step) stmt`, at `for`.
  StmtPtr parseFor(SrcLoc loc) {
    advance();
    auto s = std::make_unique<Stmt>(StmtKind::For, loc);
    if (!expectPunct("(", "after 'for'"))
      return nullptr;
    if (cur().isPunct(";")) {
      advance();
    } else if (isTypeStart()) {
      if (!(s->init = parseDeclaration()))
        return nullptr;
    } else {
      auto e = std::make_unique<Stmt>(StmtKind::ExprStmt, cur().loc);
      bool parenthesized = cur().isPunct("(");
      if (!(e->expr = parseExpression()))
        return nullptr;
      // oslc's grammar takes one expression here (the step may have
      // several): `for (i = 0, j = 1; ...)` is its syntax error.
      if (e->expr->kind == ExprKind::Comma && !parenthesized) {
        error(e->expr->loc, "a 'for' initializer is one expression or a declaration in OSL "
                            "(oslc: syntax error); assign the others before the loop");
        return nullptr;
      }
      if (!expectPunct(";", "after the 'for' initializer"))
        return nullptr;
      s->init = std::move(e);
    }
    if (!cur().isPunct(";"))
      if (!(s->expr = parseExpression()))
        return nullptr;
    if (!expectPunct(";", "after the 'for' condition"))
      return nullptr;
    if (!cur().isPunct(")"))
      if (!(s->step = parseExpression()))
        return nullptr;
    if (!expectPunct(")", "after the 'for' step"))
      return nullptr;
    if (!(s->thenStmt = parseStatement()))
      return nullptr;
    return s;
  }

  /// A declaration, or a nested function's definition (`type name (`).
  StmtPtr parseDeclarationOrFunction(SrcLoc loc) {
    size_t save = pos;
    OslType type;
    if (!parseType(type))
      return nullptr;
    if (cur().is(TokKind::Ident) && !isReserved(cur().text) && peek(1).isPunct("(")) {
      auto s = std::make_unique<Stmt>(StmtKind::FuncDef, loc);
      if (!(s->func = parseFunctionRest(type)))
        return nullptr;
      if (!s->func->body) // a prototype declares nothing that runs
        return std::make_unique<Stmt>(StmtKind::Block, loc);
      return s;
    }
    pos = save;
    return parseDeclaration();
  }

  /// `type name [= init] (, name [= init])* ;`
  StmtPtr parseDeclaration() {
    auto s = std::make_unique<Stmt>(StmtKind::Decl, cur().loc);
    if (!parseType(s->declType))
      return nullptr;
    if (s->declType.isVoid()) {
      error(s->loc, "variables cannot have type 'void'");
      return nullptr;
    }
    while (true) {
      Declarator d;
      if (!cur().is(TokKind::Ident) || isReserved(cur().text)) {
        errorExpected("a variable name");
        return nullptr;
      }
      d.name = cur().text;
      d.loc = cur().loc;
      advance();
      if (!parseArraySuffix(d.arrayLen, true))
        return nullptr;
      if (acceptPunct("=")) {
        if (!(d.init = parseInitializer()))
          return nullptr;
      } else if (d.arrayLen == 0) {
        error(d.loc, "array '" + d.name + "' needs a size or an initializer list");
        return nullptr;
      }
      s->decls.push_back(std::move(d));
      if (acceptPunct(","))
        continue;
      if (acceptPunct(";"))
        return s;
      errorExpected("',' or ';' in declaration");
      return nullptr;
    }
  }
};

} // namespace

bool osl::frontend::parseProgram(const std::vector<Token> &tokens,
                                 Diagnostics &diags, Program &program) {
  Parser parser(tokens, diags);
  return parser.parseProgram(program);
}
