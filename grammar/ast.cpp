// grammar/ast.cpp — the Expr factories.
// Each one records `depth` (1 + the deepest operand) so the parser can refuse input that
// would make the recursive passes (and the recursive destructor) overflow the stack.
#include "grammar/ast.hpp"

#include <algorithm>

namespace fortu::ast {
namespace {

ExprPtr make(Expr::Kind kind, SourceRange range) {
    auto expr = std::make_unique<Expr>();
    expr->kind = kind;
    expr->range = range;
    return expr;
}

void set_depth(Expr& expr) {
    int deepest = 0;
    for (const ExprPtr& operand : expr.operands) {
        deepest = std::max(deepest, operand->depth);
    }
    expr.depth = 1 + deepest;
}

}  // namespace

ExprPtr Expr::make_number(double value, SourceRange range) {
    ExprPtr expr = make(Kind::Number, range);
    expr->number = value;
    return expr;
}

ExprPtr Expr::make_name(std::string name, SourceRange range) {
    ExprPtr expr = make(Kind::Name, range);
    expr->name = std::move(name);
    expr->name_range = range;
    return expr;
}

ExprPtr Expr::make_unary(UnaryOp op, ExprPtr operand, SourceRange range) {
    ExprPtr expr = make(Kind::Unary, range);
    expr->unary_op = op;
    expr->operands.push_back(std::move(operand));
    set_depth(*expr);
    return expr;
}

ExprPtr Expr::make_binary(BinaryOp op, ExprPtr lhs, ExprPtr rhs, SourceRange range) {
    ExprPtr expr = make(Kind::Binary, range);
    expr->binary_op = op;
    expr->operands.push_back(std::move(lhs));
    expr->operands.push_back(std::move(rhs));
    set_depth(*expr);
    return expr;
}

ExprPtr Expr::make_call(std::string name, SourceRange name_range, std::vector<ExprPtr> args,
                        SourceRange range) {
    ExprPtr expr = make(Kind::Call, range);
    expr->name = std::move(name);
    expr->name_range = name_range;
    expr->operands = std::move(args);
    set_depth(*expr);
    return expr;
}

ExprPtr Expr::make_array(std::vector<ExprPtr> elements, SourceRange range) {
    ExprPtr expr = make(Kind::Array, range);
    expr->operands = std::move(elements);
    set_depth(*expr);
    return expr;
}

ExprPtr Expr::make_string(std::string text, SourceRange range) {
    ExprPtr expr = make(Kind::String, range);
    expr->name = std::move(text);
    return expr;
}

}  // namespace fortu::ast
