// tests/unit/interp_budget_test.cpp — no script can crash, hang or exhaust memory at compile
// time: each reproducer of the budgets (limits.def) is refused with a located diagnostic,
// and inlining memoises calls so that what is small after hash-consing compiles fast.
#include "interp_test_support.hpp"
#include "memory_source_loader.hpp"
#include "test_support.hpp"

#include <doctest/doctest.h>

#include <fmt/format.h>

#include <fstream>

using fortu::test::Compiled;
using fortu::test::compile_text;
using fortu::test::MemorySourceLoader;
using namespace fortu;

namespace {

/// The script's first diagnostic, rendered (file:line:col: error: ..., source, caret, note).
std::string first_diagnostic(const Compiled& c) {
    REQUIRE_FALSE(c.model);
    REQUIRE(!c.sink.diagnostics().empty());
    const std::string all = c.sink.render_all();
    return all;
}

std::string function_chain(int functions, const std::string& body) {
    std::string text = "ARGUMENT X, Y;\nFUNCTION F0(A)\nRETURN A;\nEND\n";
    for (int i = 1; i <= functions; ++i)
        text += fmt::format("FUNCTION F{}(A)\nRETURN {};\nEND\n", i, fmt::format(fmt::runtime(body), i - 1));
    return text + fmt::format("RETURN F{}(X) + Y;\n", functions);
}

}  // namespace

TEST_CASE("budget: 25 functions of 1,990 unary minuses each nest too deep, reported, not a stack overflow") {
    const Compiled c = compile_text(function_chain(25, std::string(1990, '-') + "F{}(A)"));
    const std::string d = first_diagnostic(c);
    CHECK(d.starts_with("test.fortu:72:1024: error: expressions nest more than 5,000 deep here, counting the "
                        "bodies of the functions called\n"));
    CHECK(d.ends_with("note: the limit 'nesting' is 5,000; raise it with --limit nesting=N\n"));
}

TEST_CASE("budget: a chain of 12,000 functions F_i(A) = F_i-1(A) + 1 is refused where it nests too deep") {
    const Compiled c = compile_text(function_chain(12000, "F{}(A) + 1"));
    CHECK(first_diagnostic(c) ==
          "test.fortu:28509:14: error: expressions nest more than 5,000 deep here, counting the bodies of the "
          "functions called\n"
          "RETURN F9501(A) + 1;\n"
          "             ^\n"
          "note: the limit 'nesting' is 5,000; raise it with --limit nesting=N\n");
}

TEST_CASE("budget: a chain of 1,000 functions compiles, and a raised nesting limit lets 3,000 through") {
    CHECK(compile_text(function_chain(1000, "F{}(A) + 1")).model);
    CompileOptions options;
    options.limits.set(LimitId::nesting, 7000);
    CHECK_FALSE(compile_text(function_chain(3000, "F{}(A) + 1")).model);
    CHECK(compile_text(function_chain(3000, "F{}(A) + 1"), options).model);
}

TEST_CASE("budget: a FOR step that does not change the index is found, not looped on forever") {
    const Compiled c = compile_text("ARGUMENT X, Y;\nVARIABLE S = 0;\nFOR I = 1E17, 1E17 + 100\n"
                                    "VARIABLE S = S + X;\nEND FOR\nRETURN S + Y;\n");
    CHECK(first_diagnostic(c) ==
          "test.fortu:3:1: error: FOR step 1 does not change I = 1e+17: the step is below the precision of "
          "numbers that large\n"
          "FOR I = 1E17, 1E17 + 100\n"
          "^\n"
          "note: use a larger step, or smaller bounds\n");
    const Compiled stepped = compile_text("ARGUMENT X, Y;\nFOR I = 0, 1E20, 1E19\nEND FOR\nFOR J = 1E17, 1E17 + 1, 0.5\n"
                                          "END FOR\nRETURN X;\n");
    CHECK(stepped.sink.render_all() ==
          "test.fortu:4:25: error: FOR step 0.5 does not change J = 1e+17: the step is below the precision of "
          "numbers that large\n"
          "FOR J = 1E17, 1E17 + 1, 0.5\n"
          "                        ^~~\n"
          "note: use a larger step, or smaller bounds\n");
}

TEST_CASE("budget: three nested FOR loops of 1,000 run out of work, located where it ran out") {
    const Compiled c = compile_text("ARGUMENT X, Y;\nCONSTANT S = 0;\nFOR I = 1, 1000\nFOR J = 1, 1000\n"
                                    "FOR K = 1, 1000\nCONSTANT S = S + 1;\nEND FOR\nEND FOR\nEND FOR\n"
                                    "RETURN X + Y + S;\n");
    const std::string d = first_diagnostic(c);
    CHECK(d.find("error: compiling the script takes more than 1,000,000 steps (FOR loops unroll and functions "
                 "inline; this is where the budget ran out)\n") != std::string::npos);
    CHECK(d.ends_with("note: the limit 'work' is 1,000,000; raise it with --limit work=N\n"));
    CHECK(c.sink.error_count() == 1);
}

TEST_CASE("budget: a 10^6-step FOR in a FUNCTION called 1,000 times runs out of work") {
    const Compiled c = compile_text("ARGUMENT X, Y;\nFUNCTION G(A)\nCONSTANT S = 0;\nFOR I = 1, 1000000\n"
                                    "CONSTANT S = S + A;\nEND FOR\nRETURN S;\nEND\nVARIABLE T = 0;\nFOR J = 1, 1000\n"
                                    "VARIABLE T = T + G(J) * X;\nEND FOR\nRETURN T + Y;\n");
    CHECK(first_diagnostic(c).ends_with("note: the limit 'work' is 1,000,000; raise it with --limit work=N\n"));
    CHECK(c.sink.error_count() == 1);
}

