// grammar/ast.hpp — the syntax tree of a FORTU script, as written.
// The parser builds it; interp/ checks and lowers it. It knows nothing of interp/.
// Names keep their spelling: case-insensitive matching is a semantic rule (interp/).
#pragma once

#include "grammar/source.hpp"

#include <memory>
#include <optional>
#include <string>
#include <variant>
#include <vector>

namespace fortu::ast {

struct Expr;
using ExprPtr = std::unique_ptr<Expr>;

enum class UnaryOp { Negate, Plus, RNot };                       // -a, +a, !a / ~a
enum class BinaryOp { Add, Sub, Mul, Div, Pow, RAnd, ROr };      // + - * / ^(**) & |

/// One expression node. A tagged struct rather than a class hierarchy: the tree is small
/// and every pass switches over `kind` anyway.
struct Expr {
    enum class Kind {
        Number,   ///< `number`
        Name,     ///< `name` (an argument, constant, variable, loop index or PI)
        Unary,    ///< `unary_op` operands[0]
        Binary,   ///< operands[0] `binary_op` operands[1]
        Call,     ///< `name`(operands...): built-in, user function or array element A(I)
        Array,    ///< [operands...]  (constant arrays, spec §4)
        String,   ///< 'name': a file name, only as IMAGE('bump.png') / IMAGE_WIDTH('bump.png')
    };
    Kind kind = Kind::Number;
    SourceRange range;               ///< the whole expression
    SourceRange name_range;          ///< Name/Call: just the name
    double number = 0.0;
    std::string name;
    UnaryOp unary_op = UnaryOp::Negate;
    BinaryOp binary_op = BinaryOp::Add;
    std::vector<ExprPtr> operands;
    int depth = 1;                   ///< 1 + the deepest operand; the parser bounds it

    static ExprPtr make_number(double value, SourceRange range);
    static ExprPtr make_name(std::string name, SourceRange range);
    static ExprPtr make_unary(UnaryOp op, ExprPtr operand, SourceRange range);
    static ExprPtr make_binary(BinaryOp op, ExprPtr lhs, ExprPtr rhs, SourceRange range);
    static ExprPtr make_call(std::string name, SourceRange name_range,
                             std::vector<ExprPtr> args, SourceRange range);
    static ExprPtr make_array(std::vector<ExprPtr> elements, SourceRange range);
    static ExprPtr make_string(std::string text, SourceRange range);
};

/// Deepest expression nesting the parser accepts; deeper input gets a diagnostic, so no
/// later recursive pass can overflow the stack.
inline constexpr int kMaxExprDepth = 2000;

enum class Section { Argument, Constant, Variable };

/// `X`, `X(5)` (= [-5, 5]) or `X(0, 10)` inside ARGUMENT.
struct ArgumentDecl {
    std::string name;
    SourceRange range;
    ExprPtr range_lo;   ///< X(a, b): a;  X(a): null (the range is [-a, a])
    ExprPtr range_hi;   ///< X(a, b): b;  X(a): a;  X: null
};

struct ArgumentStmt {
    std::vector<ArgumentDecl> arguments;
};

/// `name = expr` in a CONSTANT or VARIABLE section (also `FUNCTION name = expr`,
/// which is a VARIABLE, and a bare `name = expr` continuing the section in force).
struct Definition {
    Section section = Section::Variable;
    std::string name;
    SourceRange name_range;
    ExprPtr value;
};

struct ReturnStmt {
    ExprPtr value;
};

/// RANOK-2D header: RECTANGLE(xmin, ymin, xmax, ymax).
struct RectangleStmt {
    ExprPtr xmin, ymin, xmax, ymax;
};

/// RANOK-2D header: RECTBMP(width, height).
struct RectBmpStmt {
    ExprPtr width, height;
};

/// RSYSTEM R0 | ALPHA = a | MINMAX (spec §3).
struct RSystemStmt {
    enum class Kind { R0, Alpha, MinMax };
    Kind kind = Kind::R0;
    ExprPtr alpha;   ///< Kind::Alpha only
};

struct Statement;

/// FUNCTION NAME(P1, P2, ...) <local definitions> RETURN expr; END  (spec §4)
struct FunctionDef {
    std::string name;
    SourceRange name_range;
    std::vector<std::string> params;
    std::vector<SourceRange> param_ranges;
    std::vector<Statement> body;     ///< Definitions, FOR loops and exactly one ReturnStmt
};

/// FOR I = A, B[, STEP] ... END FOR  (spec §4)
struct ForStmt {
    std::string index;
    SourceRange index_range;
    ExprPtr from, to, step;          ///< step may be null (= 1)
    std::vector<Statement> body;
};

/// INCLUDE 'path'  (spec §4)
struct IncludeStmt {
    std::string path;
};

struct Statement {
    SourceRange range;   ///< the statement's first token to its last
    std::variant<ArgumentStmt, Definition, ReturnStmt, RectangleStmt, RectBmpStmt,
                 RSystemStmt, FunctionDef, ForStmt, IncludeStmt>
        node;
};

struct Script {
    std::vector<Statement> statements;
};

}  // namespace fortu::ast
