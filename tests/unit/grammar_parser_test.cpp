// tests/unit/grammar_parser_test.cpp — the grammar of spec §2–§4: precedence (as
// S-expressions), sections, statements, extensions, syntax errors with exact text,
// recovery, nesting limits, and every real script in shared/data/ranok-scripts.
#include "grammar_test_support.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <filesystem>
#include <memory>
#include <sstream>
#include <string>
#include <variant>
#include <vector>

using namespace fortu;
using fortu::test::Parsed;
using fortu::test::parse;
using fortu::test::sexpr;

namespace {


std::string dump(const std::vector<ast::Statement>& statements, const std::string& indent = "");

std::string dump_statement(const ast::Statement& s, const std::string& indent) {
    struct Printer {
        const std::string& indent;
        std::string operator()(const ast::ArgumentStmt& a) const {
            std::string out = "argument";
            for (const auto& d : a.arguments) {
                // Appended piece by piece: GCC 12 warns falsely (-Wrestrict) on "(" + string.
                out += ' ';
                out += d.name;
                if (d.range_hi) {
                    out += '(';
                    if (d.range_lo) {
                        out += sexpr(*d.range_lo);
                        out += ' ';
                    }
                    out += sexpr(*d.range_hi);
                    out += ')';
                }
            }
            return out;
        }
        std::string operator()(const ast::Definition& d) const {
            return (d.section == ast::Section::Constant ? "const " : "var ") + d.name + " = " +
                   sexpr(*d.value);
        }
        std::string operator()(const ast::ReturnStmt& r) const { return "return " + sexpr(*r.value); }
        std::string operator()(const ast::RectangleStmt& r) const {
            return "rectangle " + sexpr(*r.xmin) + " " + sexpr(*r.ymin) + " " + sexpr(*r.xmax) +
                   " " + sexpr(*r.ymax);
        }
        std::string operator()(const ast::RectBmpStmt& r) const {
            return "rectbmp " + sexpr(*r.width) + " " + sexpr(*r.height);
        }
        std::string operator()(const ast::RSystemStmt& r) const {
            switch (r.kind) {
            case ast::RSystemStmt::Kind::R0: return "rsystem r0";
            case ast::RSystemStmt::Kind::MinMax: return "rsystem minmax";
            case ast::RSystemStmt::Kind::Alpha: return "rsystem alpha " + sexpr(*r.alpha);
            }
            return "?";
        }
        std::string operator()(const ast::FunctionDef& f) const {
            std::string out = "function " + f.name + "(";
            for (size_t i = 0; i < f.params.size(); ++i) out += (i ? " " : "") + f.params[i];
            return out + ")\n" + dump(f.body, indent + "  ") + indent + "end";
        }
        std::string operator()(const ast::ForStmt& f) const {
            std::string out = "for " + f.index + " " + sexpr(*f.from) + " " + sexpr(*f.to);
            if (f.step) out += " step " + sexpr(*f.step);
            return out + "\n" + dump(f.body, indent + "  ") + indent + "end";
        }
        std::string operator()(const ast::IncludeStmt& i) const { return "include '" + i.path + "'"; }
    };
    return indent + std::visit(Printer{indent}, s.node) + "\n";
}

std::string dump(const std::vector<ast::Statement>& statements, const std::string& indent) {
    std::string out;
    for (const ast::Statement& s : statements) out += dump_statement(s, indent);
    return out;
}

std::string dump(const ast::Script& script) { return dump(script.statements); }

// The S-expression of `W = <expr>`.
std::string tree(const std::string& expr) {
    Parsed p = parse("W = " + expr);
    REQUIRE_MESSAGE(p.errors() == "", expr);
    REQUIRE(p.script.statements.size() == 1);
    return sexpr(*std::get<ast::Definition>(p.script.statements[0].node).value);
}

std::string where(const SourceRange& r) {
    return std::to_string(r.begin.line) + ":" + std::to_string(r.begin.column) + "-" +
           std::to_string(r.end.line) + ":" + std::to_string(r.end.column);
}

}  // namespace

