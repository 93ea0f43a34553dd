//===- Ast.h - OSL syntax tree ----------------------------------*- C++ -*-===//
#ifndef OSLFRONTEND_AST_H
#define OSLFRONTEND_AST_H

#include "Diagnostics.h"
#include "Types.h"

#include <memory>
#include <string>
#include <vector>

namespace osl::frontend {

struct Expr;
struct Stmt;
struct FunctionDecl;
using ExprPtr = std::unique_ptr<Expr>;
using StmtPtr = std::unique_ptr<Stmt>;

enum class ExprKind {
  IntLit,    // intValue
  FloatLit,  // floatValue
  StringLit, // name = the string
  Ident,     // name
  Unary,     // name = "-", "+", "!", "~"; args[0]
  Binary,    // name = operator ("+", "&&", "==", ...); args[0], args[1]
  Assign,    // name = "=", "+=", ...; args[0] = target, args[1] = value
  IncDec,    // name = "++" or "--"; prefix; args[0]
  Ternary,   // args = cond, then, else
  Call,      // name = function; args; ctorType set for type constructors
  Index,     // args[0][args[1]]
  Member,    // args[0].name
  Cast,      // (castType) args[0]
  InitList,  // { args... } (array initializers)
  Comma,     // args evaluated in order; the value is the last one's
};

struct Expr {
  ExprKind kind;
  /// The operator (binary, ternary, assignment, index), the callee name,
  /// or the token of a leaf.
  SrcLoc loc;
  /// Where the whole expression starts (for "cannot convert" messages).
  SrcLoc begin;
  std::string name;
  long long intValue = 0;
  double floatValue = 0;
  bool prefix = false;        // IncDec
  bool isCtor = false;        // Call: `color(...)`, `float(...)`...
  OslType castType;           // Cast target or constructor type
  std::vector<ExprPtr> args;
  /// Height of this subtree (1 for leaves); the parser bounds it so that
  /// recursive walks cannot exhaust the stack.
  unsigned height = 1;

  Expr(ExprKind kind, SrcLoc loc) : kind(kind), loc(loc), begin(loc) {}
};

struct Declarator {
  std::string name;
  SrcLoc loc;
  int arrayLen = -1; // as in OslType
  ExprPtr init;      // may be null; an InitList for arrays
};

enum class StmtKind {
  Block,    // body
  Decl,     // declType, decls
  ExprStmt, // expr
  If,       // expr, thenStmt, elseStmt (may be null)
  For,      // init (may be null), expr (cond, may be null), step (may be null), thenStmt = body
  While,    // expr, thenStmt = body
  DoWhile,  // thenStmt = body, expr
  Break,
  Continue,
  Return,   // expr (may be null)
  FuncDef,  // func (a function nested in a body)
  Empty,
};

struct Stmt {
  StmtKind kind;
  SrcLoc loc;
  std::vector<StmtPtr> body;
  OslType declType;
  std::vector<Declarator> decls;
  ExprPtr expr;
  ExprPtr step;
  StmtPtr init;
  StmtPtr thenStmt;
  StmtPtr elseStmt;
  std::unique_ptr<FunctionDecl> func;

  Stmt(StmtKind kind, SrcLoc loc) : kind(kind), loc(loc) {}
};

/// One `type name = value` of a `[[ ... ]]` metadata block.
struct Metadatum {
  OslType type;
  std::string name;
  ExprPtr value;
};

struct Param {
  OslType type;
  std::string name;
  SrcLoc loc;
  bool isOutput = false;
  ExprPtr init; // shader parameters: the default (may be an InitList)
  std::vector<Metadatum> metadata; // shader parameters

  /// Does the metadata say [[int NAME = 0]] (lockgeom, allowconnect)?
  bool intMetadataIsZero(llvm::StringRef metadataName) const {
    for (const Metadatum &m : metadata)
      if (m.name == metadataName && m.value && m.value->kind == ExprKind::IntLit)
        return m.value->intValue == 0;
    return false;
  }
};

struct FunctionDecl {
  OslType returnType;
  std::string name;
  SrcLoc loc;
  std::vector<Param> params;
  StmtPtr body; // a Block
  /// A file-level function: its place among them (0, 1, ...); -1 nested.
  int order = -1;
  /// Calls from positions past this see it: `order`, or just before the
  /// place of an earlier prototype (a declaration ending in ';').
  int visibleFrom = -1;
};

struct ShaderDecl {
  std::string shaderType; // shader, surface, displacement, volume, light
  std::string name;
  SrcLoc loc;
  /// How many functions the file defines before the shader (which of two
  /// definitions of one signature its body calls: the later).
  size_t functionsBefore = 0;
  std::vector<Param> params;
  StmtPtr body;
  std::vector<Metadatum> metadata;
};

struct StructField {
  OslType type;
  std::string name;
  SrcLoc loc;
};

/// `struct Name { fields };` Values of a struct type keep one value per
/// field; arrays of structs keep one array per field.
struct StructDecl {
  std::string name;
  SrcLoc loc;
  std::vector<StructField> fields;
  int fieldIndex(llvm::StringRef n) const {
    for (size_t i = 0; i < fields.size(); ++i)
      if (fields[i].name == n)
        return int(i);
    return -1;
  }
};

struct Program {
  std::vector<std::unique_ptr<StructDecl>> structs;
  std::vector<std::unique_ptr<FunctionDecl>> functions;
  std::unique_ptr<ShaderDecl> shader;
};

} // namespace osl::frontend

#endif // OSLFRONTEND_AST_H
