// tests/unit/interp_include_test.cpp — INCLUDE and IMAGE through an in-memory loader: where
// compile() looks for a file and in which order, that a library is read once, and the exact
// diagnostics when a file is missing, broken or too large. No real files.
#include "interp_test_support.hpp"
#include "memory_source_loader.hpp"

#include <doctest/doctest.h>

using namespace fortu;
using fortu::test::Compiled;
using fortu::test::compile_text;
using fortu::test::MemorySourceLoader;

namespace {

double value_at_origin(const Compiled& c) { return evaluate_point(*c.model, {0, 0, 0}, engine_named("voxel")).value; }

}  // namespace

TEST_CASE("INCLUDE looks in the script's folder first, then the include folders, in order") {
    MemorySourceLoader files;
    files.add_script("models/lib.fortu", "CONSTANT K = 1;");
    files.add_script("stdlib/lib.fortu", "CONSTANT K = 2;");
    files.add_script("stdlib/only_here.fortu", "CONSTANT L = 30;");
    files.add_script("more/only_here.fortu", "CONSTANT L = 40;");
    CompileOptions options;
    options.include_dirs = {"stdlib", "more"};
    options.loader = &files;
    Compiled c = compile_text("INCLUDE 'lib.fortu'; INCLUDE 'only_here.fortu'; ARGUMENT X, Y; RETURN K + L + X;",
                              options, "models/model.fortu");
    REQUIRE_MESSAGE(c.model, c.sink.render_all());
    CHECK(value_at_origin(c) == 31);
    CHECK(files.loaded() == std::vector<std::string>{"models/lib.fortu", "stdlib/only_here.fortu"});
}

TEST_CASE("a library reached twice, by two spellings of its path, is read once") {
    MemorySourceLoader files;
    files.add_script("m/lib.fortu", "CONSTANT K = 5;");
    CompileOptions options;
    options.loader = &files;
    Compiled c = compile_text("INCLUDE 'lib.fortu'; INCLUDE './lib.fortu'; ARGUMENT X, Y; RETURN K + X;", options,
                              "m/model.fortu");
    REQUIRE_MESSAGE(c.model, c.sink.render_all());
    CHECK(value_at_origin(c) == 5);
    CHECK(files.loaded() == std::vector<std::string>{"m/lib.fortu"});
}

TEST_CASE("an included library can include another, relative to its own folder") {
    MemorySourceLoader files;
    files.add_script("m/lib/outer.fortu", "INCLUDE 'inner.fortu'; CONSTANT OUTER = INNER * 10;");
    files.add_script("m/lib/inner.fortu", "CONSTANT INNER = 7;");
    CompileOptions options;
    options.loader = &files;
    Compiled c = compile_text("INCLUDE 'lib/outer.fortu'; ARGUMENT X, Y; RETURN OUTER + X;", options, "m/model.fortu");
    REQUIRE_MESSAGE(c.model, c.sink.render_all());
    CHECK(value_at_origin(c) == 70);
}

TEST_CASE("a missing library names every folder searched") {
    MemorySourceLoader files;
    CompileOptions options;
    options.include_dirs = {"stdlib"};
    options.loader = &files;
    Compiled c = compile_text("ARGUMENT X, Y;\nINCLUDE 'shapes.fortu';\nRETURN DISC(X, Y, 0, 0, 1);\n", options,
                              "m/model.fortu");
    CHECK_FALSE(c.model);
    CHECK(c.sink.render_all() == "m/model.fortu:2:1: error: cannot find 'shapes.fortu' to include\n"
                                 "INCLUDE 'shapes.fortu';\n"
                                 "^~~~~~~~~~~~~~~~~~~~~~\n"
                                 "note: searched: m, stdlib\n");
}

TEST_CASE("a syntax error in a library points into the library") {
    MemorySourceLoader files;
    files.add_script("m/lib/broken.fortu", "FUNCTION BROKEN(A)\n  RETURN A + ;\nEND\n");
    CompileOptions options;
    options.loader = &files;
    Compiled c = compile_text("ARGUMENT X, Y;\nINCLUDE 'lib/broken.fortu';\nRETURN BROKEN(X);\n", options,
                              "m/model.fortu");
    CHECK_FALSE(c.model);
    CHECK(c.sink.render_all() == "m/lib/broken.fortu:2:14: error: unexpected ';', expecting expression\n"
                                 "  RETURN A + ;\n"
                                 "             ^\n");
}

