//===- ExprParser.h - OSL expressions to a syntax tree ---------*- C++ -*-===//
//
// Precedence climbing over OSL's operators: assignment, the ternary,
// binary operators by precedence, unary and postfix operators, calls,
// constructors, casts and initializer lists.
//
//===----------------------------------------------------------------------===//
#ifndef OSLFRONTEND_EXPRPARSER_H
#define OSLFRONTEND_EXPRPARSER_H

#include "TokenParser.h"

#include <cerrno>
#include <cstdlib>

namespace osl::frontend {

class ExprParser : public TokenParser {
public:
  using TokenParser::TokenParser;

protected:
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
        // oslc's grammar has no trailing comma here (unlike after the last
        // parameter): a shader that has one does not compile with OSL.
        if (cur().isPunct("}")) {
          errorExpected("an expression after ',' in initializer list");
          return nullptr;
        }
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
    // OSL's compound assignments are + - * / & | ^ << >> (oslc: `%=` is a
    // syntax error).
    if (op.text == "%=") {
      error(op.loc, "OSL has no '%=' (oslc: syntax error); write 'x = x % y'");
      return nullptr;
    }
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
    bool parenthesized = cur().isPunct("(");
    ExprPtr e = parsePrimary();
    if (!e)
      return nullptr;
    while (true) {
      const Token &t = cur();
      // OSL's grammar indexes and selects fields of variables only: oslc
      // rejects (a).x, f(x)[0] and vector(1).y as syntax errors.
      bool selects = (t.isPunct("[") && !peek(1).isPunct("[")) || t.isPunct(".");
      if (selects && (parenthesized || (e->kind != ExprKind::Ident &&
                                        e->kind != ExprKind::Index &&
                                        e->kind != ExprKind::Member))) {
        error(t.loc, "'" + t.text + "' applies to a variable only, not to " +
                         (parenthesized ? "a parenthesized expression"
                                        : "the value of an expression") +
                         " (oslc: syntax error); assign the value to a variable first");
        return nullptr;
      }
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
};

} // namespace osl::frontend

#endif // OSLFRONTEND_EXPRPARSER_H
