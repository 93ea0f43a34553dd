//===- Preprocessor.cpp - A small C-style preprocessor -----------------------===//
#include "Preprocessor.h"

#include "OslFrontend/Frontend.h"

#include "llvm/ADT/SmallVector.h"
#include "llvm/ADT/StringMap.h"
#include "llvm/ADT/StringSet.h"
#include "llvm/Support/FileSystem.h"
#include "llvm/Support/MemoryBuffer.h"
#include "llvm/Support/Path.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <optional>

using namespace osl::frontend;

namespace {

struct Macro {
  bool functionLike = false;
  /// The last parameter is `...`, named __VA_ARGS__ in the body.
  bool variadic = false;
  std::vector<std::string> params;
  std::vector<Token> body;
  /// Where it was defined (line 0: on the command line).
  SrcLoc loc{0, 0, 0};

  /// The same definition (C allows redefining a macro only so).
  bool sameAs(const Macro &o) const {
    if (functionLike != o.functionLike || variadic != o.variadic || params != o.params ||
        body.size() != o.body.size())
      return false;
    for (size_t i = 0; i < body.size(); ++i)
      if (body[i].kind != o.body[i].kind || body[i].text != o.body[i].text ||
          (i > 0 && body[i].spaceBefore != o.body[i].spaceBefore))
        return false;
    return true;
  }
};

/// Limits that keep pathological macros from running away.
constexpr unsigned kMaxExpansionDepth = 128;
constexpr size_t kMaxOutputTokens = 4u << 20;

/// Limits for #include: nesting depth (cycles end here) and file size.
constexpr unsigned kMaxIncludeDepth = 32;
constexpr uint64_t kMaxIncludeBytes = 16u << 20;

class Preprocessor {
public:
  Preprocessor(Diagnostics &diags, llvm::ArrayRef<std::string> includePaths)
      : diags(diags), includePaths(includePaths) {
    auto define = [&](const char *name, int value) {
      Macro m;
      Token t;
      t.kind = TokKind::Int;
      t.text = std::to_string(value);
      m.body.push_back(t);
      macros[name] = m;
    };
    define("OSL_VERSION_MAJOR", ::osl::kOslVersionMajor);
    define("OSL_VERSION_MINOR", ::osl::kOslVersionMinor);
    define("OSL_VERSION_PATCH", ::osl::kOslVersionPatch);
    define("OSL_VERSION", ::osl::kOslVersion);
  }

  /// -D NAME[=VALUE] (VALUE defaults to 1) and -U NAME ("-NAME").
  bool defineFromCommandLine(llvm::ArrayRef<std::string> defines) {
    for (llvm::StringRef d : defines) {
      if (d.consume_front("-")) {
        macros.erase(d);
        continue;
      }
      auto [name, value] = d.split('=');
      if (!d.contains('='))
        value = "1";
      std::vector<Token> nameTokens;
      if (name.empty() || !lex(name, diags, nameTokens) || nameTokens.size() != 2 ||
          !nameTokens[0].is(TokKind::Ident)) {
        diags.error("invalid -D macro name '" + name.str() + "'");
        return false;
      }
      Macro m;
      if (!lex(value, diags, m.body))
        return false;
      m.body.pop_back(); // Eof
      macros[name] = m;
    }
    return true;
  }

