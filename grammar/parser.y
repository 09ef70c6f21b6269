// grammar/parser.y — the FORTU grammar (Bison, C++ LALR(1)); actions only build AST nodes.
// Spec: fortu-language.md §1–§4. The Lexer (lexer.re) supplies EOL tokens where a
// newline ends a statement, so the grammar treats ';' and EOL alike.
//
// Syntax errors (parse.error custom, composed in parse.cpp, Driver::syntax_error) read
//     unexpected <token>, expecting <a>, <b> or <c>
// in lower-case words, the caret under the offending token (under the point just after
// the last token for `end of line` / `end of file`). <token> is `end of file`,
// `end of line`, `name 'X'`, `number '1.5'`, `string 'p'`, or the token as written, in
// quotes (`'var'`, `')'`). The expected list names tokens by their aliases below
// (`'='`, `end of line`, `'END'`, ...) with three groups: `operator` when every binary
// operator fits (a call's '(' after a name is then implied), `expression` when any operand
// fits, `statement` when any statement fits (its terminators are then implied);
// `end of file` comes last; a list longer than six items is left out. A `note:` hint
// follows for common mistakes (two statements on one line, a missing '=' or operator, a
// line ending with an operator, a stray ')' or '.'), and an unclosed bracket or block gets
// its own `note: to match this '('` diagnostic pointing at it. Examples:
//     m.fortu:1:16: error: unexpected 'VARIABLE', expecting operator, ',', ';' or end of line
//     m.fortu:1:12: error: unexpected number '1', expecting '='
//     m.fortu:2:4: error: unexpected end of file, expecting operator or ')'
// Recovery: `error stmt_end` at statement level, so each bad statement is reported once;
// after Driver::kMaxErrors the parse stops with `too many errors, giving up`.

%require "3.8"
%language "c++"
%skeleton "lalr1.cc"
%header

%define api.namespace {fortu::syntax}
%define api.parser.class {Parser}
%define api.value.type variant
%define api.token.constructor
%define api.location.type {fortu::SourceRange}
%define parse.assert
%define parse.error custom
%define parse.lac full
%locations
%param {Driver& drv}
%expect 0

%code requires {
#include "grammar/ast.hpp"
#include "grammar/source.hpp"

#include <string>
#include <utility>
#include <vector>

namespace fortu::syntax {
class Driver;
/// A FUNCTION's parameter: name and where it is written.
struct Param {
    std::string name;
    fortu::SourceRange range;
};
}  // namespace fortu::syntax
}

%code {
#include "lexer.hpp"

// Locations carry the file; Bison's default would leave it null.
#define YYLLOC_DEFAULT(Current, Rhs, N)                        \
    do {                                                       \
        if (N) {                                               \
            (Current).file = YYRHSLOC(Rhs, 1).file;            \
            (Current).begin = YYRHSLOC(Rhs, 1).begin;          \
            (Current).end = YYRHSLOC(Rhs, N).end;              \
        } else {                                               \
            (Current).file = YYRHSLOC(Rhs, 0).file;            \
            (Current).begin = (Current).end = YYRHSLOC(Rhs, 0).end; \
        }                                                      \
    } while (false)

namespace fortu::syntax {

Parser::symbol_type yylex(Driver& drv);

namespace {

using namespace fortu::ast;
using Statements = std::vector<Statement>;

SourceRange span(const SourceRange& first, const SourceRange& last) {
    return SourceRange{first.file, first.begin, last.end};
}

template <class Node>
Statements one(Node node, const SourceRange& range) {
    Statements statements(1);
    statements[0].range = range;
    statements[0].node = std::move(node);
    return statements;
}

// Gives a `name = expr` list its section; the first definition starts at the keyword.
Statements in_section(Section section, Statements definitions, const SourceRange* keyword) {
    for (Statement& statement : definitions) {
        std::get<Definition>(statement.node).section = section;
    }
    if (keyword != nullptr && !definitions.empty()) {
        definitions.front().range.begin = keyword->begin;
    }
    return definitions;
}

ExprPtr unary(UnaryOp op, ExprPtr& operand, const SourceRange& range) {
    return Expr::make_unary(op, std::move(operand), range);
}

ExprPtr binary(BinaryOp op, ExprPtr& lhs, ExprPtr& rhs, const SourceRange& range) {
    return Expr::make_binary(op, std::move(lhs), std::move(rhs), range);
}

}  // namespace
}  // namespace fortu::syntax

// Every node is depth-checked as it is built, so no recursive pass (nor the recursive
// destructor) ever sees a tree deeper than ast::kMaxExprDepth.
#define CHECK_DEPTH(expr, at) \
    do { if (drv.too_deep(expr, at)) YYABORT; } while (false)
}

