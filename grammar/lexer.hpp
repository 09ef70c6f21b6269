// grammar/lexer.hpp — the scanner and the parse driver, private to grammar/.
// Lexer turns bytes into Bison tokens and decides when a newline ends a statement;
// Driver is the Bison `%param`: it owns the Lexer, the error budget and the script built.
#pragma once

#include "grammar/ast.hpp"
#include "grammar/diagnostic.hpp"
#include "grammar/source.hpp"
#include "parser.hpp"   // generated from parser.y (build tree)

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace fortu::syntax {

class Driver;

using Token = Parser::symbol_type;
using TokenKind = Parser::symbol_kind_type;

/// An open `(` or `[` still waiting for its partner.
struct OpenBracket {
    char bracket = '(';
    SourceRange range;
};

/// What the parser's error reporter wants to know about a token already handed out.
struct TokenInfo {
    TokenKind kind = Parser::symbol_kind::S_YYEMPTY;
    SourceRange range;
};

/// The token stream of one script.
///
/// Why a layer over the re2c scanner: RANOK 2D scripts end statements with a newline
/// (spec §1), and whether a newline ends a statement depends on the brackets open, the
/// token before it and the first token of the next non-blank line. So `scan()` reports
/// raw newlines and `next()` either drops them or turns them into an EOL token, peeking
/// one token ahead; it also tracks brackets for the nesting limit and for error hints.
class Lexer {
public:
    Lexer(const SourceFile& source, Driver& driver);

    /// The next token for the parser (EOL tokens included, raw newlines resolved).
    Token next();

    /// Drops the open brackets (after a syntax error), so newlines end statements again.
    void forget_brackets() { brackets_.clear(); }

    /// The innermost bracket open before the last token handed out (for error hints).
    const std::optional<OpenBracket>& open_before_last() const { return open_before_last_; }
    /// The last token handed out and the one before it.
    const TokenInfo& last() const { return last_; }
    const TokenInfo& before_last() const { return before_last_; }

private:
    // A raw token with the lexical errors found while scanning it: they are reported
    // only when the token is handed out, so diagnostics stay in source order even
    // though the newline rule peeks ahead.
    struct Scanned {
        Token token;
        std::vector<Diagnostic> diagnostics;
    };

    Scanned scan();                       // lexer.re; a raw newline comes back as EOL
    Token scan_token();                   // lexer.re; the re2c automaton
    Token emit(Scanned scanned);
    bool skip_block_comment();   // true when the comment spans a line break
    void unexpected_character();
    Token number(std::string_view text);
    Token string_literal();
    Token unterminated_string();
    void bad_number();
    void lex_error(SourceRange range, std::string message, std::string hint = {});

    SourcePos pos(const unsigned char* p) const;
    SourceRange range(const unsigned char* from, const unsigned char* to) const;
    SourceRange token_range() const { return range(token_, cursor_); }
    std::string_view lexeme() const {
        return {reinterpret_cast<const char*>(token_), static_cast<size_t>(cursor_ - token_)};
    }
    SourceRange point_after_last() const;
    void start_line(const unsigned char* after_newline);

    const SourceFile& source_;
    Driver& driver_;
    const unsigned char* begin_;
    const unsigned char* limit_;          // one past the last byte; *limit_ == '\0'
    const unsigned char* cursor_;
    const unsigned char* marker_ = nullptr;
    const unsigned char* token_ = nullptr;
    const unsigned char* line_begin_;
    int line_ = 1;
    std::vector<Diagnostic> scan_diagnostics_;
    int lexical_errors_ = 0;

    std::optional<Scanned> peeked_;
    std::vector<OpenBracket> brackets_;
    std::optional<OpenBracket> open_before_last_;
    bool last_ends_statement_ = false;    // a newline after it may end the statement
    TokenInfo last_;
    TokenInfo before_last_;
};

/// An open FOR or FUNCTION block, for the section-in-force and for error hints.
struct OpenBlock {
    bool is_function = false;
    SourceRange keyword;
    ast::Section outer_section = ast::Section::Variable;
};

/// The Bison `%param`: everything a parse needs, so the parser has no global state.
class Driver {
public:
    /// More errors than this in one script and the parse stops.
    static constexpr int kMaxErrors = 20;
    /// FOR/FUNCTION blocks nested deeper than this are refused (the AST is recursive).
    static constexpr int kMaxBlockDepth = 100;

    Driver(const SourceFile& source, DiagnosticSink& sink);

    const SourceFile& source() const { return source_; }
    Lexer& lexer() { return lexer_; }

    /// Reports an error unless the parse has stopped; stops after kMaxErrors.
    void error(const SourceRange& range, std::string message, std::string hint = {});
    void note(const SourceRange& range, std::string message);
    /// Reports an error and stops the parse (the lexer then only returns end of file).
    void fatal(const SourceRange& range, std::string message);
    bool stopped() const { return stopped_; }

    /// True (after a fatal error) when `expr` is deeper than ast::kMaxExprDepth.
    bool too_deep(const ast::ExprPtr& expr, const SourceRange& at);

    ast::Section section() const { return section_; }
    void set_section(ast::Section section) { section_ = section; }
    /// Opens a FOR/FUNCTION block; false (after a fatal error) when nested too deeply.
    bool enter_block(bool is_function, const SourceRange& keyword);
    void leave_block();
    const std::vector<OpenBlock>& open_blocks() const { return blocks_; }

    /// `RSYSTEM name [= alpha]`: the statement, or nullopt after reporting a bad name.
    std::optional<ast::RSystemStmt> rsystem(const std::string& name, const SourceRange& name_range,
                                            ast::ExprPtr* alpha, const SourceRange& statement);

    void append(std::vector<ast::Statement> statements);
    ast::Script take_script() { return std::move(script_); }

    /// The source text of a single-line range ("" when it spans lines).
    std::string_view text(const SourceRange& range) const;

    /// Composes and reports a syntax error (parse.error custom), see parser.y's header.
    void syntax_error(const Parser::context& context);

private:
    bool followed_by_equals(const SourceRange& range) const;

    const SourceFile& source_;
    DiagnosticSink& sink_;
    Lexer lexer_;
    int errors_ = 0;
    bool stopped_ = false;
    ast::Section section_ = ast::Section::Variable;
    std::vector<OpenBlock> blocks_;
    ast::Script script_;
};

}  // namespace fortu::syntax