  /// Preprocesses one file's tokens into `out` (the Eof token only for
  /// the main file, at include depth 0).
  bool run(const std::vector<Token> &raw, std::vector<Token> &out, unsigned depth) {
    std::vector<Cond> outerConds;
    std::swap(outerConds, conds); // conditionals do not cross files
    unsigned outerDepth = includeDepth;
    includeDepth = depth;
    LineRemap outerRemap = lineRemap; // nor do #line directives
    lineRemap = {};
    // oslc reads the main file after a line of its own, so there __LINE__
    // is one more than the line (its messages count right); a #line
    // directive sets it right.
    lineRemap.lineMacroBias = depth == 0 ? 1 : 0;
    bool ok = runFile(raw, out);
    std::swap(outerConds, conds);
    includeDepth = outerDepth;
    lineRemap = outerRemap;
    return ok;
  }

private:
  bool runFile(const std::vector<Token> &raw, std::vector<Token> &out) {
    size_t i = 0;
    std::vector<Token> text; // a run of ordinary lines
    while (true) {
      const Token &tok = raw[i];
      if (tok.is(TokKind::Eof) || (tok.isPunct("#") && tok.startOfLine)) {
        if (!text.empty()) {
          if (!expand(text, out, {}, 0))
            return false;
          text.clear();
        }
        if (tok.is(TokKind::Eof))
          break;
        // Gather the directive's line.
        SrcLoc hashLoc = tok.loc;
        ++i;
        std::vector<Token> line;
        while (!raw[i].is(TokKind::Eof) && !raw[i].startOfLine)
          line.push_back(raw[i++]);
        if (!directive(hashLoc, line, out))
          return false;
        continue;
      }
      if (active()) {
        text.push_back(tok);
        lineRemap.apply(text.back().loc);
      }
      ++i;
    }
    if (!conds.empty()) {
      diags.error(conds.back().loc, "unterminated conditional directive (missing #endif)");
      return false;
    }
    if (includeDepth == 0)
      out.push_back(raw.back()); // Eof
    return true;
  }

  struct Cond {
    SrcLoc loc;
    bool parentActive; // the enclosing region is being compiled
    bool taken;        // some branch of this #if has been taken
    bool active;       // the current branch is being compiled
    bool sawElse;
  };

  bool active() const { return conds.empty() || conds.back().active; }

  bool directive(SrcLoc hashLoc, std::vector<Token> &line, std::vector<Token> &out) {
    if (line.empty())
      return true; // null directive
    const Token &name = line[0];
    if (!name.is(TokKind::Ident)) {
      if (!active())
        return true;
      diags.error(name.loc, "expected a preprocessor directive after '#', found " +
                                describeToken(name));
      return false;
    }
    const std::string &d = name.text;
    // Conditionals are tracked even in inactive regions.
    if (d == "if" || d == "ifdef" || d == "ifndef") {
      bool parentActive = active();
      bool value = false;
      if (parentActive) {
        if (d == "if") {
          if (!evalCondition(name, line, value))
            return false;
        } else {
          if (line.size() < 2 || !line[1].is(TokKind::Ident)) {
            diags.error(line.size() < 2 ? name.loc : line[1].loc,
                        "#" + d + " needs a macro name");
            return false;
          }
          value = macros.count(line[1].text) != 0;
          if (d == "ifndef")
            value = !value;
        }
      }
      conds.push_back({hashLoc, parentActive, value, parentActive && value, false});
      return true;
    }
    if (d == "elif" || d == "else" || d == "endif") {
      if (conds.empty()) {
        diags.error(name.loc, "#" + d + " without #if");
        return false;
      }
      Cond &c = conds.back();
      if (d == "endif") {
        conds.pop_back();
        return true;
      }
      if (c.sawElse) {
        diags.error(name.loc, "#" + d + " after #else");
        return false;
      }
      if (d == "else") {
        c.sawElse = true;
        c.active = c.parentActive && !c.taken;
        c.taken = true;
        return true;
      }
      bool value = false;
      if (c.parentActive && !c.taken) {
        if (!evalCondition(name, line, value))
          return false;
      }
      c.active = c.parentActive && !c.taken && value;
      c.taken = c.taken || value;
      return true;
    }
    if (!active())
      return true;
    if (d == "include") {
      std::string file;
      if (line.size() >= 2 && line[1].is(TokKind::String)) {
        file = line[1].text;
      } else if (line.size() >= 2 && line[1].isPunct("<")) {
        for (size_t k = 2; k < line.size() && !line[k].isPunct(">"); ++k)
          file += line[k].text;
      }
      if (file.empty()) {
        diags.error(name.loc, "malformed #include (expected \"file\" or <file>)");
        return false;
      }
      return include(name.loc, file, line[1].is(TokKind::String), out);
    }
    if (d == "define")
      return define(name, line);
    if (d == "undef") {
      if (line.size() < 2 || !line[1].is(TokKind::Ident)) {
        diags.error(name.loc, "#undef needs a macro name");
        return false;
      }
      macros.erase(line[1].text);
      return true;
    }
    if (d == "pragma")
      return pragma(line);
    if (d == "line")
      return lineDirective(name, line);
    if (d == "error") {
      std::string msg;
      for (size_t k = 1; k < line.size(); ++k)
        msg += (k > 1 ? " " : "") + line[k].text;
      diags.error(name.loc, "#error " + msg);
      return false;
    }
    diags.error(name.loc, "unsupported preprocessor directive '#" + d + "'");
    return false;
  }

