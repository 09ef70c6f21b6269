// grammar/parse.cpp — parse_script(), the parse Driver, and the syntax-error messages.
// The message scheme (`unexpected X, expecting A, B or C` plus hints) is documented at the
// top of parser.y; it is composed here from Bison's expected-token set (exact, thanks to LAC).
#include "grammar/parse.hpp"

#include "lexer.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <initializer_list>

namespace fortu {
namespace syntax {
namespace {

using Kind = Parser::symbol_kind;

constexpr int kTokenCount = Kind::YYNTOKENS;

constexpr std::array kOperators = {
    Kind::S_PLUS, Kind::S_MINUS, Kind::S_STAR, Kind::S_SLASH,
    Kind::S_CARET, Kind::S_STARSTAR, Kind::S_AMP, Kind::S_BAR,
};
constexpr std::array kOperandStarts = {
    Kind::S_NUMBER, Kind::S_NAME, Kind::S_LPAREN, Kind::S_LBRACKET,
    Kind::S_MINUS, Kind::S_PLUS, Kind::S_BANG, Kind::S_TILDE,
};
constexpr std::array kStatementStarts = {
    Kind::S_ARGUMENT, Kind::S_CONSTANT, Kind::S_VARIABLE, Kind::S_FUNCTION,
    Kind::S_RETURN, Kind::S_RECTANGLE, Kind::S_RECTBMP, Kind::S_RSYSTEM,
    Kind::S_FOR, Kind::S_INCLUDE, Kind::S_NAME,
};

/// The set of tokens the parser could have accepted.
struct TokenSet {
    std::array<bool, kTokenCount> has{};