TEST_CASE("IMAGE gives the picture's grey levels row after row from the top; IMAGE_WIDTH and IMAGE_HEIGHT its size") {
    MemorySourceLoader files;
    files.add_image("m/bumps.png", ImageTable{3, 2, {0.0, 0.25, 0.5, 0.75, 1.0, 0.125}});
    CompileOptions options;
    options.loader = &files;
    const std::string head = "ARGUMENT X, Y; CONSTANT T = IMAGE('bumps.png'), W = IMAGE_WIDTH('bumps.png'), "
                             "H = IMAGE_HEIGHT('bumps.png'); ";
    Compiled size = compile_text(head + "RETURN X + 1000*W + 100*H + SIZE(T);", options, "m/model.fortu");
    REQUIRE_MESSAGE(size.model, size.sink.render_all());
    CHECK(value_at_origin(size) == 3000 + 200 + 6);
    const std::vector<double> expected{0.0, 0.25, 0.5, 0.75, 1.0, 0.125};
    for (int k = 1; k <= 6; ++k) {
        CAPTURE(k);
        Compiled c = compile_text(head + "RETURN X + T(" + std::to_string(k) + ");", options, "m/model.fortu");
        REQUIRE_MESSAGE(c.model, c.sink.render_all());
        CHECK(value_at_origin(c) == expected[k - 1]);
    }
    CHECK(files.loaded().front() == "m/bumps.png");
}

TEST_CASE("IMAGE of a missing picture, or of one too large, is a model error naming the file") {
    MemorySourceLoader files;
    files.add_image("m/huge.png", ImageTable{129, 128, std::vector<double>(129 * 128, 0.5)});
    CompileOptions options;
    options.loader = &files;
    Compiled missing = compile_text("ARGUMENT X, Y; CONSTANT T = IMAGE('gone.png'); RETURN X + T(1);", options,
                                    "m/model.fortu");
    CHECK_FALSE(missing.model);
    CHECK(missing.sink.render_all() == "m/model.fortu:1:35: error: cannot read image 'gone.png': no such picture in memory\n"
                                       "ARGUMENT X, Y; CONSTANT T = IMAGE('gone.png'); RETURN X + T(1);\n"
                                       "                                  ^~~~~~~~~~\n");
    Compiled huge = compile_text("ARGUMENT X, Y; CONSTANT T = IMAGE('huge.png'); RETURN X + T(1);", options,
                                 "m/model.fortu");
    CHECK_FALSE(huge.model);
    REQUIRE(huge.sink.diagnostics().size() == 1);
    CHECK(huge.sink.diagnostics()[0].message == "image 'huge.png' is 129x128: at most 16384 pixels");
}

TEST_CASE("an INCLUDE cycle is an error naming the chain of files") {
    MemorySourceLoader files;
    CompileOptions options;
    options.loader = &files;
    SUBCASE("a file including itself") {
        files.add_script("m/a.fortu", "INCLUDE 'a.fortu';\nARGUMENT X, Y;\nRETURN X;\n");
        Compiled c = compile_text("INCLUDE 'a.fortu';\nARGUMENT X, Y;\nRETURN X;\n", options, "m/a.fortu");
        CHECK_FALSE(c.model);
        CHECK(c.sink.render_all() == "m/a.fortu:1:1: error: INCLUDE cycle: m/a.fortu -> m/a.fortu\n"
                                     "INCLUDE 'a.fortu';\n"
                                     "^~~~~~~~~~~~~~~~~\n");
    }
    SUBCASE("a.fortu -> b.fortu -> a.fortu") {
        files.add_script("m/a.fortu", "INCLUDE 'b.fortu';\nARGUMENT X, Y;\nRETURN X + B;\n");
        files.add_script("m/b.fortu", "CONSTANT B = 2;\nINCLUDE 'a.fortu';\n");
        Compiled c = compile_text("INCLUDE 'b.fortu';\nARGUMENT X, Y;\nRETURN X + B;\n", options, "m/a.fortu");
        CHECK_FALSE(c.model);
        CHECK(c.sink.render_all() == "m/b.fortu:2:1: error: INCLUDE cycle: m/a.fortu -> m/b.fortu -> m/a.fortu\n"
                                     "INCLUDE 'a.fortu';\n"
                                     "^~~~~~~~~~~~~~~~~\n");
    }
}

TEST_CASE("a library reached along two paths that make no cycle is still read once") {
    // model -> shapes -> rfunc and model -> rfunc: a diamond, not a cycle
    MemorySourceLoader files;
    files.add_script("m/rfunc.fortu", "CONSTANT R = 1;");
    files.add_script("m/shapes.fortu", "INCLUDE 'rfunc.fortu'; CONSTANT S = R * 10;");
    CompileOptions options;
    options.loader = &files;
    Compiled c = compile_text("INCLUDE 'shapes.fortu'; INCLUDE 'rfunc.fortu'; ARGUMENT X, Y; RETURN X + S + R;", options,
                              "m/model.fortu");
    REQUIRE_MESSAGE(c.model, c.sink.render_all());
    CHECK(value_at_origin(c) == 11);
    CHECK(files.loaded() == std::vector<std::string>{"m/shapes.fortu", "m/rfunc.fortu"});
}
