// tests/unit/grammar_lexer_test.cpp — lexical rules of spec §1 seen through parse_script():
// numbers, keywords, comments, stray bytes, and when a newline ends a statement.
#include "grammar_test_support.hpp"

#include <doctest/doctest.h>

#include <cstdint>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <variant>

using namespace fortu;
using fortu::test::Parsed;
using fortu::test::parse;
using fortu::test::sexpr;

namespace {


// One line per statement: "const X = 1", "var W = (+ a b)", "return w", ...
std::string dump(const ast::Script& script) {
    std::string out;
    for (const ast::Statement& s : script.statements) {
        if (const auto* d = std::get_if<ast::Definition>(&s.node)) {
            out += (d->section == ast::Section::Constant ? "const " : "var ") + d->name + " = " +
                   sexpr(*d->value);
        } else if (const auto* r = std::get_if<ast::ReturnStmt>(&s.node)) {
            out += "return " + sexpr(*r->value);
        } else if (const auto* a = std::get_if<ast::ArgumentStmt>(&s.node)) {
            out += "argument";
            for (const auto& decl : a->arguments) out += ' ' + decl.name;
        } else if (const auto* i = std::get_if<ast::IncludeStmt>(&s.node)) {
            out += "include '" + i->path + "'";
        } else {
            out += "other";
        }
        out += '\n';
    }
    return out;
}

double number_value(const std::string& literal) {
    Parsed p = parse("W = " + literal);
    REQUIRE_MESSAGE(p.errors() == "", literal);
    REQUIRE(p.script.statements.size() == 1);
    const auto& d = std::get<ast::Definition>(p.script.statements[0].node);
    REQUIRE(d.value->kind == ast::Expr::Kind::Number);
    return d.value->number;
}

}  // namespace

TEST_CASE("numbers: every form of spec §1") {
    CHECK(number_value("1") == 1.0);
    CHECK(number_value("1.") == 1.0);
    CHECK(number_value(".5") == 0.5);
    CHECK(number_value("1.5") == 1.5);
    CHECK(number_value("2e-3") == 2e-3);
    CHECK(number_value("1.5E+15") == 1.5e15);
    CHECK(number_value("1.D0") == 1.0);
    CHECK(number_value("1d-3") == 1e-3);
    CHECK(number_value("2.5d+2") == 250.0);
    CHECK(number_value("1.e5") == 1e5);
    CHECK(number_value("0.1") == 0.1);
    CHECK(number_value("3.141593") == 3.141593);
    CHECK(number_value("00012") == 12.0);
    CHECK(number_value("1e-999") == 0.0);   // underflow reads as zero
}

TEST_CASE("numbers: malformed ones are reported at the number") {
    CHECK(parse("W = 1e").errors() ==
          "t.fortu:1:5: error: bad number '1e'\nW = 1e\n    ^~\n"
          "note: numbers read 1, 1., .5, 2e-3, 1.5E+15 or 1.D0\n");
    CHECK(parse("W = 1.5e+;").errors() ==
          "t.fortu:1:5: error: bad number '1.5e+'\nW = 1.5e+;\n    ^~~~~\n"
          "note: numbers read 1, 1., .5, 2e-3, 1.5E+15 or 1.D0\n");
    CHECK(parse("W = 2.5.3;").errors() ==
          "t.fortu:1:5: error: bad number '2.5.3'\nW = 2.5.3;\n    ^~~~~\n"
          "note: numbers read 1, 1., .5, 2e-3, 1.5E+15 or 1.D0\n");
    CHECK(parse("W = 3x + 1").errors() ==
          "t.fortu:1:5: error: bad number '3x'\nW = 3x + 1\n    ^~\n"
          "note: write '3*x' for a product\n");
    CHECK(parse("W = 1e999").errors() ==
          "t.fortu:1:5: error: number '1e999' is out of range\nW = 1e999\n    ^~~~~\n");
    // The statement itself still parses: one error, not a cascade.
    Parsed p = parse("W = 1e + 2\nV = 3");
    CHECK(p.sink.error_count() == 1);
    CHECK(dump(p.script) == "var W = (+ 0 2)\nvar V = 3\n");
}

TEST_CASE("keywords are case-insensitive, with abbreviations; names keep their spelling") {
    Parsed p = parse(
        "Argument x, Y\n"
        "const r = 2\n"
        "CONST R = 4\n"
        "cOnStAnT q = 1\n"
        "var circle = r^2 - x^2\n"
        "Variable V2 = circle\n"
        "arg Z\n"
        "VAR argx = 1; CONSTANTS = 2; variable_ = 3; for_x = 4; End1 = 5\n"
        "rEtUrN Circle");
    CHECK(p.errors() == "");
    CHECK(dump(p.script) ==
          "argument x Y\n"
          "const r = 2\n"
          "const R = 4\n"
          "const q = 1\n"
          "var circle = (- (^ r 2) (^ x 2))\n"
          "var V2 = circle\n"
          "argument Z\n"
          "var argx = 1\n"
          "var CONSTANTS = 2\n"
          "var variable_ = 3\n"
          "var for_x = 4\n"
          "var End1 = 5\n"
          "return Circle\n");
}