    bool contains(TokenKind kind) const { return kind >= 0 && kind < kTokenCount && has[kind]; }
    template <size_t N>
    bool contains_all(const std::array<TokenKind, N>& kinds) const {
        return std::all_of(kinds.begin(), kinds.end(), [&](TokenKind k) { return contains(k); });
    }
    template <size_t N>
    void remove(const std::array<TokenKind, N>& kinds) {
        for (TokenKind k : kinds) has[k] = false;
    }
    int size() const { return static_cast<int>(std::count(has.begin(), has.end(), true)); }
    bool is_only(std::initializer_list<TokenKind> kinds) const {
        TokenSet other;
        for (TokenKind k : kinds) other.has[k] = true;
        return other.has == has;
    }
};

bool is_keyword(TokenKind kind) {
    return kind >= Kind::S_ARGUMENT && kind <= Kind::S_INCLUDE;
}

bool is_operator(TokenKind kind) {
    return std::find(kOperators.begin(), kOperators.end(), kind) != kOperators.end();
}

bool ends_operand(TokenKind kind) {
    return kind == Kind::S_NAME || kind == Kind::S_NUMBER || kind == Kind::S_STRING ||
           kind == Kind::S_RPAREN || kind == Kind::S_RBRACKET;
}

// "A", "A or B", "A, B or C".
std::string join_or(const std::vector<std::string>& items) {
    std::string out;
    for (size_t i = 0; i < items.size(); ++i) {
        if (i > 0) out += i + 1 == items.size() ? " or " : ", ";
        out += items[i];
    }
    return out;
}

constexpr int kMaxListed = 6;

std::vector<std::string> describe_expected(TokenSet expected) {
    std::vector<std::string> items;
    if (expected.contains_all(kOperators)) {
        // After a name, '(' (a call) is one more way to go on: counted as an operator.
        items.push_back("operator");
        expected.remove(kOperators);
        expected.remove(std::array{Kind::S_LPAREN});
    }
    if (expected.contains_all(kOperandStarts)) {
        items.push_back("expression");
        expected.remove(kOperandStarts);
    }
    if (expected.contains_all(kStatementStarts)) {
        items.push_back("statement");
        expected.remove(kStatementStarts);
        expected.remove(std::array{Kind::S_SEMICOLON, Kind::S_EOL, Kind::S_YYEOF});
    }
    for (int k = 0; k < kTokenCount; ++k) {
        if (expected.has[k] && k != Kind::S_YYEOF) {
            items.push_back(Parser::symbol_name(static_cast<TokenKind>(k)));
        }
    }
    if (expected.contains(Kind::S_YYEOF)) items.push_back("end of file");
    return items;
}

}  // namespace

Driver::Driver(const SourceFile& source, DiagnosticSink& sink)
    : source_(source), sink_(sink), lexer_(source, *this) {}

void Driver::error(const SourceRange& range, std::string message, std::string hint) {
    if (stopped_) return;
    if (errors_ == kMaxErrors) {
        // Binary garbage would otherwise give one error per byte.
        sink_.error(SourceRange{}, "too many errors, giving up");
        stopped_ = true;
        return;
    }
    ++errors_;
    sink_.error(range, std::move(message), std::move(hint));
}

void Driver::note(const SourceRange& range, std::string message) {
    if (stopped_) return;
    sink_.note(range, std::move(message));
}

void Driver::fatal(const SourceRange& range, std::string message) {
    if (stopped_) return;
    ++errors_;
    sink_.error(range, std::move(message));
    stopped_ = true;
}

bool Driver::too_deep(const ast::ExprPtr& expr, const SourceRange& at) {
    if (expr->depth <= ast::kMaxExprDepth) return false;
    fatal(at, "expression nested too deeply (more than " + std::to_string(ast::kMaxExprDepth) +
                  " levels)");
    return true;
}

bool Driver::enter_block(bool is_function, const SourceRange& keyword) {
    if (blocks_.size() >= static_cast<size_t>(kMaxBlockDepth)) {
        fatal(keyword, "FOR and FUNCTION blocks nested too deeply (more than " +
                           std::to_string(kMaxBlockDepth) + " levels)");
        return false;
    }
    blocks_.push_back(OpenBlock{is_function, keyword, section_});
    // A function body starts afresh, as a script does; a FOR body continues the section.
    if (is_function) section_ = ast::Section::Variable;
    return true;
}

void Driver::leave_block() {
    if (blocks_.empty()) return;   // only after error recovery
    if (blocks_.back().is_function) section_ = blocks_.back().outer_section;
    blocks_.pop_back();
}

std::optional<ast::RSystemStmt> Driver::rsystem(const std::string& name,
                                                const SourceRange& name_range,
                                                ast::ExprPtr* alpha,
                                                const SourceRange& statement) {
    std::string lower = name;
    for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    ast::RSystemStmt rsystem;
    if (lower == "alpha") {
        if (alpha == nullptr) {
            error(statement, "RSYSTEM ALPHA needs a value", "write RSYSTEM ALPHA = 0.5");
            return std::nullopt;
        }
        rsystem.kind = ast::RSystemStmt::Kind::Alpha;
        rsystem.alpha = std::move(*alpha);
        return rsystem;
    }
    if (lower == "r0" || lower == "minmax" || lower == "r1") {
        if (alpha != nullptr) {
            error(statement, "RSYSTEM " + name + " takes no value");
            return std::nullopt;
        }
        rsystem.kind = lower == "r0" ? ast::RSystemStmt::Kind::R0 : ast::RSystemStmt::Kind::MinMax;
        return rsystem;
    }
    error(name_range, "unknown R-system '" + name + "'",
          "write RSYSTEM R0, RSYSTEM ALPHA = a or RSYSTEM MINMAX");
    return std::nullopt;
}

void Driver::append(std::vector<ast::Statement> statements) {
    for (ast::Statement& statement : statements) {
        script_.statements.push_back(std::move(statement));
    }
}

std::string_view Driver::text(const SourceRange& range) const {
    if (range.file == nullptr || range.begin.line != range.end.line) return {};
    const std::string_view line = range.file->line(range.begin.line);
    const size_t begin = static_cast<size_t>(std::max(range.begin.column, 1) - 1);
    if (begin >= line.size() || range.end.column <= range.begin.column) return {};
    return line.substr(begin, static_cast<size_t>(range.end.column - range.begin.column));
}

bool Driver::followed_by_equals(const SourceRange& range) const {
    const std::string_view line = source_.line(range.end.line);
    size_t i = static_cast<size_t>(range.end.column - 1);
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    return i < line.size() && line[i] == '=' && (i + 1 == line.size() || line[i + 1] != '=');
}

void Driver::syntax_error(const Parser::context& context) {
    if (stopped_) return;
    const TokenKind kind = context.token();
    const SourceRange where = context.location();
    const std::string written(text(where));

    std::string message = "unexpected ";
    switch (kind) {
    case Kind::S_YYEOF: message += "end of file"; break;
    case Kind::S_EOL: message += "end of line"; break;
    case Kind::S_NAME: message += "name '" + written + "'"; break;
    case Kind::S_NUMBER: message += "number '" + written + "'"; break;
    case Kind::S_STRING:   // shown with its quotes, unless it is unterminated
        message += "string";
        if (written.size() >= 2 && written.front() == written.back()) message += " " + written;
        break;
    default:
        message += written.empty() ? std::string(Parser::symbol_name(kind)) : "'" + written + "'";
        break;
    }

    std::array<TokenKind, kTokenCount> buffer{};
    const int count = context.expected_tokens(buffer.data(), kTokenCount);
    TokenSet expected;
    for (int i = 0; i < count; ++i) expected.has[buffer[i]] = true;
    const std::vector<std::string> items = describe_expected(expected);
    if (!items.empty() && static_cast<int>(items.size()) <= kMaxListed) {
        message += ", expecting " + join_or(items);
    }

    // Hints need the token before the offending one; the lexer's record of the last
    // token handed out is the offending one itself (Bison reports on its lookahead).
    const Lexer& lexer = lexer_;
    const bool lexer_in_step = lexer.last().kind == kind &&
                               lexer.last().range.begin.line == where.begin.line &&
                               lexer.last().range.begin.column == where.begin.column;
    const TokenInfo& previous = lexer.before_last();
    const std::optional<OpenBracket>& open = lexer.open_before_last();
    const bool same_line = lexer_in_step && previous.range.file != nullptr &&
                           previous.range.end.line == where.begin.line;
    const bool starts_line = lexer_in_step && previous.range.file != nullptr &&
                             previous.range.end.line < where.begin.line;

    std::string hint;
    if ((kind == Kind::S_RPAREN || kind == Kind::S_RBRACKET) && lexer_in_step && !open) {
        hint = kind == Kind::S_RPAREN ? "this ')' has no matching '('"
                                      : "this ']' has no matching '['";
    } else if (kind == Kind::S_DOT && !expected.contains(Kind::S_DOT)) {
        hint = "'.' ends only a RETURN statement";
    } else if (kind == Kind::S_END && expected.contains(Kind::S_RETURN) && blocks_.empty()) {
        hint = "'END' closes a FOR or FUNCTION block, and none is open";
    } else if (expected.is_only({Kind::S_EQUALS})) {
        hint = "a definition reads 'name = expression'";
    } else if (expected.is_only({Kind::S_LPAREN, Kind::S_EQUALS})) {
        hint = "write 'FUNCTION name = expression' or 'FUNCTION name(parameters) ... END'";
    } else if (starts_line && (is_operator(previous.kind) || previous.kind == Kind::S_COMMA ||
                               previous.kind == Kind::S_EQUALS)) {
        hint = "the statement continues from line " + std::to_string(previous.range.end.line) +
               ", which ends with '" + std::string(text(previous.range)) + "'";
    } else if (same_line && ends_operand(previous.kind) &&
               (expected.contains(Kind::S_SEMICOLON) || expected.contains(Kind::S_EOL))) {
        if (is_keyword(kind) || (kind == Kind::S_NAME && followed_by_equals(where))) {
            hint = "two statements on one line need a ';' between them";
        } else if (kind == Kind::S_NAME || kind == Kind::S_NUMBER || kind == Kind::S_LPAREN ||
                   kind == Kind::S_LBRACKET) {
            hint = expected.contains_all(kOperators) ? "is an operator or a ';' missing before it?"
                   : expected.contains(Kind::S_COMMA) ? "is a ',' or a ';' missing before it?"
                                                      : "is a ';' missing before it?";
        }
    }
    error(where, std::move(message), std::move(hint));
    // Recovery skips to the end of the statement; a bracket left open would otherwise
    // keep every later newline from ending it.
    lexer_.forget_brackets();

    // Point at what is left open, as clang does.
    if (lexer_in_step && open &&
        expected.contains(open->bracket == '(' ? Kind::S_RPAREN : Kind::S_RBRACKET)) {
        note(open->range, std::string("to match this '") + open->bracket + "'");
    } else if (kind == Kind::S_YYEOF && expected.contains(Kind::S_END) && !blocks_.empty()) {
        const SourceRange& keyword = blocks_.back().keyword;
        note(keyword, "to match this '" + std::string(text(keyword)) + "'");
    }
}

Parser::symbol_type yylex(Driver& drv) {
    return drv.lexer().next();
}

void Parser::error(const location_type& location, const std::string& message) {
    drv.error(location, message);
}

void Parser::report_syntax_error(const context& context) const {
    drv.syntax_error(context);
}

}  // namespace syntax

ast::Script parse_script(const SourceFile& source, DiagnosticSink& sink) {
    syntax::Driver driver(source, sink);
    syntax::Parser parser(driver);
    parser.parse();
    return driver.take_script();
}

}  // namespace fortu