TEST_CASE("precedence and associativity (spec §3)") {
    CHECK(tree("-2^2") == "(neg (^ 2 2))");
    CHECK(tree("2^3^2") == "(^ 2 (^ 3 2))");
    CHECK(tree("2^-2") == "(^ 2 (neg 2))");
    CHECK(tree("2^-2*3") == "(* (^ 2 (neg 2)) 3)");
    CHECK(tree("a|b&c") == "(| a (& b c))");
    CHECK(tree("a&b|c&d") == "(| (& a b) (& c d))");
    CHECK(tree("a+b&c-d") == "(& (+ a b) (- c d))");
    CHECK(tree("!a^2") == "(rnot (^ a 2))");
    CHECK(tree("~a") == "(rnot a)");
    CHECK(tree("+a") == "(pos a)");
    CHECK(tree("- -a") == "(neg (neg a))");
    CHECK(tree("-a*b") == "(* (neg a) b)");
    CHECK(tree("a-b-c") == "(- (- a b) c)");
    CHECK(tree("a/b*c") == "(* (/ a b) c)");
    CHECK(tree("a+b*c") == "(+ a (* b c))");
    CHECK(tree("a**b**c") == "(^ a (^ b c))");
    CHECK(tree("a^b**c") == "(^ a (^ b c))");
    CHECK(tree("(a+b)*c") == "(* (+ a b) c)");
    CHECK(tree("-(x-1)^2") == "(neg (^ (- x 1) 2))");
    CHECK(tree("0 & 3") == "(& 0 3)");
    CHECK(tree("1./2.*SQRT(A*A+B*B)") == "(* (/ 1 2) (SQRT (+ (* A A) (* B B))))");
}

TEST_CASE("calls, array elements and arrays") {
    CHECK(tree("SQRT(x)") == "(SQRT x)");
    CHECK(tree("MAX(a, b, c)") == "(MAX a b c)");
    CHECK(tree("PX(I+1)") == "(PX (+ I 1))");
    CHECK(tree("[0., 1., 1.5]") == "[0 1 1.5]");
    CHECK(tree("[-1, [2]]") == "[(neg 1) [2]]");
    CHECK(tree("F(G(x), -y)^2") == "(^ (F (G x) (neg y)) 2)");
    CHECK(tree("IMAGE('bumps.png')") == "(IMAGE 'bumps.png')");  // a file name, the one string operand
}

TEST_CASE("ranges of statements, expressions and names") {
    Parsed p = parse("CONSTANT A = 1, B = 2;\n  VARIABLE W = SQRT(x) * (a + b);\nRETURN W.");
    REQUIRE(p.errors() == "");
    REQUIRE(p.script.statements.size() == 4);
    CHECK(where(p.script.statements[0].range) == "1:1-1:15");   // from the keyword
    CHECK(where(p.script.statements[1].range) == "1:17-1:22");
    const auto& w = std::get<ast::Definition>(p.script.statements[2].node);
    CHECK(where(p.script.statements[2].range) == "2:3-2:33");
    CHECK(where(w.name_range) == "2:12-2:13");
    CHECK(where(w.value->range) == "2:16-2:33");
    const ast::Expr& call = *w.value->operands[0];
    CHECK(where(call.range) == "2:16-2:23");
    CHECK(where(call.name_range) == "2:16-2:20");
    CHECK(where(call.operands[0]->name_range) == "2:21-2:22");
    CHECK(where(w.value->operands[1]->range) == "2:26-2:33");   // the parentheses belong to it
    CHECK(where(p.script.statements[3].range) == "3:1-3:9");     // without the '.'
    CHECK(p.script.statements[0].range.file == p.file.get());
    CHECK(call.range.file == p.file.get());
}

TEST_CASE("RETURN ends with ';', '.' or the end of the file") {
    CHECK(dump(parse("RETURN w.").script) == "return w\n");
    CHECK(dump(parse("RETURN w;").script) == "return w\n");
    CHECK(dump(parse("RETURN w").script) == "return w\n");
    CHECK(dump(parse("RETURN w.\n").script) == "return w\n");
    CHECK(dump(parse("RETURN (a+b).\nRETURN 2").script) == "return (+ a b)\nreturn 2\n");
    CHECK(dump(parse("return 1.").script) == "return 1\n");   // "1." is the number
}

