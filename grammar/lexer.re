// grammar/lexer.re — the FORTU scanner (re2c) and the newline rule on top of it.
// The rules below read as the token table of spec §1; `Lexer::next()` decides which
// newlines end a statement. Generated into the build tree with reproducible flags.
#include "lexer.hpp"

#include <cctype>
#include <charconv>
#include <cstdio>
#include <system_error>

namespace fortu::syntax {
namespace {

using Kind = Parser::symbol_kind;

bool is_binary_operator(TokenKind kind) {
    switch (kind) {
    case Kind::S_PLUS: case Kind::S_MINUS: case Kind::S_STAR: case Kind::S_SLASH:
    case Kind::S_CARET: case Kind::S_STARSTAR: case Kind::S_AMP: case Kind::S_BAR:
        return true;
    default:
        return false;
    }
}

// The length of the valid UTF-8 sequence of two or more bytes at `p`, else 0.
size_t utf8_sequence_length(const unsigned char* p, const unsigned char* limit) {
    const unsigned char lead = p[0];
    size_t length = 0;
    unsigned char low = 0x80;
    unsigned char high = 0xBF;
    if (lead >= 0xC2 && lead <= 0xDF) {
        length = 2;
    } else if (lead >= 0xE0 && lead <= 0xEF) {
        length = 3;
        if (lead == 0xE0) low = 0xA0;       // overlong
        if (lead == 0xED) high = 0x9F;      // surrogates
    } else if (lead >= 0xF0 && lead <= 0xF4) {
        length = 4;
        if (lead == 0xF0) low = 0x90;       // overlong
        if (lead == 0xF4) high = 0x8F;      // beyond U+10FFFF
    } else {
        return 0;
    }
    if (static_cast<size_t>(limit - p) < length) return 0;
    if (p[1] < low || p[1] > high) return 0;
    for (size_t i = 2; i < length; ++i) {
        if (p[i] < 0x80 || p[i] > 0xBF) return 0;
    }
    return length;
}

}  // namespace

Lexer::Lexer(const SourceFile& source, Driver& driver)
    : source_(source),
      driver_(driver),
      begin_(reinterpret_cast<const unsigned char*>(source.text().c_str())),
      limit_(begin_ + source.text().size()),
      cursor_(begin_),
      line_begin_(begin_) {}

SourcePos Lexer::pos(const unsigned char* p) const {
    return SourcePos{line_, static_cast<int>(p - line_begin_) + 1};
}

SourceRange Lexer::range(const unsigned char* from, const unsigned char* to) const {
    return SourceRange{&source_, pos(from), pos(to)};
}

SourceRange Lexer::point_after_last() const {
    if (last_.range.file == nullptr) {
        return SourceRange{&source_, SourcePos{}, SourcePos{}};
    }
    return SourceRange{&source_, last_.range.end, last_.range.end};
}

void Lexer::start_line(const unsigned char* after_newline) {
    ++line_;
    line_begin_ = after_newline;
}

void Lexer::lex_error(SourceRange range, std::string message, std::string hint) {
    // The driver gives up after kMaxErrors anyway; not keeping more bounds the memory a
    // peek over megabytes of garbage could take.
    if (lexical_errors_ > Driver::kMaxErrors) return;
    ++lexical_errors_;
    scan_diagnostics_.push_back(
        Diagnostic{Severity::Error, range, std::move(message), std::move(hint)});
}

Token Lexer::next() {
    for (;;) {
        if (driver_.stopped()) {
            return Parser::make_YYEOF(point_after_last());
        }
        Scanned scanned = peeked_ ? std::move(*peeked_) : scan();
        peeked_.reset();
        const TokenKind kind = scanned.token.kind();
        if (kind == Kind::S_EOL) {   // a raw newline
            for (const Diagnostic& d : scanned.diagnostics) {
                driver_.error(d.range, d.message, d.hint);
            }
            if (brackets_.empty() && last_ends_statement_) {
                // Peek at the first token of the next non-blank line.
                std::vector<Diagnostic> skipped;
                for (;;) {
                    peeked_.emplace(scan());
                    if (peeked_->token.kind() != Kind::S_EOL) break;
                    skipped.insert(skipped.end(), peeked_->diagnostics.begin(),
                                   peeked_->diagnostics.end());
                }
                skipped.insert(skipped.end(), peeked_->diagnostics.begin(),
                               peeked_->diagnostics.end());
                peeked_->diagnostics = std::move(skipped);
                const TokenKind next_kind = peeked_->token.kind();
                if (!is_binary_operator(next_kind) && next_kind != Kind::S_COMMA) {
                    last_ends_statement_ = false;
                    return emit(Scanned{Parser::make_EOL(point_after_last()), {}});
                }
            }
            continue;
        }
        if (kind == Kind::S_YYEOF && brackets_.empty() && last_ends_statement_) {
            // The last statement may end at the end of the file, as at a newline.
            peeked_.emplace(std::move(scanned));
            last_ends_statement_ = false;
            return emit(Scanned{Parser::make_EOL(point_after_last()), {}});
        }
        return emit(std::move(scanned));
    }
}

Token Lexer::emit(Scanned scanned) {
    for (const Diagnostic& d : scanned.diagnostics) driver_.error(d.range, d.message, d.hint);
    if (driver_.stopped()) {
        return Parser::make_YYEOF(point_after_last());
    }
    Token token = std::move(scanned.token);
    const TokenKind kind = token.kind();
    if (kind == Kind::S_YYEOF) {
        token.location = point_after_last();
    }
    open_before_last_.reset();
    if (!brackets_.empty()) open_before_last_ = brackets_.back();
    switch (kind) {
    case Kind::S_LPAREN:
    case Kind::S_LBRACKET:
        brackets_.push_back(OpenBracket{kind == Kind::S_LPAREN ? '(' : '[', token.location});
        // Refused here, before the parser stacks them all up.
        if (brackets_.size() > static_cast<size_t>(ast::kMaxExprDepth)) {
            driver_.fatal(token.location, "expression nested too deeply (more than " +
                                              std::to_string(ast::kMaxExprDepth) + " levels)");
            return Parser::make_YYEOF(token.location);
        }
        break;
    case Kind::S_RPAREN:
    case Kind::S_RBRACKET:
        if (!brackets_.empty()) brackets_.pop_back();
        break;
    default:
        break;
    }
    switch (kind) {
    case Kind::S_NAME: case Kind::S_NUMBER: case Kind::S_STRING:
    case Kind::S_RPAREN: case Kind::S_RBRACKET: case Kind::S_END:
        last_ends_statement_ = true;
        break;
    case Kind::S_FOR: case Kind::S_FUNCTION:   // `END FOR`, `END FUNCTION`
        last_ends_statement_ = last_.kind == Kind::S_END;
        break;
    default:
        last_ends_statement_ = false;
        break;
    }
    before_last_ = last_;
    last_ = TokenInfo{kind, token.location};
    return token;
}

Lexer::Scanned Lexer::scan() {
    scan_diagnostics_.clear();
    Token token = scan_token();
    return Scanned{std::move(token), std::move(scan_diagnostics_)};
}

Token Lexer::number(std::string_view text) {
    const SourceRange where = token_range();
    std::string digits(text);
    for (char& c : digits) {
        if (c == 'd' || c == 'D') c = 'e';   // Fortran's double-precision exponent
    }
    double value = 0.0;
    const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
    if (ec == std::errc::result_out_of_range) {
        // Underflow reads as 0 (as strtod would give); overflow is an error.
        const size_t e = digits.find_first_of("eE");
        const bool negative_exponent = e != std::string::npos && e + 1 < digits.size() &&
                                       digits[e + 1] == '-';
        const std::string integer_part = digits.substr(0, digits.find_first_of(".eE"));
        const bool tiny = negative_exponent ||
                          integer_part.find_first_not_of('0') == std::string::npos;
        value = 0.0;
        if (!tiny) lex_error(where, "number '" + std::string(text) + "' is out of range");
    } else if (ec != std::errc() || end != digits.data() + digits.size()) {
        lex_error(where, "bad number '" + std::string(text) + "'");   // the regex forbids it
    }
    return Parser::make_NUMBER(value, where);
}

Token Lexer::string_literal() {
    // token_ .. cursor_ spans the quotes.
    const SourceRange where = token_range();
    const std::string_view quoted = lexeme();
    std::string text(quoted.substr(1, quoted.size() - 2));
    return Parser::make_STRING(std::move(text), where);
}

Token Lexer::unterminated_string() {
    // Report it and take the rest of the line as the string, so parsing goes on.
    const SourceRange opening = token_range();
    while (cursor_ < limit_ && *cursor_ != '\n' && *cursor_ != '\r') ++cursor_;
    lex_error(opening, "unterminated string");
    return Parser::make_STRING(std::string(lexeme().substr(1)), token_range());
}

bool Lexer::skip_block_comment() {
    // cursor_ is just after "/*".
    const SourceRange opening = token_range();
    bool crossed_newline = false;
    for (const unsigned char* p = cursor_; p < limit_; ++p) {
        if (*p == '\r' && p + 1 < limit_ && p[1] == '\n') {
            continue;   // CRLF: the '\n' ends the line
        }
        if (*p == '\n' || *p == '\r') {
            start_line(p + 1);
            crossed_newline = true;
        } else if (*p == '*' && p + 1 < limit_ && p[1] == '/') {
            cursor_ = p + 2;
            return crossed_newline;
        }
    }
    cursor_ = limit_;
    lex_error(opening, "unterminated comment");
    return crossed_newline;
}

void Lexer::bad_number() {
    const std::string_view text = lexeme();
    const size_t first = text.find_first_not_of("0123456789.");
    const char c = first == std::string_view::npos ? '\0' : text[first];
    const bool product = std::isalpha(static_cast<unsigned char>(c)) && c != 'e' && c != 'E' &&
                         c != 'd' && c != 'D';
    std::string hint;
    if (product) {
        hint = "write '" + std::string(text.substr(0, first)) + "*" +
               std::string(text.substr(first)) + "' for a product";
    } else {
        hint = "numbers read 1, 1., .5, 2e-3, 1.5E+15 or 1.D0";
    }
    lex_error(token_range(), "bad number '" + std::string(text) + "'", std::move(hint));
}

void Lexer::unexpected_character() {
    // cursor_ is one byte past token_.
    std::string shown;
    const size_t length = utf8_sequence_length(token_, limit_);
    if (length > 1) {
        cursor_ = token_ + length;   // one character, one error
        shown.assign(reinterpret_cast<const char*>(token_), length);
    } else if (*token_ >= 0x21 && *token_ <= 0x7E) {
        shown = static_cast<char>(*token_);
    } else {
        char hex[8];
        std::snprintf(hex, sizeof hex, "\\x%02X", static_cast<unsigned>(*token_));
        shown = hex;
    }
    lex_error(token_range(), "unexpected character '" + shown + "'",
              // Once per run of such bytes: a Cyrillic name is one mistake.
              *token_ >= 0x80 && (token_ == begin_ || token_[-1] < 0x80)
                  ? "only comments may hold non-ASCII characters" : "");
    if (lexical_errors_ > Driver::kMaxErrors) {
        cursor_ = limit_;   // nothing more will be reported: do not scan the rest
    }
}

Token Lexer::scan_token() {
    for (;;) {
        token_ = cursor_;
        /*!re2c
        re2c:define:YYCTYPE = "unsigned char";
        re2c:define:YYCURSOR = "cursor_";
        re2c:define:YYMARKER = "marker_";
        re2c:define:YYLIMIT = "limit_";
        re2c:yyfill:enable = 0;
        re2c:eof = 0;
        re2c:indent:top = 2;

        digits     = [0-9]+;
        mantissa   = digits | digits "." [0-9]* | "." digits;
        exponent   = [eEdD] [+-]? digits;
        number     = mantissa exponent?;
        // Anything that starts like a number and runs on into letters, dots or a dangling
        // exponent: `1e`, `1.5e+`, `2.5.3`, `3x`. Longer than `number`, so it wins then.
        bad_number = (digits | "." digits) ([0-9a-zA-Z_.] | [eEdD] [+-])*;
        name       = [a-zA-Z_] [a-zA-Z0-9_]*;
        // LF (Unix), CRLF (Windows) and a lone CR (classic Mac OS) each end a line.
        newline    = "\r\n" | "\n" | "\r";

        $                   { return Parser::make_YYEOF(token_range()); }
        newline             { start_line(cursor_); return Parser::make_EOL(SourceRange{}); }
        [ \t\v\f]+         { continue; }
        "//" [^\r\n]*       { continue; }
        "/*"                { // A comment over a line break ends the line, as a newline would.
                              if (skip_block_comment()) return Parser::make_EOL(SourceRange{});
                              continue; }

        'argument' | 'arg'  { return Parser::make_ARGUMENT(token_range()); }
        'constant' | 'const'{ return Parser::make_CONSTANT(token_range()); }
        'variable' | 'var'  { return Parser::make_VARIABLE(token_range()); }
        'function'          { return Parser::make_FUNCTION(token_range()); }
        'return'            { return Parser::make_RETURN(token_range()); }
        'rectangle'         { return Parser::make_RECTANGLE(token_range()); }
        'rectbmp'           { return Parser::make_RECTBMP(token_range()); }
        'rsystem'           { return Parser::make_RSYSTEM(token_range()); }
        'for'               { return Parser::make_FOR(token_range()); }
        'end'               { return Parser::make_END(token_range()); }
        'include'           { return Parser::make_INCLUDE(token_range()); }

        number              { return number(lexeme()); }
        bad_number          { bad_number(); return Parser::make_NUMBER(0.0, token_range()); }
        name                { return Parser::make_NAME(std::string(lexeme()), token_range()); }
        ['] [^'\r\n]* [']   { return string_literal(); }
        ["] [^"\r\n]* ["]   { return string_literal(); }
        ['"]                { return unterminated_string(); }

        "+"                 { return Parser::make_PLUS(token_range()); }
        "-"                 { return Parser::make_MINUS(token_range()); }
        "*"                 { return Parser::make_STAR(token_range()); }
        "/"                 { return Parser::make_SLASH(token_range()); }
        "^"                 { return Parser::make_CARET(token_range()); }
        "**"                { return Parser::make_STARSTAR(token_range()); }
        "&"                 { return Parser::make_AMP(token_range()); }
        "|"                 { return Parser::make_BAR(token_range()); }
        "!"                 { return Parser::make_BANG(token_range()); }
        "~"                 { return Parser::make_TILDE(token_range()); }
        "("                 { return Parser::make_LPAREN(token_range()); }
        ")"                 { return Parser::make_RPAREN(token_range()); }
        "["                 { return Parser::make_LBRACKET(token_range()); }
        "]"                 { return Parser::make_RBRACKET(token_range()); }
        ","                 { return Parser::make_COMMA(token_range()); }
        ";"                 { return Parser::make_SEMICOLON(token_range()); }
        "="                 { return Parser::make_EQUALS(token_range()); }
        "."                 { return Parser::make_DOT(token_range()); }

        *                   { unexpected_character(); continue; }
        */
    }
}

}  // namespace fortu::syntax