  /// oslc's `#pragma error "msg"` and `#pragma warning "msg"` report msg at
  /// their line; `#pragma osl nowarn` silences the warnings of the next
  /// line; other pragmas (once...) change nothing here.
  bool pragma(const std::vector<Token> &line) {
    if (line.size() >= 3 && line[1].is(TokKind::Ident) && line[1].text == "osl" &&
        line[2].is(TokKind::Ident) && line[2].text == "nowarn") {
      SrcLoc at = line[1].loc; // numbered as the lines after #line are
      lineRemap.apply(at);
      diags.noWarningsOnLine(at.file, at.line + 1);
      return true;
    }
    if (line.size() < 3 || !line[1].is(TokKind::Ident) || !line[2].is(TokKind::String))
      return true;
    if (line[1].text == "error") {
      diags.error(line[1].loc, line[2].text);
      return false;
    }
    if (line[1].text == "warning")
      return diags.warning(line[1].loc, line[2].text);
    return true;
  }

  bool define(const Token &directiveTok, std::vector<Token> &line) {
    if (line.size() < 2 || !line[1].is(TokKind::Ident)) {
      diags.error(line.size() < 2 ? directiveTok.loc : line[1].loc,
                  "#define needs a macro name");
      return false;
    }
    Macro m;
    size_t k = 2;
    if (k < line.size() && line[k].isPunct("(") && !line[k].spaceBefore) {
      m.functionLike = true;
      ++k;
      if (k < line.size() && line[k].isPunct(")")) {
        ++k;
      } else {
        while (true) {
          if (k < line.size() && line[k].isPunct("...")) {
            m.variadic = true;
            m.params.push_back("__VA_ARGS__");
            if (++k < line.size() && line[k].isPunct(")")) {
              ++k;
              break;
            }
            diags.error(k < line.size() ? line[k].loc : line[1].loc,
                        "expected ')' after '...' in macro parameter list");
            return false;
          }
          if (k >= line.size() || !line[k].is(TokKind::Ident)) {
            diags.error(k < line.size() ? line[k].loc : line[1].loc,
                        "expected a macro parameter name");
            return false;
          }
          m.params.push_back(line[k].text);
          ++k;
          if (k < line.size() && line[k].isPunct(",")) {
            ++k;
            continue;
          }
          if (k < line.size() && line[k].isPunct(")")) {
            ++k;
            break;
          }
          diags.error(k < line.size() ? line[k].loc : line[1].loc,
                      "expected ',' or ')' in macro parameter list");
          return false;
        }
      }
    }
    for (; k < line.size(); ++k) {
      bool pasteAtEdge = line[k].isPunct("##") && (k + 1 == line.size() || m.body.empty());
      if (pasteAtEdge) {
        diags.error(line[k].loc, "'##' cannot be at either end of a macro body");
        return false;
      }
      if (m.functionLike && line[k].isPunct("#") &&
          (k + 1 >= line.size() || !line[k + 1].is(TokKind::Ident) ||
           !llvm::is_contained(m.params, line[k + 1].text))) {
        diags.error(line[k].loc, "'#' must be followed by a macro parameter");
        return false;
      }
      m.body.push_back(line[k]);
    }
    m.loc = line[1].loc;
    auto old = macros.find(line[1].text);
    if (old != macros.end() && !old->second.sameAs(m)) {
      const SrcLoc &was = old->second.loc;
      std::string where = was.line == 0 ? std::string("predefined or on the command line")
                                        : "at " + diags.fileName(was.file).str() + ":" +
                                              std::to_string(was.line);
      if (!diags.warning(line[1].loc, "macro '" + line[1].text +
                                          "' redefined (previous definition " + where + ")"))
        return false;
    }
    macros[line[1].text] = std::move(m);
    return true;
  }