TEST_CASE("memoised inlining: F_k(A) = F_k-1(A) + F_k-1(A+1), 40 levels, lowers each call once") {
    std::string text = "ARGUMENT X, Y;\nFUNCTION F0(A)\nRETURN A;\nEND\n";
    for (int k = 1; k <= 40; ++k)
        text += fmt::format("FUNCTION F{}(A)\nRETURN F{}(A) + F{}(A + 1);\nEND\n", k, k - 1, k - 1);
    const Compiled c = compile_text(text + "RETURN F40(X) - Y;\n");
    REQUIRE_MESSAGE(c.model, c.sink.render_all());
    // One sum per distinct call F_k(X+1+...+1): quadratic in the levels, not 2^40.
    CHECK(c.model->graph.reachable(c.model->root).size() == 864);
    // The same call with other arguments, or after RSYSTEM changed, is lowered again.
    const Compiled twice = compile_text("ARGUMENT X, Y;\nFUNCTION G(A)\nRETURN A & Y;\nEND\n"
                                        "VARIABLE P = G(X);\nRSYSTEM MINMAX;\nRETURN P + G(X);\n");
    REQUIRE(twice.model);
    CHECK(fortu::test::value_at("ARGUMENT X, Y;\nFUNCTION G(A)\nRETURN A & Y;\nEND\nVARIABLE P = G(X);\n"
                                "RSYSTEM MINMAX;\nRETURN P - G(X);\n", 1, 2) ==
          doctest::Approx((1 + 2 - std::sqrt(1.0 + 4.0)) - 1));
}

TEST_CASE("budget: P = [P, P] forty times stops at the array limit") {
    const Compiled c = compile_text("ARGUMENT X, Y;\nCONSTANT P = [1];\nFOR I = 1, 40\nCONSTANT P = [P, P];\n"
                                    "END FOR\nRETURN X + Y + SIZE(P);\n");
    CHECK(first_diagnostic(c) ==
          "test.fortu:4:18: error: array 'P' would have more than 1,000,000 elements\n"
          "CONSTANT P = [P, P];\n"
          "                 ^\n"
          "note: the limit 'array' is 1,000,000; raise it with --limit array=N\n");
}

TEST_CASE("budget: INCLUDE nested deeper than the limit is refused, not a stack overflow") {
    MemorySourceLoader files;
    for (int i = 0; i < 100; ++i)
        files.add_script(fmt::format("m/lib{}.fortu", i), fmt::format("INCLUDE 'lib{}.fortu';\n", i + 1));
    files.add_script("m/lib100.fortu", "CONSTANT C = 1;\n");
    CompileOptions options;
    options.loader = &files;
    const Compiled c = compile_text("ARGUMENT X, Y;\nINCLUDE 'lib0.fortu';\nRETURN X + Y + C;\n", options, "m/model.fortu");
    CHECK(first_diagnostic(c) ==
          "m/lib62.fortu:1:1: error: INCLUDE nests more than 64 files deep\n"
          "INCLUDE 'lib63.fortu';\n"
          "^~~~~~~~~~~~~~~~~~~~~\n"
          "note: the limit 'include-depth' is 64; raise it with --limit include-depth=N\n");
    options.limits.set(LimitId::include_depth, 200);
    CHECK(compile_text("ARGUMENT X, Y;\nINCLUDE 'lib0.fortu';\nRETURN X + Y + C;\n", options, "m/model.fortu").model);
}

TEST_CASE("budget: a picture claiming more pixels than allowed is refused from its header") {
    test::ScratchDir dir;
    // A 379-byte BMP claiming 12 x 16,777,207 pixels (bottom-up height negative).
    std::string bmp = "BM";
    auto put = [&](std::uint32_t v, int bytes) {
        for (int i = 0; i < bytes; ++i) bmp += static_cast<char>((v >> (8 * i)) & 0xff);
    };
    put(379, 4), put(0, 4), put(54, 4), put(40, 4), put(12, 4), put(static_cast<std::uint32_t>(-16777207), 4);
    put(1, 2), put(24, 2), put(0, 4), put(0, 4), put(2835, 4), put(2835, 4), put(0, 4), put(0, 4);
    bmp.resize(379, '\0');
    dir.write("huge.bmp", bmp);
    const std::string script = dir / "model.fortu";
    const Compiled c = compile_text("ARGUMENT X, Y;\nCONSTANT T = IMAGE('huge.bmp');\nRETURN X + Y + T(1);\n", {}, script);
    CHECK(first_diagnostic(c) ==
          script + ":2:20: error: cannot read image 'huge.bmp': the picture is 12x16777207, more than 16384 pixels\n"
          "CONSTANT T = IMAGE('huge.bmp');\n"
          "                   ^~~~~~~~~~\n");
}

TEST_CASE("limits: --limit NAME=VALUE parsing") {
    Limits limits;
    CHECK(limits[LimitId::work] == 1'000'000);
    CHECK(limits.parse("nodes=42").empty());
    CHECK(limits[LimitId::nodes] == 42);
    CHECK(limits.parse("nodes") ==
          "'nodes' is not NAME=VALUE (names: work, nodes, array, loop, nesting, include-depth, image-pixels)");
    CHECK(limits.parse("speed=1") ==
          "unknown limit 'speed' (names: work, nodes, array, loop, nesting, include-depth, image-pixels)");
    CHECK(limits.parse("nodes=0") == "'0' is not a whole number from 1 for limit 'nodes'");
    CHECK(limits.parse("nodes=1e6") == "'1e6' is not a whole number from 1 for limit 'nodes'");
}
