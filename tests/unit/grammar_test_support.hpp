// tests/unit/grammar_test_support.hpp — parsing text in grammar tests, and printing
// expressions as S-expressions so tests can assert the tree's shape exactly.
#pragma once

#include "grammar/parse.hpp"

#include <memory>
#include <sstream>
#include <string>

namespace fortu::test {

struct Parsed {
    std::unique_ptr<SourceFile> file;   // the AST points into it
    DiagnosticSink sink;
    ast::Script script;

    std::string errors() const { return sink.render_all(); }
};

inline Parsed parse(const std::string& text) {
    Parsed parsed;
    parsed.file = std::make_unique<SourceFile>("t.fortu", text);
    parsed.script = parse_script(*parsed.file, parsed.sink);
    return parsed;
}

inline std::string sexpr(const ast::Expr& e) {
    using Kind = ast::Expr::Kind;
    std::ostringstream out;
    switch (e.kind) {
    case Kind::Number: out << e.number; break;
    case Kind::Name: out << e.name; break;
    case Kind::Unary: {
        const char* op = e.unary_op == ast::UnaryOp::Negate ? "neg"
                         : e.unary_op == ast::UnaryOp::Plus ? "pos" : "rnot";
        out << '(' << op << ' ' << sexpr(*e.operands[0]) << ')';
        break;
    }
    case Kind::Binary: {
        static const char* const ops[] = {"+", "-", "*", "/", "^", "&", "|"};
        out << '(' << ops[static_cast<int>(e.binary_op)] << ' ' << sexpr(*e.operands[0]) << ' '
            << sexpr(*e.operands[1]) << ')';
        break;
    }
    case Kind::Call:
        out << '(' << e.name;
        for (const auto& a : e.operands) out << ' ' << sexpr(*a);
        out << ')';
        break;
    case Kind::String: out << '\'' << e.name << '\''; break;
    case Kind::Array:
        out << '[';
        for (size_t i = 0; i < e.operands.size(); ++i) out << (i ? " " : "") << sexpr(*e.operands[i]);
        out << ']';
        break;
    }
    return out.str();
}

}  // namespace fortu::test