  /// How a token is written in source.
  static std::string spelling(const Token &t) {
    if (!t.is(TokKind::String))
      return t.text;
    std::string s = "\"";
    for (char c : t.text) {
      if (c == '"' || c == '\\')
        s += '\\';
      if (c == '\n') {
        s += "\\n";
        continue;
      }
      s += c;
    }
    return s + "\"";
  }

  /// `#arg`: the argument as written, as a string literal.
  static Token stringize(const std::vector<Token> &arg, SrcLoc loc) {
    Token t;
    t.kind = TokKind::String;
    t.loc = loc;
    for (size_t i = 0; i < arg.size(); ++i)
      t.text += (i && arg[i].spaceBefore ? " " : "") + spelling(arg[i]);
    return t;
  }

  /// `a ## b`: the tokens on either side of each ## become one, lexed anew.
  bool pasteTokens(std::vector<Token> &tokens, SrcLoc loc) {
    for (size_t j = 0; j < tokens.size(); ++j) {
      if (!tokens[j].isPunct("##"))
        continue;
      std::string text = (j > 0 ? spelling(tokens[j - 1]) : "") +
                         (j + 1 < tokens.size() ? spelling(tokens[j + 1]) : "");
      std::vector<Token> lexed;
      if (!lex(text, diags, lexed, loc.file))
        return false;
      lexed.pop_back(); // Eof
      if (lexed.size() > 1) {
        diags.error(loc, "pasting makes '" + text + "', which is not one token");
        return false;
      }
      size_t first = j > 0 ? j - 1 : j;
      size_t last = std::min(tokens.size(), j + 2);
      for (Token &t : lexed)
        t.loc = loc;
      tokens.erase(tokens.begin() + first, tokens.begin() + last);
      tokens.insert(tokens.begin() + first, lexed.begin(), lexed.end());
      j = first;
    }
    return true;
  }

  /// __LINE__ and __FILE__ (where they are used; in a macro, where the
  /// macro is used), as oslc has them; other tokens as they are.
  Token predefined(const Token &tok) const {
    if (!tok.is(TokKind::Ident) || (tok.text != "__LINE__" && tok.text != "__FILE__"))
      return tok;
    Token t = tok;
    if (tok.text == "__LINE__") {
      t.kind = TokKind::Int;
      t.text = std::to_string((long long)tok.loc.line + lineRemap.lineMacroBias);
    } else {
      t.kind = TokKind::String;
      t.text = diags.fileName(tok.loc.file).str();
    }
    return t;
  }

