//===- Lexer.cpp - OSL tokens -----------------------------------------------===//
#include "Lexer.h"

#include "llvm/ADT/StringExtras.h"

using namespace osl::frontend;

namespace {

class Lexer {
public:
  Lexer(llvm::StringRef src, Diagnostics &diags, unsigned file)
      : src(src), diags(diags), file(file) {}

  bool run(std::vector<Token> &out) {
    bool startOfLine = true;
    bool space = false;
    while (true) {
      // Whitespace, comments and line continuations.
      while (pos < src.size()) {
        char c = src[pos];
        if (c == '\n') {
          advance();
          startOfLine = true;
          space = true;
        } else if (c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v') {
          advance();
          space = true;
        } else if (c == '\\' && (peek(1) == '\n' || (peek(1) == '\r' && peek(2) == '\n'))) {
          advance();
          if (src[pos] == '\r')
            advance();
          advance();
          space = true;
        } else if (c == '/' && peek(1) == '/') {
          while (pos < src.size() && src[pos] != '\n')
            advance();
          space = true;
        } else if (c == '/' && peek(1) == '*') {
          SrcLoc start = loc();
          advance();
          advance();
          while (pos < src.size() && !(src[pos] == '*' && peek(1) == '/')) {
            if (src[pos] == '\n')
              startOfLine = true;
            advance();
          }
          if (pos >= src.size()) {
            diags.error(start, "unterminated comment");
            return false;
          }
          advance();
          advance();
          space = true;
        } else {
          break;
        }
      }
      Token tok;
      tok.loc = loc();
      tok.startOfLine = startOfLine;
      tok.spaceBefore = space;
      startOfLine = false;
      space = false;
      if (pos >= src.size()) {
        tok.kind = TokKind::Eof;
        tok.startOfLine = true;
        out.push_back(tok);
        return true;
      }
      char c = src[pos];
      if (llvm::isAlpha(c) || c == '_') {
        size_t begin = pos;
        while (pos < src.size() && (llvm::isAlnum(src[pos]) || src[pos] == '_'))
          advance();
        tok.kind = TokKind::Ident;
        tok.text = src.slice(begin, pos).str();
      } else if (llvm::isDigit(c) || (c == '.' && llvm::isDigit(peek(1)))) {
        if (!lexNumber(tok))
          return false;
      } else if (c == '"') {
        if (!lexString(tok))
          return false;
      } else {
        static const char *puncts[] = {
            "...", "<<=", ">>=", "##", "++", "--", "+=", "-=", "*=", "/=", "%=",
            "&=",  "|=",  "^=", "<<", ">>", "<=", ">=", "==", "!=", "&&",
            "||",  "(",   ")",  "[",  "]",  "{",  "}",  ",",  ";",  ":",
            "?",   ".",   "+",  "-",  "*",  "/",  "%",  "=",  "<",  ">",
            "!",   "~",   "&",  "|",  "^",  "#"};
        llvm::StringRef rest = src.substr(pos);
        const char *match = nullptr;
        for (const char *p : puncts)
          if (rest.starts_with(p)) {
            match = p;
            break;
          }
        if (!match) {
          tok.kind = TokKind::Invalid;
          tok.text = std::string(1, c);
          advance();
          out.push_back(std::move(tok));
          continue;
        }
        tok.kind = TokKind::Punct;
        tok.text = match;
        for (size_t i = 0, e = tok.text.size(); i < e; ++i)
          advance();
      }
      out.push_back(std::move(tok));
    }
  }

private:
  char peek(size_t k) const { return pos + k < src.size() ? src[pos + k] : '\0'; }
  SrcLoc loc() const { return {line, col, file}; }
  void advance() {
    if (pos >= src.size())
      return;
    if (src[pos] == '\n') {
      ++line;
      col = 1;
    } else {
      ++col;
    }
    ++pos;
  }