TEST_CASE("sections: keywords, ',' lists and continuation lines (spec §2)") {
    Parsed p = parse(
        "W0 = 1\n"
        "ARGUMENT X, Y\n"
        "W1 = X\n"
        "CONSTANT A = 1, B = 2;\n"
        "C = 3, D = 4;\n"
        "FUNCTION F = X + A\n"
        "E = 5\n"
        "VARIABLE V = X, U = Y\n"
        "T = V\n"
        "CONSTANT K = 1\n"
        "RETURN T");
    CHECK(p.errors() == "");
    CHECK(dump(p.script) ==
          "var W0 = 1\n"
          "argument X Y\n"
          "var W1 = X\n"
          "const A = 1\n"
          "const B = 2\n"
          "const C = 3\n"
          "const D = 4\n"
          "var F = (+ X A)\n"
          "const E = 5\n"      // FUNCTION name = expr does not change the section
          "var V = X\n"
          "var U = Y\n"
          "var T = V\n"
          "const K = 1\n"
          "return T\n");
}

TEST_CASE("ARGUMENT ranges") {
    Parsed p = parse("ARGUMENT X(5), Y(0, 10), Z(-2, 2);\narg u(1.1), v, w(2*3)");
    CHECK(p.errors() == "");
    CHECK(dump(p.script) == "argument X(5) Y(0 10) Z((neg 2) 2)\nargument u(1.1) v w((* 2 3))\n");
    const auto& a = std::get<ast::ArgumentStmt>(p.script.statements[0].node);
    CHECK(a.arguments[0].range_lo == nullptr);
    CHECK(where(a.arguments[1].range) == "1:16-1:24");
}

TEST_CASE("RANOK-2D headers and RSYSTEM") {
    Parsed p = parse(
        "RECTANGLE(-1, -1, 1, 1) RECTBMP(3, 3)\n"
        "RECTBMP(800, 600);\n"
        "RSYSTEM R0; rsystem Alpha = 0.5; RSYSTEM MINMAX\n"
        "ARGUMENT x, y\nRETURN y + x");
    CHECK(p.errors() == "");
    CHECK(dump(p.script) ==
          "rectangle (neg 1) (neg 1) 1 1\n"
          "rectbmp 3 3\n"
          "rectbmp 800 600\n"
          "rsystem r0\n"
          "rsystem alpha 0.5\n"
          "rsystem minmax\n"
          "argument x y\n"
          "return (+ y x)\n");
    SUBCASE("R0, ALPHA and MINMAX are ordinary names elsewhere") {
        CHECK(dump(parse("alpha = 1; R0 = alpha; MINMAX = R0").script) ==
              "var alpha = 1\nvar R0 = alpha\nvar MINMAX = R0\n");
    }
    SUBCASE("bad R-systems") {
        CHECK(parse("RSYSTEM R2").errors() ==
              "t.fortu:1:9: error: unknown R-system 'R2'\nRSYSTEM R2\n        ^~\n"
              "note: write RSYSTEM R0, RSYSTEM ALPHA = a or RSYSTEM MINMAX\n");
        CHECK(parse("RSYSTEM ALPHA;").errors() ==
              "t.fortu:1:1: error: RSYSTEM ALPHA needs a value\nRSYSTEM ALPHA;\n^~~~~~~~~~~~~\n"
              "note: write RSYSTEM ALPHA = 0.5\n");
        CHECK(parse("RSYSTEM MINMAX = 1").errors() ==
              "t.fortu:1:1: error: RSYSTEM MINMAX takes no value\nRSYSTEM MINMAX = 1\n^~~~~~~~~~~~~~~~~~\n");
    }
}