%token <std::string> NAME "name"
%token <double> NUMBER "number"
%token <std::string> STRING "string"
%token
    PLUS      "'+'"
    MINUS     "'-'"
    STAR      "'*'"
    SLASH     "'/'"
    CARET     "'^'"
    STARSTAR  "'**'"
    AMP       "'&'"
    BAR       "'|'"
    BANG      "'!'"
    TILDE     "'~'"
    LPAREN    "'('"
    LBRACKET  "'['"
    EQUALS    "'='"
    COMMA     "','"
    RPAREN    "')'"
    RBRACKET  "']'"
    DOT       "'.'"
    SEMICOLON "';'"
    EOL       "end of line"
    ARGUMENT  "'ARGUMENT'"
    CONSTANT  "'CONSTANT'"
    VARIABLE  "'VARIABLE'"
    FUNCTION  "'FUNCTION'"
    RETURN    "'RETURN'"
    RECTANGLE "'RECTANGLE'"
    RECTBMP   "'RECTBMP'"
    RSYSTEM   "'RSYSTEM'"
    FOR       "'FOR'"
    END       "'END'"
    INCLUDE   "'INCLUDE'"
;

%nterm <std::vector<fortu::ast::Statement>> item statement block def_list for_stmt function_def
%nterm <fortu::ast::Statement> definition
%nterm <std::vector<fortu::ast::ArgumentDecl>> arg_list
%nterm <fortu::ast::ArgumentDecl> arg_decl
%nterm <fortu::ast::ExprPtr> expr for_step
%nterm <std::vector<fortu::ast::ExprPtr>> expr_list
%nterm <std::vector<fortu::syntax::Param>> params param_list

// Spec §3, lowest first. Unary minus binds looser than '^': -2^2 = -(2^2), and the right
// operand of '^' may itself be unary: 2^-2.
%left "'|'"
%left "'&'"
%left "'+'" "'-'"
%left "'*'" "'/'"
%precedence UNARY
%right "'^'" "'**'"

%start script

%%

script:
    %empty
  | script item                    { drv.append(std::move($2)); }
  ;

block:
    %empty                         {}
  | block item                     { $$ = std::move($1);
                                     for (auto& s : $2) $$.push_back(std::move(s)); }
  ;

// An item is an empty statement, a statement and its terminator, or one of the statements
// that end themselves: `RETURN w.` and the RANOK-2D headers, which scripts write as
// `RECTANGLE(-1,-1,1,1) RECTBMP(3,3)` on one line.
item:
    stmt_end                       {}
  | statement stmt_end             { $$ = std::move($1); }
  | "'RETURN'" expr "'.'"          { $$ = one(ReturnStmt{std::move($2)}, span(@1, @2)); }
  | "'RECTANGLE'" "'('" expr "','" expr "','" expr "','" expr "')'"
                                   { $$ = one(RectangleStmt{std::move($3), std::move($5),
                                                            std::move($7), std::move($9)}, @$); }
  | "'RECTBMP'" "'('" expr "','" expr "')'"
                                   { $$ = one(RectBmpStmt{std::move($3), std::move($5)}, @$); }
  | error stmt_end                 { yyerrok; }
  ;

stmt_end: "';'" | "end of line" ;

statement:
    argument_kw arg_list           { $$ = one(ArgumentStmt{std::move($2)}, @$); }
  | constant_kw def_list           { $$ = in_section(Section::Constant, std::move($2), &@1); }
  | variable_kw def_list           { $$ = in_section(Section::Variable, std::move($2), &@1); }
  | "'FUNCTION'" def_list          { $$ = in_section(Section::Variable, std::move($2), &@1); }
  | def_list                       { $$ = in_section(drv.section(), std::move($1), nullptr); }
  | "'RETURN'" expr                { $$ = one(ReturnStmt{std::move($2)}, @$); }
  | "'RSYSTEM'" "name"             { if (auto s = drv.rsystem($2, @2, nullptr, @$))
                                         $$ = one(std::move(*s), @$); }
  | "'RSYSTEM'" "name" "'='" expr  { if (auto s = drv.rsystem($2, @2, &$4, @$))
                                         $$ = one(std::move(*s), @$); }
  | "'INCLUDE'" "string"           { $$ = one(IncludeStmt{std::move($2)}, @$); }
  | for_stmt                       { $$ = std::move($1); }
  | function_def                   { $$ = std::move($1); }
  ;

// The section changes as soon as its keyword is read, so definitions after a broken
// statement still land in the right section.
argument_kw: "'ARGUMENT'"          { drv.set_section(Section::Variable); } ;
constant_kw: "'CONSTANT'"          { drv.set_section(Section::Constant); } ;
variable_kw: "'VARIABLE'"          { drv.set_section(Section::Variable); } ;

arg_list:
    arg_decl                       { $$.push_back(std::move($1)); }
  | arg_list "','" arg_decl        { $$ = std::move($1); $$.push_back(std::move($3)); }
  ;

arg_decl:
    "name"                         { $$ = ArgumentDecl{std::move($1), @$, nullptr, nullptr}; }
  | "name" "'('" expr "')'"        { $$ = ArgumentDecl{std::move($1), @$, nullptr, std::move($3)}; }
  | "name" "'('" expr "','" expr "')'"
                                   { $$ = ArgumentDecl{std::move($1), @$, std::move($3),
                                                       std::move($5)}; }
  ;