  bool lexNumber(Token &tok) {
    size_t begin = pos;
    bool isFloat = false;
    if (src[pos] == '0' && (peek(1) == 'x' || peek(1) == 'X')) {
      advance();
      advance();
      size_t digits = pos;
      while (pos < src.size() && llvm::isHexDigit(src[pos]))
        advance();
      if (pos == digits) {
        diags.error(tok.loc, "malformed hexadecimal number");
        return false;
      }
    } else {
      while (pos < src.size() && llvm::isDigit(src[pos]))
        advance();
      if (pos < src.size() && src[pos] == '.') {
        isFloat = true;
        advance();
        while (pos < src.size() && llvm::isDigit(src[pos]))
          advance();
      }
      if (pos < src.size() && (src[pos] == 'e' || src[pos] == 'E')) {
        size_t save = pos;
        unsigned saveLine = line, saveCol = col;
        advance();
        if (pos < src.size() && (src[pos] == '+' || src[pos] == '-'))
          advance();
        if (pos < src.size() && llvm::isDigit(src[pos])) {
          isFloat = true;
          while (pos < src.size() && llvm::isDigit(src[pos]))
            advance();
        } else {
          pos = save;
          line = saveLine;
          col = saveCol;
        }
      }
    }
    tok.text = src.slice(begin, pos).str();
    // An optional 'f' suffix on floats (C style).
    if (pos < src.size() && (src[pos] == 'f' || src[pos] == 'F') &&
        !(pos + 1 < src.size() && (llvm::isAlnum(src[pos + 1]) || src[pos + 1] == '_'))) {
      isFloat = true;
      advance();
    }
    if (pos < src.size() && (llvm::isAlnum(src[pos]) || src[pos] == '_')) {
      diags.error(tok.loc, "malformed number '" + tok.text + src.substr(pos, 1) + "'");
      return false;
    }
    tok.kind = isFloat ? TokKind::Float : TokKind::Int;
    return true;
  }

  bool lexString(Token &tok) {
    advance(); // opening quote
    std::string value;
    while (true) {
      if (pos >= src.size() || src[pos] == '\n') {
        // The quote and the rest of its line (escapes resolved).
        tok.kind = TokKind::Invalid;
        tok.text = "\"" + value;
        return true;
      }
      char c = src[pos];
      if (c == '"') {
        advance();
        break;
      }
      if (c == '\\') {
        advance();
        char e = peek(0);
        if (e >= '0' && e <= '7') {
          // \ooo: up to three octal digits, as in C.
          int code = 0;
          for (int n = 0; n < 3 && pos < src.size() && src[pos] >= '0' && src[pos] <= '7'; ++n) {
            code = code * 8 + (src[pos] - '0');
            advance();
          }
          value += char(code);
          continue;
        }
        if (e == 'x' && pos + 1 < src.size() && llvm::isHexDigit(src[pos + 1])) {
          // \xhh...: hex digits, as in C.
          advance();
          int code = 0;
          while (pos < src.size() && llvm::isHexDigit(src[pos])) {
            code = code * 16 + int(llvm::hexDigitValue(src[pos]));
            advance();
          }
          value += char(code);
          continue;
        }
        switch (e) {
        case 'n': value += '\n'; break;
        case 't': value += '\t'; break;
        case 'r': value += '\r'; break;
        case '\\': value += '\\'; break;
        case '"': value += '"'; break;
        case '\'': value += '\''; break;
        case 'a': value += '\a'; break;
        case 'b': value += '\b'; break;
        case 'f': value += '\f'; break;
        case 'v': value += '\v'; break;
        case '\n': // a line continued inside the literal
          break;
        default:
          if (pos >= src.size()) {
            diags.error(tok.loc, "unterminated string literal");
            return false;
          }
          value += '\\';
          value += e;
        }
        advance();
        continue;
      }
      value += c;
      advance();
    }
    tok.kind = TokKind::String;
    tok.text = std::move(value);
    return true;
  }

  llvm::StringRef src;
  Diagnostics &diags;
  unsigned file;
  size_t pos = 0;
  unsigned line = 1, col = 1;
};

} // namespace

std::string osl::frontend::invalidTokenMessage(const Token &t) {
  if (!t.text.empty() && t.text[0] == '"')
    return "unterminated string literal";
  unsigned char c = t.text.empty() ? 0 : static_cast<unsigned char>(t.text[0]);
  if (c >= 0x80 || !llvm::isPrint(c))
    return "invalid character in source (byte 0x" + llvm::utohexstr(c) + ")";
  return "invalid character '" + t.text + "' in source";
}

bool osl::frontend::lex(llvm::StringRef source, Diagnostics &diags,
                        std::vector<Token> &out, unsigned file) {
  Lexer lexer(source, diags, file);
  return lexer.run(out);
}

std::string osl::frontend::describeToken(const Token &tok) {
  switch (tok.kind) {
  case TokKind::Eof: return "end of file";
  case TokKind::String: return "string \"" + tok.text + "\"";
  default: return "'" + tok.text + "'";
  }
}