TEST_CASE("FUNCTION definitions (spec §4)") {
    Parsed p = parse(
        "FUNCTION FLOZ2(X, Y, X1, Y1, X2, Y2)\n"
        "  RETURN SQRT((X-X1)^2+(Y-Y1)^2) + SQRT((X-X2)^2+(Y-Y2)^2) - SQRT((X2-X1)^2+(Y2-Y1)^2);\n"
        "END\n"
        "function Half(a)\n"
        "  const h = 0.5\n"
        "  t = a * h\n"
        "  return t\n"
        "end function\n"
        "FUNCTION ONE() RETURN 1; END;\n"
        "W = 1\n");
    CHECK(p.errors() == "");
    CHECK(dump(p.script) ==
          "function FLOZ2(X Y X1 Y1 X2 Y2)\n"
          "  return (- (+ (SQRT (+ (^ (- X X1) 2) (^ (- Y Y1) 2))) (SQRT (+ (^ (- X X2) 2) (^ (- Y Y2) 2)))) "
          "(SQRT (+ (^ (- X2 X1) 2) (^ (- Y2 Y1) 2))))\n"
          "end\n"
          "function Half(a)\n"
          "  const h = 0.5\n"
          "  const t = (* a h)\n"
          "  return t\n"
          "end\n"
          "function ONE()\n"
          "  return 1\n"
          "end\n"
          "var W = 1\n");   // the section in force inside a function does not leak out
    const auto& f = std::get<ast::FunctionDef>(p.script.statements[0].node);
    CHECK(where(p.script.statements[0].range) == "1:1-3:4");
    CHECK(where(f.name_range) == "1:10-1:15");
    CHECK(where(f.param_ranges[5]) == "1:34-1:36");
}

TEST_CASE("FOR loops (spec §4)") {
    Parsed p = parse(
        "CONSTANT PX = [0., 1., 1.5], PY = [0., 0., 1.], N = SIZE(PX);\n"
        "VARIABLE W = FLOZ2(X, Y, PX(N), PY(N), PX(1), PY(1));\n"
        "FOR I = 1, N - 1\n"
        "  W = W & FLOZ2(X, Y, PX(I), PY(I), PX(I+1), PY(I+1));\n"
        "END FOR\n"
        "for j = 10, 1, -2; for k = 1, 2\n W = W | k\n end for; end for\n"
        "RETURN W");
    CHECK(p.errors() == "");
    CHECK(dump(p.script) ==
          "const PX = [0 1 1.5]\n"
          "const PY = [0 0 1]\n"
          "const N = (SIZE PX)\n"
          "var W = (FLOZ2 X Y (PX N) (PY N) (PX 1) (PY 1))\n"
          "for I 1 (- N 1)\n"
          "  var W = (& W (FLOZ2 X Y (PX I) (PY I) (PX (+ I 1)) (PY (+ I 1))))\n"
          "end\n"
          "for j 10 1 step (neg 2)\n"
          "  for k 1 2\n"
          "    var W = (| W k)\n"
          "  end\n"
          "end\n"
          "return W\n");
    CHECK(where(p.script.statements[4].range) == "3:1-5:8");
}

TEST_CASE("INCLUDE") {
    Parsed p = parse("INCLUDE 'stdlib/floz.fortu'\nINCLUDE \"rfunc.fortu\";");
    CHECK(p.errors() == "");
    CHECK(dump(p.script) == "include 'stdlib/floz.fortu'\ninclude 'rfunc.fortu'\n");
}