def_list:
    definition                     { $$.push_back(std::move($1)); }
  | def_list "','" definition      { $$ = std::move($1); $$.push_back(std::move($3)); }
  ;

definition:
    "name" "'='" expr              { $$.range = @$;
                                     $$.node = Definition{Section::Variable, std::move($1), @1,
                                                          std::move($3)}; }
  ;

for_stmt:
    "'FOR'" "name" "'='" expr "','" expr for_step
                                   { if (!drv.enter_block(false, @1)) YYABORT; }
    block "'END'" end_for          { drv.leave_block();
                                     $$ = one(ForStmt{std::move($2), @2, std::move($4),
                                                      std::move($6), std::move($7),
                                                      std::move($9)}, @$); }
  ;

// A bare END closes the loop too (with an error), so the rest of the script still parses.
end_for:
    "'FOR'"
  | %empty                         { drv.error(@0, "a FOR loop ends with 'END FOR', not 'END'"); }
  ;

for_step:
    %empty                         {}
  | "','" expr                     { $$ = std::move($2); }
  ;

function_def:
    "'FUNCTION'" "name" "'('" params "')'"
                                   { if (!drv.enter_block(true, @1)) YYABORT; }
    block "'END'" end_function     { drv.leave_block();
                                     FunctionDef def;
                                     def.name = std::move($2);
                                     def.name_range = @2;
                                     for (Param& p : $4) {
                                         def.params.push_back(std::move(p.name));
                                         def.param_ranges.push_back(p.range);
                                     }
                                     def.body = std::move($7);
                                     $$ = one(std::move(def), @$); }
  ;

end_function: %empty | "'FUNCTION'" ;

params:
    %empty                         {}
  | param_list                     { $$ = std::move($1); }
  ;

param_list:
    "name"                         { $$.push_back(Param{std::move($1), @1}); }
  | param_list "','" "name"        { $$ = std::move($1); $$.push_back(Param{std::move($3), @3}); }
  ;

expr:
    "number"                       { $$ = Expr::make_number($1, @$); }
  | "name"                         { $$ = Expr::make_name(std::move($1), @$); }
  | "name" "'('" expr_list "')'"   { $$ = Expr::make_call(std::move($1), @1, std::move($3), @$);
                                     CHECK_DEPTH($$, @2); }
  | "name" "'('" "string" "')'"    { std::vector<ExprPtr> file;  // IMAGE('bump.png'): a file name
                                     file.push_back(Expr::make_string(std::move($3), @3));
                                     $$ = Expr::make_call(std::move($1), @1, std::move(file), @$); }
  | "'['" expr_list "']'"          { $$ = Expr::make_array(std::move($2), @$);
                                     CHECK_DEPTH($$, @1); }
  | "'['" "']'"                    { $$ = Expr::make_array({}, @$); }
  | "'('" expr "')'"               { $$ = std::move($2); $$->range = @$; }
  | "'-'" expr %prec UNARY         { $$ = unary(UnaryOp::Negate, $2, @$); CHECK_DEPTH($$, @1); }
  | "'+'" expr %prec UNARY         { $$ = unary(UnaryOp::Plus, $2, @$); CHECK_DEPTH($$, @1); }
  | "'!'" expr %prec UNARY         { $$ = unary(UnaryOp::RNot, $2, @$); CHECK_DEPTH($$, @1); }
  | "'~'" expr %prec UNARY         { $$ = unary(UnaryOp::RNot, $2, @$); CHECK_DEPTH($$, @1); }
  | expr "'|'" expr                { $$ = binary(BinaryOp::ROr, $1, $3, @$); CHECK_DEPTH($$, @2); }
  | expr "'&'" expr                { $$ = binary(BinaryOp::RAnd, $1, $3, @$); CHECK_DEPTH($$, @2); }
  | expr "'+'" expr                { $$ = binary(BinaryOp::Add, $1, $3, @$); CHECK_DEPTH($$, @2); }
  | expr "'-'" expr                { $$ = binary(BinaryOp::Sub, $1, $3, @$); CHECK_DEPTH($$, @2); }
  | expr "'*'" expr                { $$ = binary(BinaryOp::Mul, $1, $3, @$); CHECK_DEPTH($$, @2); }
  | expr "'/'" expr                { $$ = binary(BinaryOp::Div, $1, $3, @$); CHECK_DEPTH($$, @2); }
  | expr "'^'" expr                { $$ = binary(BinaryOp::Pow, $1, $3, @$); CHECK_DEPTH($$, @2); }
  | expr "'**'" expr               { $$ = binary(BinaryOp::Pow, $1, $3, @$); CHECK_DEPTH($$, @2); }
  ;

expr_list:
    expr                           { $$.push_back(std::move($1)); }
  | expr_list "','" expr           { $$ = std::move($1); $$.push_back(std::move($3)); }
  ;

%%