  /// Macro-expands `in` into `out`. `hidden` holds macros being expanded.
  bool expand(const std::vector<Token> &in, std::vector<Token> &out,
              const llvm::StringSet<> &hidden, unsigned depth) {
    if (depth > kMaxExpansionDepth) {
      diags.error(in.empty() ? SrcLoc() : in.front().loc,
                  "macro expansion nested too deeply");
      return false;
    }
    for (size_t i = 0; i < in.size(); ++i) {
      const Token &tok = in[i];
      if (++produced > kMaxOutputTokens) {
        diags.error(tok.loc, "macro expansion is too large");
        return false;
      }
      auto it = tok.is(TokKind::Ident) && !hidden.contains(tok.text)
                    ? macros.find(tok.text)
                    : macros.end();
      if (it == macros.end()) {
        out.push_back(predefined(tok));
        continue;
      }
      const Macro &m = it->second;
      llvm::StringSet<> inner = hidden;
      inner.insert(tok.text);
      std::vector<Token> result;
      if (!m.functionLike) {
        result = m.body;
      } else {
        if (i + 1 >= in.size() || !in[i + 1].isPunct("(")) {
          out.push_back(tok); // a function-like macro name alone
          continue;
        }
        // Collect the arguments.
        std::vector<std::vector<Token>> args(1);
        size_t k = i + 2;
        int parens = 0;
        for (; k < in.size(); ++k) {
          const Token &a = in[k];
          if (a.isPunct("(")) {
            ++parens;
          } else if (a.isPunct(")")) {
            if (parens == 0)
              break;
            --parens;
          } else if (a.isPunct(",") && parens == 0) {
            args.emplace_back();
            continue;
          }
          args.back().push_back(a);
        }
        if (k >= in.size()) {
          diags.error(tok.loc, "unterminated call of macro '" + tok.text + "'");
          return false;
        }
        if (m.params.empty() && args.size() == 1 && args[0].empty())
          args.clear();
        if (m.variadic) {
          // The arguments past the named ones are __VA_ARGS__, commas kept.
          size_t named = m.params.size() - 1;
          if (args.size() == named)
            args.emplace_back();
          while (args.size() > named + 1) {
            Token comma;
            comma.kind = TokKind::Punct;
            comma.text = ",";
            comma.loc = tok.loc;
            args[named].push_back(comma);
            args[named].insert(args[named].end(), args[named + 1].begin(),
                               args[named + 1].end());
            args.erase(args.begin() + named + 1);
          }
        }
        if (args.size() != m.params.size()) {
          diags.error(tok.loc, "macro '" + tok.text + "' takes " +
                                   llvm::Twine(m.params.size()) + " argument(s), got " +
                                   llvm::Twine(args.size()));
          return false;
        }
        std::vector<std::vector<Token>> expandedArgs(args.size());
        for (size_t a = 0; a < args.size(); ++a)
          if (!expand(args[a], expandedArgs[a], hidden, depth + 1))
            return false;
        auto paramIndex = [&](const Token &b) -> int {
          auto p = b.is(TokKind::Ident)
                       ? std::find(m.params.begin(), m.params.end(), b.text)
                       : m.params.end();
          return p == m.params.end() ? -1 : int(p - m.params.begin());
        };
        const std::vector<Token> &body = m.body;
        for (size_t j = 0; j < body.size(); ++j) {
          const Token &b = body[j];
          if (b.isPunct("#") && j + 1 < body.size() && paramIndex(body[j + 1]) >= 0) {
            result.push_back(stringize(args[paramIndex(body[++j])], tok.loc));
            continue;
          }
          int p = paramIndex(b);
          if (p < 0) {
            result.push_back(b);
            continue;
          }
          // Operands of ## are pasted as written, others expanded first.
          bool pasted = (j > 0 && body[j - 1].isPunct("##")) ||
                        (j + 1 < body.size() && body[j + 1].isPunct("##"));
          const std::vector<Token> &arg = pasted ? args[p] : expandedArgs[p];
          produced += arg.size();
          if (produced > kMaxOutputTokens) {
            diags.error(tok.loc, "macro expansion is too large");
            return false;
          }
          size_t first = result.size();
          result.insert(result.end(), arg.begin(), arg.end());
          // The argument is spaced where the parameter stood (as in C's
          // preprocessors), so stringizing the result reads as written.
          if (first < result.size())
            result[first].spaceBefore = b.spaceBefore;
        }
        i = k; // the closing ')'
      }
      if (!pasteTokens(result, tok.loc))
        return false;
      // Expanded tokens report the position of the macro use.
      for (Token &r : result) {
        r.loc = tok.loc;
        r.startOfLine = false;
      }
      if (!result.empty())
        result.front().spaceBefore = tok.spaceBefore;
      if (!expand(result, out, inner, depth + 1))
        return false;
    }
    return true;
  }