TEST_CASE("syntax errors: exact messages, carets and hints") {
    SUBCASE("two statements on one line") {
        CHECK(parse("VARIABLE A = 1 VARIABLE B = 2;").errors() ==
              "t.fortu:1:16: error: unexpected 'VARIABLE', expecting operator, ',', ';' or end of line\n"
              "VARIABLE A = 1 VARIABLE B = 2;\n"
              "               ^~~~~~~~\n"
              "note: two statements on one line need a ';' between them\n");
        CHECK(parse("b = 2 c = 3").errors() ==
              "t.fortu:1:7: error: unexpected name 'c', expecting operator, ',', ';' or end of line\n"
              "b = 2 c = 3\n"
              "      ^\n"
              "note: two statements on one line need a ';' between them\n");
    }
    SUBCASE("a missing operator") {
        CHECK(parse("W = a b").errors() ==
              "t.fortu:1:7: error: unexpected name 'b', expecting operator, ',', ';' or end of line\n"
              "W = a b\n"
              "      ^\n"
              "note: is an operator or a ';' missing before it?\n");
    }
    SUBCASE("hints fit what could have come") {
        CHECK(parse("ARGUMENT X(5) Y").errors() ==
              "t.fortu:1:15: error: unexpected name 'Y', expecting ',', ';' or end of line\n"
              "ARGUMENT X(5) Y\n"
              "              ^\n"
              "note: is a ',' or a ';' missing before it?\n");
        CHECK(parse("W = 1; 2").errors() ==
              "t.fortu:1:8: error: unexpected number '2', expecting statement\nW = 1; 2\n       ^\n");
        CHECK(parse("INCLUDE 'a' 'b'").errors() ==
              "t.fortu:1:13: error: unexpected string 'b', expecting ';' or end of line\n"
              "INCLUDE 'a' 'b'\n"
              "            ^~~\n");
    }
    SUBCASE("'=' missing in a definition") {
        CHECK(parse("VARIABLE W 1 + 2;").errors() ==
              "t.fortu:1:12: error: unexpected number '1', expecting '='\n"
              "VARIABLE W 1 + 2;\n"
              "           ^\n"
              "note: a definition reads 'name = expression'\n");
        CHECK(parse("VARIABLE W\nRETURN W").errors() ==
              "t.fortu:1:11: error: unexpected end of line, expecting '='\n"
              "VARIABLE W\n"
              "          ^\n"
              "note: a definition reads 'name = expression'\n");
        CHECK(parse("FUNCTION F x").errors() ==
              "t.fortu:1:12: error: unexpected name 'x', expecting '(' or '='\n"
              "FUNCTION F x\n"
              "           ^\n"
              "note: write 'FUNCTION name = expression' or 'FUNCTION name(parameters) ... END'\n");
    }
    SUBCASE("an unclosed bracket: the note points at it") {
        CHECK(parse("VARIABLE W = (1 + 2;").errors() ==
              "t.fortu:1:20: error: unexpected ';', expecting operator or ')'\n"
              "VARIABLE W = (1 + 2;\n"
              "                   ^\n"
              "t.fortu:1:14: note: to match this '('\n"
              "VARIABLE W = (1 + 2;\n"
              "             ^\n");
        CHECK(parse("W = MAX(a, [b, c)").errors() ==
              "t.fortu:1:17: error: unexpected ')', expecting operator, ',' or ']'\n"
              "W = MAX(a, [b, c)\n"
              "                ^\n"
              "t.fortu:1:12: note: to match this '['\n"
              "W = MAX(a, [b, c)\n"
              "           ^\n");
        CHECK(parse("W = (a +\n  b\n").errors() ==
              "t.fortu:2:4: error: unexpected end of file, expecting operator or ')'\n"
              "  b\n"
              "   ^\n"
              "t.fortu:1:5: note: to match this '('\n"
              "W = (a +\n"
              "    ^\n");
    }
    SUBCASE("an extra closing bracket") {
        CHECK(parse("W = 1 + 2)").errors() ==
              "t.fortu:1:10: error: unexpected ')', expecting operator, ',', ';' or end of line\n"
              "W = 1 + 2)\n"
              "         ^\n"
              "note: this ')' has no matching '('\n");
    }
    SUBCASE("end of file in the middle of a statement") {
        CHECK(parse("W = 1 +").errors() ==
              "t.fortu:1:8: error: unexpected end of file, expecting expression\nW = 1 +\n       ^\n");
        CHECK(parse("RETURN").errors() ==
              "t.fortu:1:7: error: unexpected end of file, expecting expression\nRETURN\n      ^\n");
        CHECK(parse("FOR I = 1, 3\n W = W & I\n").errors() ==
              "t.fortu:2:11: error: unexpected end of file, expecting statement or 'END'\n"
              " W = W & I\n"
              "          ^\n"
              "t.fortu:1:1: note: to match this 'FOR'\n"
              "FOR I = 1, 3\n"
              "^~~\n");
    }
    SUBCASE("a statement continued by a trailing operator") {
        CHECK(parse("W = 1 +\nVARIABLE B = 2\n").errors() ==
              "t.fortu:2:1: error: unexpected 'VARIABLE', expecting expression\n"
              "VARIABLE B = 2\n"
              "^~~~~~~~\n"
              "note: the statement continues from line 1, which ends with '+'\n");
    }
    SUBCASE("misplaced '.', END, and a bare expression") {
        CHECK(parse("W = a.").errors() ==
              "t.fortu:1:6: error: unexpected '.', expecting operator, ',', ';' or end of line\n"
              "W = a.\n"
              "     ^\n"
              "note: '.' ends only a RETURN statement\n");
        CHECK(parse("end").errors() ==
              "t.fortu:1:1: error: unexpected 'end', expecting statement\nend\n^~~\n"
              "note: 'END' closes a FOR or FUNCTION block, and none is open\n");
        CHECK(parse("x^2 + y^2 - 1").errors() ==
              "t.fortu:1:2: error: unexpected '^', expecting '='\nx^2 + y^2 - 1\n ^\n"
              "note: a definition reads 'name = expression'\n");
        CHECK(parse("W = )").errors() ==
              "t.fortu:1:5: error: unexpected ')', expecting expression\nW = )\n    ^\n"
              "note: this ')' has no matching '('\n");
    }
    SUBCASE("END instead of END FOR") {
        Parsed p = parse("FOR I = 1, 3\n  W = I\nEND\nV = 1\n");
        CHECK(p.errors() ==
              "t.fortu:3:1: error: a FOR loop ends with 'END FOR', not 'END'\nEND\n^~~\n");
        CHECK(dump(p.script) == "for I 1 3\n  var W = I\nend\nvar V = 1\n");
    }
}