TEST_CASE("comments: line, block, any bytes inside") {
    SUBCASE("line and block comments") {
        Parsed p = parse("// header\nW = 1 /* one */ + /* two */ 2; // tail\nRETURN W // end");
        CHECK(p.errors() == "");
        CHECK(dump(p.script) == "var W = (+ 1 2)\nreturn W\n");
    }
    SUBCASE("cp1251 bytes and NULs in comments are never rejected") {
        static const char text[] =
            "//\xcf\xf0\xe8\xec\xe5\xf0 \xea\xee\xec\xec\xe5\xed\xf2\xe0\xf0\xe8\xff\n"
            "W = 1; /* \xc2\xf2\xee\xf0\xe0\xff\x00\xff */ V = 2;\n";
        Parsed p = parse(std::string(text, sizeof text - 1));
        CHECK(p.errors() == "");
        CHECK(dump(p.script) == "var W = 1\nvar V = 2\n");
    }
    SUBCASE("a block comment over a line break ends the line") {
        Parsed p = parse("W = 1 /* first\n  second */ V = 2\nU = 3 /* a\n b */ + 4");
        CHECK(p.errors() == "");
        CHECK(dump(p.script) == "var W = 1\nvar V = 2\nvar U = (+ 3 4)\n");
    }
    SUBCASE("unterminated comment") {
        Parsed p = parse("W = 1;\nV = 2; /* never closed\nU = 3;\n");
        CHECK(p.errors() == "t.fortu:2:8: error: unterminated comment\nV = 2; /* never closed\n       ^~\n");
        CHECK(dump(p.script) == "var W = 1\nvar V = 2\n");
    }
    SUBCASE("'/*' inside a line comment is nothing") {
        Parsed p = parse("W = 1 // /* not a comment start\nRETURN W");
        CHECK(p.errors() == "");
    }
}

TEST_CASE("stray characters are reported, skipped, and lexing goes on") {
    CHECK(parse("W = 1 @+ 2").errors() ==
          "t.fortu:1:7: error: unexpected character '@'\nW = 1 @+ 2\n      ^\n");
    CHECK(parse("W = #1;").errors() ==
          "t.fortu:1:5: error: unexpected character '#'\nW = #1;\n    ^\n");
    CHECK(parse("W = $1;").errors() ==
          "t.fortu:1:5: error: unexpected character '$'\nW = $1;\n    ^\n");
    // Control bytes are shown as '?' in the source excerpt, so they cannot drive the terminal.
    CHECK(parse("W = \x01 1;").errors() ==
          "t.fortu:1:5: error: unexpected character '\\x01'\nW = ? 1;\n    ^\n");
    const std::string nul(1, '\0');
    CHECK(parse("W = " + nul + " 1;").errors() ==
          "t.fortu:1:5: error: unexpected character '\\x00'\nW = ? 1;\n    ^\n");
    SUBCASE("non-ASCII outside a comment") {
        CHECK(parse("W = \xcf 1;").errors() ==
              "t.fortu:1:5: error: unexpected character '\\xCF'\nW = \xcf 1;\n    ^\n"
              "note: only comments may hold non-ASCII characters\n");
        // A UTF-8 character is one error, shown as itself; the hint comes once per run.
        CHECK(parse("W = \xd1\x88\xd0\xb0 + 1").errors() ==
              "t.fortu:1:5: error: unexpected character '\xd1\x88'\nW = \xd1\x88\xd0\xb0 + 1\n    ^\n"
              "note: only comments may hold non-ASCII characters\n"
              "t.fortu:1:7: error: unexpected character '\xd0\xb0'\nW = \xd1\x88\xd0\xb0 + 1\n     ^\n");
    }
}

TEST_CASE("binary garbage never crashes or hangs, and gives up after 20 errors") {
    std::mt19937 random(12345);
    std::string garbage;
    for (int i = 0; i < 1 << 20; ++i) garbage += static_cast<char>(random() & 0xFF);
    Parsed p = parse(garbage);
    CHECK(p.sink.error_count() == 21);
    REQUIRE_FALSE(p.sink.diagnostics().empty());
    CHECK(p.sink.diagnostics().back().message == "too many errors, giving up");
    CHECK(p.sink.diagnostics().back().range.file == nullptr);

    SUBCASE("every single byte, alone and after a statement") {
        for (int b = 0; b < 256; ++b) {
            const std::string byte(1, static_cast<char>(b));
            Parsed alone = parse(byte);
            Parsed after = parse("W = (1 +" + byte + "\n2)" + byte + byte);
            CHECK(alone.sink.error_count() <= 2);
            CHECK(after.sink.error_count() <= 4);
        }
    }
}