  // --- #if expressions -----------------------------------------------------

  bool evalCondition(const Token &directiveTok, std::vector<Token> &line,
                     bool &value) {
    // Replace defined(X) / defined X before expanding macros.
    std::vector<Token> pre;
    for (size_t k = 1; k < line.size(); ++k) {
      if (line[k].isIdent("defined")) {
        size_t n = k + 1;
        bool paren = n < line.size() && line[n].isPunct("(");
        if (paren)
          ++n;
        if (n >= line.size() || !line[n].is(TokKind::Ident) ||
            (paren && (n + 1 >= line.size() || !line[n + 1].isPunct(")")))) {
          diags.error(line[k].loc, "malformed 'defined' in #" + directiveTok.text);
          return false;
        }
        Token t = line[k];
        t.kind = TokKind::Int;
        t.text = macros.count(line[n].text) ? "1" : "0";
        pre.push_back(t);
        k = paren ? n + 1 : n;
        continue;
      }
      pre.push_back(line[k]);
    }
    if (pre.empty()) {
      diags.error(directiveTok.loc, "#" + directiveTok.text + " needs an expression");
      return false;
    }
    std::vector<Token> toks;
    if (!expand(pre, toks, {}, 0))
      return false;
    Token end;
    end.kind = TokKind::Eof;
    end.loc = toks.back().loc;
    toks.push_back(end);
    cur = &toks;
    pos = 0;
    evalDepth = 0;
    double v;
    if (!evalExpr(v, 0))
      return false;
    if (!toks[pos].is(TokKind::Eof)) {
      diags.error(toks[pos].loc, "unexpected " + describeToken(toks[pos]) + " in #" +
                                     directiveTok.text);
      return false;
    }
    value = v != 0;
    return true;
  }

  static int precedence(const Token &t) {
    if (t.kind != TokKind::Punct)
      return -1;
    static const std::pair<const char *, int> table[] = {
        {"||", 1}, {"&&", 2}, {"|", 3},  {"^", 4},  {"&", 5},  {"==", 6},
        {"!=", 6}, {"<", 7},  {"<=", 7}, {">", 7},  {">=", 7}, {"<<", 8},
        {">>", 8}, {"+", 9},  {"-", 9},  {"*", 10}, {"/", 10}, {"%", 10}};
    for (auto &[op, prec] : table)
      if (t.text == op)
        return prec;
    return -1;
  }

  /// The integer an #if operand stands for; values past long long's range
  /// saturate (a plain cast of them is undefined behaviour, which the
  /// fuzzer found with `#if 27777777777777777777777777777777 == 1`).
  static long long toInteger(double x) {
    if (std::isnan(x))
      return 0;
    if (x >= 9223372036854775807.0)
      return LLONG_MAX;
    if (x <= -9223372036854775808.0)
      return LLONG_MIN;
    return (long long)x;
  }

  bool evalExpr(double &v, int minPrec) {
    if (!evalUnary(v))
      return false;
    while (true) {
      const Token &op = (*cur)[pos];
      int prec = precedence(op);
      if (prec < 0 || prec < minPrec)
        return true;
      ++pos;
      double r;
      if (!evalExpr(r, prec + 1))
        return false;
      long long a = toInteger(v), b = toInteger(r);
      const std::string &o = op.text;
      if (o == "||") v = (v != 0) || (r != 0);
      else if (o == "&&") v = (v != 0) && (r != 0);
      else if (o == "|") v = double(a | b);
      else if (o == "^") v = double(a ^ b);
      else if (o == "&") v = double(a & b);
      else if (o == "==") v = v == r;
      else if (o == "!=") v = v != r;
      else if (o == "<") v = v < r;
      else if (o == "<=") v = v <= r;
      else if (o == ">") v = v > r;
      else if (o == ">=") v = v >= r;
      else if (o == "<<") v = double((long long)((unsigned long long)a << (b & 63)));
      else if (o == ">>") v = double(a >> (b & 63));
      else if (o == "+") v = v + r;
      else if (o == "-") v = v - r;
      else if (o == "*") v = v * r;
      else if (o == "/") v = r == 0 ? 0 : v / r;
      else if (o == "%") v = b == 0 || b == -1 ? 0 : double(a % b);
    }
  }