TEST_CASE("recovery: one error per bad statement, the rest still parsed") {
    SUBCASE("RANOK 2D style, no ';'") {
        Parsed p = parse("ARGUMENT x, y\na = 1 2\nb = * 3\nc = (4\nd = 5\nRETURN d\n");
        CHECK(p.sink.error_count() == 3);
        CHECK(p.errors() ==
              "t.fortu:2:7: error: unexpected number '2', expecting operator, ',', ';' or end of line\n"
              "a = 1 2\n"
              "      ^\n"
              "note: is an operator or a ';' missing before it?\n"
              "t.fortu:3:5: error: unexpected '*', expecting expression\n"
              "b = * 3\n"
              "    ^\n"
              "t.fortu:5:1: error: unexpected name 'd', expecting operator or ')'\n"
              "d = 5\n"
              "^\n"
              "t.fortu:4:5: note: to match this '('\n"
              "c = (4\n"
              "    ^\n");
        // The unclosed bracket swallows `d = 5` (the error is there), not the rest.
        CHECK(dump(p.script) == "argument x y\nreturn d\n");
    }
    SUBCASE("with ';', several on one line") {
        Parsed p = parse("CONSTANT a = ; b = 2; c = 3 3; VARIABLE d == 1; e = 5;\nRETURN e;");
        CHECK(p.sink.error_count() == 3);
        CHECK(dump(p.script) == "const b = 2\nvar e = 5\nreturn e\n");
    }
    SUBCASE("errors in a FOR body") {
        Parsed p = parse("FOR I = 1, 2\n W = ;\n V = 1\n U = )\nEND FOR\nRETURN V");
        CHECK(p.sink.error_count() == 2);
        CHECK(dump(p.script) == "for I 1 2\n  var V = 1\nend\nreturn V\n");
    }
    SUBCASE("after 20 errors the parse gives up") {
        std::string text;
        for (int i = 0; i < 30; ++i) text += "W = * 1\n";
        Parsed p = parse(text);
        CHECK(p.sink.error_count() == 21);
        CHECK(render(p.sink.diagnostics().back()) == "error: too many errors, giving up\n");
    }
}

