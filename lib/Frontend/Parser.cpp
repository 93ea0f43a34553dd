//===- Parser.cpp - OSL tokens to a syntax tree ------------------------------===//
#include "Parser.h"

#include "llvm/ADT/StringMap.h"
#include "llvm/ADT/StringSwitch.h"

#include <algorithm>
#include <cerrno>
#include <cstdlib>

using namespace osl::frontend;

namespace {

bool isShaderTypeKeyword(llvm::StringRef s) {
  return s == "shader" || s == "surface" || s == "displacement" || s == "volume" ||
         s == "light";
}

/// Type names: the keywords that start a declaration.
bool lookupTypeName(llvm::StringRef s, BaseType &base) {
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

bool isReserved(llvm::StringRef s) {
  BaseType b;
  return lookupTypeName(s, b) ||
         llvm::StringSwitch<bool>(s)
             .Cases("if", "else", "for", "while", "do", "break", "continue", true)
             .Cases("return", "struct", "output", "uniform", "varying", true)
             .Cases("and", "or", "not", "illuminate", "illuminance", "gather", true)
             .Default(false);
}

class Parser {
public:
  Parser(const std::vector<Token> &toks, Diagnostics &diags)
      : toks(toks), diags(diags) {}

  bool parseProgram(Program &program) {
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
        if (fn->body)
          program.functions.push_back(std::move(fn));
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
    Parser &p;
    bool ok;
    Nest(Parser &p) : p(p), ok(++p.depth <= kMaxNesting) {
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
    if (t.isIdent("if")) {
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
    if (t.isIdent("while")) {
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
    if (t.isIdent("do")) {
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
    if (t.isIdent("for")) {
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
        if (!(e->expr = parseExpression()))
          return nullptr;
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
    if (isTypeStart()) {
      // A nested function definition: `type name (`.
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

  /// An expression or `{ a, b, ... }`; `{ }` only where `emptyAllowed`
  /// (a shader parameter's default, as oslc allows it).
  ExprPtr parseInitializer(bool emptyAllowed = false) {
    if (!cur().isPunct("{"))
      return parseAssignment();
    auto list = std::make_unique<Expr>(ExprKind::InitList, cur().loc);
    advance();
    if (acceptPunct("}")) {
      if (!emptyAllowed) {
        error(list->loc, "Empty compound initializers '{ }' only allowed for shader parameters.");
        return nullptr;
      }
      return list;
    }
    while (true) {
      ExprPtr e = parseAssignment();
      if (!e)
        return nullptr;
      list->args.push_back(std::move(e));
      if (acceptPunct(",")) {
        if (acceptPunct("}"))
          return finish(*list) ? std::move(list) : nullptr;
        continue;
      }
      if (acceptPunct("}"))
        return finish(*list) ? std::move(list) : nullptr;
      errorExpected("',' or '}' in initializer list");
      return nullptr;
    }
  }

  // --- expressions -------------------------------------------------------------
  ExprPtr parseExpression() {
    ExprPtr e = parseAssignment();
    if (!e || !cur().isPunct(","))
      return e;
    auto comma = std::make_unique<Expr>(ExprKind::Comma, cur().loc);
    comma->begin = e->begin;
    comma->args.push_back(std::move(e));
    while (acceptPunct(",")) {
      ExprPtr next = parseAssignment();
      if (!next)
        return nullptr;
      comma->args.push_back(std::move(next));
    }
    return finish(*comma) ? std::move(comma) : nullptr;
  }

  static bool isAssignOp(const Token &t) {
    static const char *ops[] = {"=", "+=", "-=", "*=", "/=", "%=",
                                "&=", "|=", "^=", "<<=", ">>="};
    if (t.kind != TokKind::Punct)
      return false;
    for (const char *op : ops)
      if (t.text == op)
        return true;
    return false;
  }

  ExprPtr parseAssignment() {
    Nest nest(*this);
    if (!nest.ok)
      return nullptr;
    ExprPtr lhs = parseTernary();
    if (!lhs)
      return nullptr;
    if (!isAssignOp(cur()))
      return lhs;
    const Token &op = cur();
    if (lhs->kind != ExprKind::Ident && lhs->kind != ExprKind::Index &&
        lhs->kind != ExprKind::Member) {
      error(op.loc, "the left side of '" + op.text + "' is not assignable");
      return nullptr;
    }
    auto e = std::make_unique<Expr>(ExprKind::Assign, op.loc);
    e->begin = lhs->begin;
    e->name = op.text;
    advance();
    ExprPtr rhs = parseAssignment();
    if (!rhs)
      return nullptr;
    e->args.push_back(std::move(lhs));
    e->args.push_back(std::move(rhs));
    if (!finish(*e))
      return nullptr;
    return e;
  }

  ExprPtr parseTernary() {
    ExprPtr cond = parseBinary(1);
    if (!cond || !cur().isPunct("?"))
      return cond;
    Nest nest(*this);
    if (!nest.ok)
      return nullptr;
    auto e = std::make_unique<Expr>(ExprKind::Ternary, cur().loc);
    e->begin = cond->begin;
    advance();
    ExprPtr a = parseAssignment();
    if (!a)
      return nullptr;
    if (!expectPunct(":", "in conditional expression"))
      return nullptr;
    ExprPtr b = parseTernary();
    if (!b)
      return nullptr;
    e->args.push_back(std::move(cond));
    e->args.push_back(std::move(a));
    e->args.push_back(std::move(b));
    if (!finish(*e))
      return nullptr;
    return e;
  }

  /// The binary operator at the cursor and its precedence (0: none).
  int binaryPrecedence(std::string &op) const {
    const Token &t = cur();
    if (t.is(TokKind::Ident)) {
      if (t.text == "or") { op = "||"; return 1; }
      if (t.text == "and") { op = "&&"; return 2; }
      return 0;
    }
    if (t.kind != TokKind::Punct)
      return 0;
    static const std::pair<const char *, int> table[] = {
        {"||", 1}, {"&&", 2}, {"|", 3},  {"^", 4},  {"&", 5},  {"==", 6},
        {"!=", 6}, {"<", 7},  {"<=", 7}, {">", 7},  {">=", 7}, {"<<", 8},
        {">>", 8}, {"+", 9},  {"-", 9},  {"*", 10}, {"/", 10}, {"%", 10}};
    for (auto &[o, prec] : table)
      if (t.text == o) {
        op = o;
        return prec;
      }
    return 0;
  }

  ExprPtr parseBinary(int minPrec) {
    ExprPtr lhs = parseUnary();
    if (!lhs)
      return nullptr;
    while (true) {
      std::string op;
      int prec = binaryPrecedence(op);
      if (prec == 0 || prec < minPrec)
        return lhs;
      SrcLoc loc = cur().loc;
      advance();
      Nest nest(*this);
      if (!nest.ok)
        return nullptr;
      ExprPtr rhs = parseBinary(prec + 1);
      if (!rhs)
        return nullptr;
      auto e = std::make_unique<Expr>(ExprKind::Binary, loc);
      e->begin = lhs->begin;
      e->name = op;
      e->args.push_back(std::move(lhs));
      e->args.push_back(std::move(rhs));
      if (!finish(*e))
        return nullptr;
      lhs = std::move(e);
    }
  }

  ExprPtr parseUnary() {
    Nest nest(*this);
    if (!nest.ok)
      return nullptr;
    const Token &t = cur();
    SrcLoc loc = t.loc;
    if (t.isPunct("-") || t.isPunct("+") || t.isPunct("!") || t.isPunct("~") ||
        t.isIdent("not")) {
      std::string op = t.isIdent("not") ? "!" : t.text;
      advance();
      ExprPtr operand = parseUnary();
      if (!operand)
        return nullptr;
      auto e = std::make_unique<Expr>(ExprKind::Unary, loc);
      e->name = op;
      e->args.push_back(std::move(operand));
      if (!finish(*e))
        return nullptr;
      return e;
    }
    if (t.isPunct("++") || t.isPunct("--")) {
      std::string op = t.text;
      advance();
      ExprPtr operand = parseUnary();
      if (!operand)
        return nullptr;
      if (operand->kind != ExprKind::Ident && operand->kind != ExprKind::Index &&
          operand->kind != ExprKind::Member) {
        error(loc, "the operand of '" + op + "' is not assignable");
        return nullptr;
      }
      auto e = std::make_unique<Expr>(ExprKind::IncDec, loc);
      e->name = op;
      e->prefix = true;
      e->args.push_back(std::move(operand));
      if (!finish(*e))
        return nullptr;
      return e;
    }
    // A cast: '(' type ')' unary.
    BaseType base;
    if (t.isPunct("(") && peek(1).is(TokKind::Ident) &&
        lookupTypeName(peek(1).text, base) && peek(2).isPunct(")")) {
      advance();
      advance();
      advance();
      ExprPtr operand = parseUnary();
      if (!operand)
        return nullptr;
      auto e = std::make_unique<Expr>(ExprKind::Cast, loc);
      e->castType = OslType(base);
      e->args.push_back(std::move(operand));
      if (!finish(*e))
        return nullptr;
      return e;
    }
    return parsePostfix();
  }

  ExprPtr parsePostfix() {
    ExprPtr e = parsePrimary();
    if (!e)
      return nullptr;
    while (true) {
      const Token &t = cur();
      if (t.isPunct("[") && !peek(1).isPunct("[")) { // `[[` starts metadata
        SrcLoc loc = t.loc;
        advance();
        ExprPtr index = parseExpression();
        if (!index)
          return nullptr;
        if (!expectPunct("]", "after array index"))
          return nullptr;
        auto ix = std::make_unique<Expr>(ExprKind::Index, loc);
        ix->begin = e->begin;
        ix->args.push_back(std::move(e));
        ix->args.push_back(std::move(index));
        if (!finish(*ix))
          return nullptr;
        e = std::move(ix);
      } else if (t.isPunct(".")) {
        SrcLoc loc = t.loc;
        advance();
        if (!cur().is(TokKind::Ident)) {
          errorExpected("a component name after '.'");
          return nullptr;
        }
        auto m = std::make_unique<Expr>(ExprKind::Member, loc);
        m->begin = e->begin;
        m->name = cur().text;
        advance();
        m->args.push_back(std::move(e));
        if (!finish(*m))
          return nullptr;
        e = std::move(m);
      } else if (t.isPunct("++") || t.isPunct("--")) {
        if (e->kind != ExprKind::Ident && e->kind != ExprKind::Index &&
            e->kind != ExprKind::Member) {
          error(t.loc, "the operand of '" + t.text + "' is not assignable");
          return nullptr;
        }
        auto inc = std::make_unique<Expr>(ExprKind::IncDec, t.loc);
        inc->begin = e->begin;
        inc->name = t.text;
        inc->prefix = false;
        advance();
        inc->args.push_back(std::move(e));
        if (!finish(*inc))
          return nullptr;
        e = std::move(inc);
      } else if (t.isPunct("(")) {
        error(t.loc, "only named functions can be called");
        return nullptr;
      } else {
        return e;
      }
    }
  }

  bool parseCallArgs(Expr &call) {
    advance(); // '('
    if (acceptPunct(")"))
      return true;
    while (true) {
      ExprPtr a = parseAssignment();
      if (!a)
        return false;
      call.args.push_back(std::move(a));
      if (acceptPunct(","))
        continue;
      if (acceptPunct(")"))
        return finish(call);
      errorExpected("',' or ')' in argument list of '" + call.name + "'");
      return false;
    }
  }

  ExprPtr parsePrimary() {
    const Token &t = cur();
    SrcLoc loc = t.loc;
    switch (t.kind) {
    case TokKind::Int: {
      auto e = std::make_unique<Expr>(ExprKind::IntLit, loc);
      unsigned long long v;
      if (llvm::StringRef(t.text).getAsInteger(0, v) || v > 0xffffffffull) {
        error(loc, "integer literal '" + t.text + "' is too large for an int");
        return nullptr;
      }
      e->intValue = (long long)(int32_t)(uint32_t)v;
      // oslc takes 2147483648 (it wraps, so that -2147483648 can be written)
      // and rejects larger decimal literals; hex literals are bit patterns.
      if (v > 0x80000000ull && !llvm::StringRef(t.text).starts_with_insensitive("0x")) {
        error(loc, "integer overflow, value must be between -2147483648 and 2147483647");
        return nullptr;
      }
      advance();
      return e;
    }
    case TokKind::Float: {
      auto e = std::make_unique<Expr>(ExprKind::FloatLit, loc);
      std::string text = t.text;
      if (!text.empty() && (text.back() == 'f' || text.back() == 'F'))
        text.pop_back();
      e->floatValue = std::strtod(text.c_str(), nullptr);
      advance();
      return e;
    }
    case TokKind::String: {
      auto e = std::make_unique<Expr>(ExprKind::StringLit, loc);
      while (cur().is(TokKind::String)) { // adjacent literals concatenate
        e->name += cur().text;
        advance();
      }
      return e;
    }
    case TokKind::Punct:
      if (t.isPunct("(")) {
        advance();
        ExprPtr e = parseExpression();
        if (!e)
          return nullptr;
        SrcLoc close = cur().loc;
        if (!expectPunct(")", "to close '('"))
          return nullptr;
        // (a, b, c) reads like a triple but is the comma operator: oslc warns.
        if (e->kind == ExprKind::Comma &&
            !diags.warning(close, "Comma operator inside parenthesis is probably an error -- "
                                  "it is not a vector/color."))
          return nullptr;
        return e;
      }
      if (t.isPunct("{"))
        return parseInitializer(); // typed by its context
      errorExpected("an expression");
      return nullptr;
    case TokKind::Eof:
      errorExpected("an expression");
      return nullptr;
    case TokKind::Ident:
      break;
    }
    BaseType base;
    if (lookupTypeName(t.text, base)) {
      if (!peek(1).isPunct("(") || base == BaseType::Void || base == BaseType::Closure) {
        error(loc, "unexpected type name '" + t.text + "' in expression");
        return nullptr;
      }
      auto e = std::make_unique<Expr>(ExprKind::Call, loc);
      e->name = t.text;
      e->isCtor = true;
      e->castType = OslType(base);
      advance();
      if (!parseCallArgs(*e))
        return nullptr;
      return e;
    }
    if (isReserved(t.text)) {
      error(loc, "unexpected '" + t.text + "' in expression");
      return nullptr;
    }
    if (peek(1).isPunct("(")) {
      auto e = std::make_unique<Expr>(ExprKind::Call, loc);
      e->name = t.text;
      advance();
      if (!parseCallArgs(*e))
        return nullptr;
      return e;
    }
    auto e = std::make_unique<Expr>(ExprKind::Ident, loc);
    e->name = t.text;
    advance();
    return e;
  }

  const std::vector<Token> &toks;
  Diagnostics &diags;
  size_t pos = 0;
  unsigned depth = 0;
  /// Structs defined so far: their names are type names from then on.
  llvm::StringMap<const StructDecl *> structTypes;
};

} // namespace

bool osl::frontend::parseProgram(const std::vector<Token> &tokens,
                                 Diagnostics &diags, Program &program) {
  Parser parser(tokens, diags);
  return parser.parseProgram(program);
}