  bool evalUnary(double &v) {
    if (evalDepth >= 200) {
      diags.error((*cur)[pos].loc, "#if expression nested too deeply");
      return false;
    }
    ++evalDepth;
    bool ok = evalPrimary(v);
    --evalDepth;
    return ok;
  }

  bool evalPrimary(double &v) {
    const Token &t = (*cur)[pos];
    if (t.isPunct("!") || t.isPunct("-") || t.isPunct("+") || t.isPunct("~")) {
      ++pos;
      if (!evalUnary(v))
        return false;
      if (t.text == "!") v = v == 0;
      else if (t.text == "-") v = -v;
      else if (t.text == "~") v = double(~toInteger(v));
      return true;
    }
    if (t.isPunct("(")) {
      ++pos;
      if (!evalExpr(v, 0))
        return false;
      if (!(*cur)[pos].isPunct(")")) {
        diags.error((*cur)[pos].loc, "expected ')' in #if expression, found " +
                                         describeToken((*cur)[pos]));
        return false;
      }
      ++pos;
      return true;
    }
    if (t.is(TokKind::Int) || t.is(TokKind::Float)) {
      llvm::StringRef s(t.text);
      long long iv;
      if (t.is(TokKind::Int) && !s.getAsInteger(0, iv))
        v = double(iv);
      else
        v = std::strtod(t.text.c_str(), nullptr);
      ++pos;
      return true;
    }
    if (t.is(TokKind::Ident)) {
      v = 0; // undefined identifiers are 0, as in C
      ++pos;
      return true;
    }
    diags.error(t.loc, "unexpected " + describeToken(t) + " in #if expression");
    return false;
  }

  /// #include "file" looks next to the including file first, then in the
  /// -I directories; <file> only in the -I directories; both then in the
  /// standard header directory. stdosl.h is built in when no file of that
  /// name is found.
  bool include(SrcLoc loc, const std::string &file, bool quoted, std::vector<Token> &out) {
    llvm::SmallVector<std::string> candidates;
    if (llvm::sys::path::is_absolute(file)) {
      candidates.push_back(file);
    } else {
      if (quoted) {
        llvm::SmallString<256> here(llvm::sys::path::parent_path(diags.fileName(loc.file)));
        llvm::sys::path::append(here, file);
        candidates.push_back(std::string(here));
      }
      for (const std::string &dir : includePaths) {
        llvm::SmallString<256> p(dir);
        llvm::sys::path::append(p, file);
        candidates.push_back(std::string(p));
      }
      // Last, osl-mlir's own versions of OSL's standard headers
      // (oslutil.h, color2.h, vector2.h, ...).
      llvm::SmallString<256> standard(OSL_MLIR_STDINCLUDE_DIR);
      llvm::sys::path::append(standard, file);
      candidates.push_back(std::string(standard));
    }
    std::string found;
    for (const std::string &c : candidates)
      if (llvm::sys::fs::is_regular_file(c)) {
        found = c;
        break;
      }
    if (found.empty()) {
      if (file == "stdosl.h")
        return true; // its contents are built in
      diags.error(loc, "cannot find #include file '" + file + "'" +
                           (includePaths.empty() ? " (no -I directories given)" : ""));
      return false;
    }
    if (includeDepth + 1 > kMaxIncludeDepth) {
      diags.error(loc, "#include nested too deeply (an include cycle?)");
      return false;
    }
    uint64_t size = 0;
    if (llvm::sys::fs::file_size(found, size) || size > kMaxIncludeBytes) {
      diags.error(loc, "#include file '" + found + "' is too large or unreadable");
      return false;
    }
    auto buffer = llvm::MemoryBuffer::getFile(found, /*IsText=*/true);
    if (!buffer) {
      diags.error(loc, "cannot read #include file '" + found + "': " +
                           buffer.getError().message());
      return false;
    }
    unsigned fileId = diags.addFile(found);
    std::vector<Token> raw;
    if (!lex((*buffer)->getBuffer(), diags, raw, fileId))
      return false;
    return run(raw, out, includeDepth + 1);
  }