TEST_CASE("nesting limits: a clear error, never a stack overflow") {
    const int n = 100000;
    SUBCASE("10^5 nested brackets") {
        Parsed p = parse("W = " + std::string(n, '(') + "1" + std::string(n, ')'));
        REQUIRE(p.sink.diagnostics().size() == 1);
        CHECK(p.sink.diagnostics()[0].message == "expression nested too deeply (more than 2000 levels)");
        CHECK(where(p.sink.diagnostics()[0].range) == "1:2005-1:2006");   // the 2001st '('
        CHECK(parse("W = " + std::string(n, '[') + "1").sink.error_count() == 1);
    }
    SUBCASE("10^5 unary minus") {
        Parsed p = parse("W = " + std::string(n, '-') + "1");
        REQUIRE(p.sink.diagnostics().size() == 1);
        CHECK(p.sink.diagnostics()[0].message == "expression nested too deeply (more than 2000 levels)");
    }
    SUBCASE("a sum of 10^5 terms, a power tower, nested calls") {
        std::string sum = "W = 1";
        std::string tower = "W = 2";
        std::string calls = "W = ";
        for (int i = 0; i < n; ++i) {
            sum += "+1";
            tower += "^2";
            calls += "f(";
        }
        for (const std::string& text : {sum, tower, calls + "1" + std::string(n, ')')}) {
            Parsed p = parse(text);
            REQUIRE(p.sink.diagnostics().size() == 1);
            CHECK(p.sink.diagnostics()[0].message ==
                  "expression nested too deeply (more than 2000 levels)");
        }
    }
    SUBCASE("just below the limit is fine") {
        Parsed p = parse("W = " + std::string(1999, '(') + "-1" + std::string(1999, ')'));
        CHECK(p.errors() == "");
        std::string sum = "W = 1";
        for (int i = 1; i < 2000; ++i) sum += "+1";
        CHECK(parse(sum).errors() == "");
    }
    SUBCASE("10^5 nested FOR blocks") {
        std::string text;
        for (int i = 0; i < n; ++i) text += "FOR I = 1, 2\n";
        text += "W = 1\n";
        for (int i = 0; i < n; ++i) text += "END FOR\n";
        Parsed p = parse(text);
        REQUIRE(p.sink.diagnostics().size() == 1);
        CHECK(p.sink.diagnostics()[0].message ==
              "FOR and FUNCTION blocks nested too deeply (more than 100 levels)");
    }
}

TEST_CASE("every script in shared/data/ranok-scripts parses without a diagnostic") {
    const std::filesystem::path dir = std::filesystem::path(FORTU_SHARED_DIR) / "data" / "ranok-scripts";
    std::vector<std::filesystem::path> scripts;
    for (const auto& entry : std::filesystem::directory_iterator(dir)) {
        if (entry.path().extension() == ".fortu") scripts.push_back(entry.path());
    }
    std::sort(scripts.begin(), scripts.end());
    CHECK(scripts.size() >= 56);
    for (const auto& path : scripts) {
        std::string error;
        auto file = SourceFile::load(path.string(), error);
        REQUIRE_MESSAGE(file != nullptr, error);
        DiagnosticSink sink;
        const ast::Script script = parse_script(*file, sink);
        CHECK_MESSAGE(sink.render_all() == "", path.filename().string());
        CHECK_MESSAGE(!script.statements.empty(), path.filename().string());
        const bool has_return = std::any_of(script.statements.begin(), script.statements.end(),
            [](const ast::Statement& s) { return std::holds_alternative<ast::ReturnStmt>(s.node); });
        CHECK_MESSAGE(has_return, path.filename().string());
    }
}