TEST_CASE("string literals for INCLUDE") {
    Parsed p = parse("INCLUDE 'stdlib/floz.fortu'\ninclude \"my lib.fortu\";");
    CHECK(p.errors() == "");
    CHECK(dump(p.script) == "include 'stdlib/floz.fortu'\ninclude 'my lib.fortu'\n");
    CHECK(parse("INCLUDE 'oops\nW = 1").errors() ==
          "t.fortu:1:9: error: unterminated string\nINCLUDE 'oops\n        ^\n");
}

TEST_CASE("newline as a statement terminator (RANOK 2D style)") {
    SUBCASE("one statement per line, no ';'") {
        Parsed p = parse("ARGUMENT X(5), Y(5)\n\nCONSTANT R = 2\nVARIABLE W = R^2 - X^2 - Y^2\nRETURN W\n");
        CHECK(p.errors() == "");
        CHECK(dump(p.script) ==
              "argument X Y\nconst R = 2\nvar W = (- (- (^ R 2) (^ X 2)) (^ Y 2))\nreturn W\n");
    }
    SUBCASE("a line ending with an operator continues") {
        Parsed p = parse("W = 1 +\n  2 *\n\n  3\nV = W");
        CHECK(p.errors() == "");
        CHECK(dump(p.script) == "var W = (+ 1 (* 2 3))\nvar V = W\n");
    }
    SUBCASE("inside brackets a newline is whitespace") {
        Parsed p = parse("W = SQRT(1\n  , 2\n)\nV = (a\n\n+ b) * [1,\n2]\nU = 1");
        CHECK(p.errors() == "");
        CHECK(dump(p.script) == "var W = (SQRT 1 2)\nvar V = (* (+ a b) [1 2])\nvar U = 1\n");
    }
    SUBCASE("a next line starting with a binary operator or ',' continues") {
        Parsed p = parse("W = a\n+ b\nV = a\n  - b\nU = a\n* b\n/ c\n^ d\n** e\n& f\n| g\n"
                         "CONSTANT P = 1\n, Q = 2\nRETURN W");
        CHECK(p.errors() == "");
        CHECK(dump(p.script) ==
              "var W = (+ a b)\nvar V = (- a b)\nvar U = (| (& (/ (* a b) (^ c (^ d e))) f) g)\n"
              "const P = 1\nconst Q = 2\nreturn W\n");
    }
    SUBCASE("comments and blank lines between do not count") {
        Parsed p = parse("W = a // first part\n\n  // more\n  /* and */ + b\nV = 1 // done\n\n!c");
        // `!c` starts no binary operation: the line before has ended.
        CHECK(dump(p.script) == "var W = (+ a b)\nvar V = 1\n");
        CHECK(p.sink.error_count() == 1);
    }
    SUBCASE("unary-only operators on the next line do not continue") {
        Parsed p = parse("W = a\n~b");
        CHECK(p.errors() ==
              "t.fortu:2:1: error: unexpected '~', expecting statement\n~b\n^\n");
    }
    SUBCASE("CRLF line ends") {
        Parsed p = parse("ARGUMENT X\r\nW = X +\r\n  1\r\nRETURN W\r\n");
        CHECK(p.errors() == "");
        CHECK(dump(p.script) == "argument X\nvar W = (+ X 1)\nreturn W\n");
    }
    SUBCASE("CR line ends (classic Mac OS) end a statement as LF does") {
        Parsed p = parse("ARGUMENT X, Y\rRETURN X\r");
        CHECK(p.errors() == "");
        CHECK(dump(p.script) == "argument X Y\nreturn X\n");
    }
    SUBCASE("CR line ends: comments, continuation and positions") {
        Parsed p = parse("ARGUMENT X // the one\r/* two\rlines */ W = X +\r  1\rV = 1 2\rRETURN W");
        CHECK(p.errors() ==
              "t.fortu:5:7: error: unexpected number '2', expecting operator, ',', ';' or end of line\n"
              "V = 1 2\n      ^\nnote: is an operator or a ';' missing before it?\n");
    }
    SUBCASE("the last statement may end at the end of the file") {
        CHECK(dump(parse("RETURN W").script) == "return W\n");
        CHECK(dump(parse("W = f(x)").script) == "var W = (f x)\n");
    }
    SUBCASE("statements end with ';' anywhere") {
        Parsed p = parse("W = 1; V = 2;;\n; U = 3;");
        CHECK(p.errors() == "");
        CHECK(dump(p.script) == "var W = 1\nvar V = 2\nvar U = 3\n");
    }
    SUBCASE("tabs are whitespace") {
        Parsed p = parse("\tW\t=\t1\t+\n\t\t2");
        CHECK(p.errors() == "");
        CHECK(dump(p.script) == "var W = (+ 1 2)\n");
    }
}