  /// `#line N ["file"]`: the next line is line N (of that file).
  bool lineDirective(const Token &name, const std::vector<Token> &line) {
    if (line.size() < 2 || !line[1].is(TokKind::Int) ||
        (line.size() > 2 && !line[2].is(TokKind::String)) || line.size() > 3) {
      diags.error(name.loc, "#line needs a line number and, optionally, a file name");
      return false;
    }
    long long number = std::strtoll(line[1].text.c_str(), nullptr, 10);
    if (number < 1 || number > 2147483647) {
      diags.error(line[1].loc, "#line number " + line[1].text + " is out of range");
      return false;
    }
    // Lines are counted in the file as written; the offset holds across
    // the remap's own file changes.
    lineRemap.offset = number - (long long)(name.loc.line + 1);
    lineRemap.lineMacroBias = 0;
    if (line.size() > 2)
      lineRemap.file = diags.addFileName(line[2].text);
    return true;
  }

  struct LineRemap {
    long long offset = 0;
    /// Added to __LINE__'s value (not to locations).
    long long lineMacroBias = 0;
    std::optional<unsigned> file;
    void apply(SrcLoc &loc) const {
      loc.line = unsigned((long long)loc.line + offset);
      if (file)
        loc.file = *file;
    }
  };

  Diagnostics &diags;
  llvm::ArrayRef<std::string> includePaths;
  unsigned includeDepth = 0;
  LineRemap lineRemap;
  llvm::StringMap<Macro> macros;
  std::vector<Cond> conds;
  size_t produced = 0; // tokens made by macro expansion, against runaway macros
  // #if evaluation state.
  std::vector<Token> *cur = nullptr;
  size_t pos = 0;
  unsigned evalDepth = 0;
};

} // namespace

bool osl::frontend::preprocess(const std::vector<Token> &raw, Diagnostics &diags,
                               std::vector<Token> &out,
                               llvm::ArrayRef<std::string> includePaths,
                               llvm::ArrayRef<std::string> defines) {
  Preprocessor pp(diags, includePaths);
  if (!pp.defineFromCommandLine(defines))
    return false;
  if (!pp.run(raw, out, 0))
    return false;
  // What the lexer could not make a token of is an error once compiled.
  for (const Token &t : out)
    if (t.is(TokKind::Invalid))
      return diags.error(t.loc, invalidTokenMessage(t)), false;
  // Adjacent string literals are one string, as in C.
  size_t kept = 0;
  for (size_t i = 0; i < out.size(); ++i) {
    if (kept > 0 && out[i].is(TokKind::String) && out[kept - 1].is(TokKind::String)) {
      out[kept - 1].text += out[i].text;
      continue;
    }
    if (kept != i)
      out[kept] = std::move(out[i]);
    ++kept;
  }
  out.resize(kept);
  return true;
}

bool osl::frontend::lexAndPreprocess(llvm::StringRef source, Diagnostics &diags,
                                     std::vector<Token> &out,
                                     llvm::ArrayRef<std::string> includePaths,
                                     llvm::ArrayRef<std::string> defines) {
  std::vector<Token> raw;
  return lex(source, diags, raw) && preprocess(raw, diags, out, includePaths, defines);
}