TEST_CASE("the LRFM listing of the spec (S2 restored by symmetry)") {
    const char* listing =
        "ARGUMENT X,Y,Z;\n"
        "CONSTANT X1=1., Y1=0., Z1=1.;\n"
        "X2=-1., Y2=1., Z2=-1.;\n"
        "X3=-1., Y3=-1., Z3=-1.;\n"
        "A=Y1*(Z2-Z3)-Y2*(Z1-Z3)+Y3*(Z1-Z2);\n"
        "B=-(X1*(Z2-Z3)-X2*(Z1-Z3)+X3*(Z1-Z2));\n"
        "C=X1*(Y2-Y3)-X2*(Y1-Y3)+X3*(Y1-Y2);\n"
        "S=1./2.*SQRT(A*A+B*B+C*C);\n"
        "VARIABLE AA=Y*(Z2-Z3)-Y2*(Z-Z3)+Y3*(Z-Z2);\n"
        "BB=-(X*(Z2-Z3)-X2*(Z-Z3)+X3*(Z-Z2));\n"
        "CC=X*(Y2-Y3)-X2*(Y-Y3)+X3*(Y-Y2);\n"
        "S1=1./2.*SQRT(AA*AA+BB*BB+CC*CC);\n"
        "AA=Y1*(Z-Z3)-Y*(Z1-Z3)+Y3*(Z1-Z);\n"
        "BB=-(X1*(Z-Z3)-X*(Z1-Z3)+X3*(Z1-Z));\n"
        "CC=X1*(Y-Y3)-X*(Y1-Y3)+X3*(Y1-Y);\n"
        "S2=1./2.*SQRT(AA*AA+BB*BB+CC*CC);\n"
        "AA=Y1*(Z2-Z)-Y2*(Z1-Z)+Y*(Z1-Z2);\n"
        "BB=-(X1*(Z2-Z)-X2*(Z1-Z)+X*(Z1-Z2));\n"
        "CC=X1*(Y2-Y)-X2*(Y1-Y)+X*(Y1-Y2);\n"
        "VARIABLE S3=1./2.*SQRT(AA*AA+BB*BB+CC*CC);\n"
        "VARIABLE SS=S1+S2+S3-S;\n"
        "RETURN SS;\n";
    Parsed p = parse(listing);
    CHECK(p.errors() == "");
    const std::string out = dump(p.script);
    CHECK(out.rfind(
              "argument X Y Z\n"
              "const X1 = 1\nconst Y1 = 0\nconst Z1 = 1\n"
              "const X2 = (neg 1)\nconst Y2 = 1\nconst Z2 = (neg 1)\n"
              "const X3 = (neg 1)\nconst Y3 = (neg 1)\nconst Z3 = (neg 1)\n"
              "const A = (+ (- (* Y1 (- Z2 Z3)) (* Y2 (- Z1 Z3))) (* Y3 (- Z1 Z2)))\n"
              "const B = (neg (+ (- (* X1 (- Z2 Z3)) (* X2 (- Z1 Z3))) (* X3 (- Z1 Z2))))\n"
              "const C = (+ (- (* X1 (- Y2 Y3)) (* X2 (- Y1 Y3))) (* X3 (- Y1 Y2)))\n"
              "const S = (* (/ 1 2) (SQRT (+ (+ (* A A) (* B B)) (* C C))))\n"
              "var AA = (+ (- (* Y (- Z2 Z3)) (* Y2 (- Z Z3))) (* Y3 (- Z Z2)))\n",
              0) == 0);
    CHECK(p.script.statements.size() == 1 + 9 + 4 + 12 + 1 + 1);
    CHECK(out.find("const", out.find("var AA")) == std::string::npos);   // VARIABLE stays in force
    const std::string tail = "var SS = (- (+ (+ S1 S2) S3) S)\nreturn SS\n";
    CHECK(out.find(tail) == out.size() - tail.size());
}

TEST_CASE("the lower-case fragment of the spec") {
    Parsed p = parse(
        "s1=((x-x13)^2+(y-y13)^2)^0.5\n"
        "s2=((x14-x)^2+(y14-y)^2)^0.5\n"
        "w13=s1+s2-((x14-x13)^2+(y14-y13)^2)^0.5\n"
        "w=w1&w2&w3&w4&w5&w6&w7&w8&w9&w10&w11&w12&w13&w14\n"
        "RETURN w.");
    CHECK(p.errors() == "");
    CHECK(dump(p.script) ==
          "var s1 = (^ (+ (^ (- x x13) 2) (^ (- y y13) 2)) 0.5)\n"
          "var s2 = (^ (+ (^ (- x14 x) 2) (^ (- y14 y) 2)) 0.5)\n"
          "var w13 = (- (+ s1 s2) (^ (+ (^ (- x14 x13) 2) (^ (- y14 y13) 2)) 0.5))\n"
          "var w = (& (& (& (& (& (& (& (& (& (& (& (& (& w1 w2) w3) w4) w5) w6) w7) w8) w9) w10) w11) "
          "w12) w13) w14)\n"
          "return w\n");
}
