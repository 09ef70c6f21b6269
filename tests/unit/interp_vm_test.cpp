// tests/unit/interp_vm_test.cpp — the .vm importer: the six benchmark models load (2D and
// 3D), values follow the format's semantics with the sign negated, and malformed files get
// located diagnostics.
#include "interp_test_support.hpp"

#include "interp/vm_import.hpp"

#include <doctest/doctest.h>

#include <filesystem>

using namespace fortu;

namespace {

struct Imported {
    std::optional<Model> model;
    DiagnosticSink sink;
    std::shared_ptr<SourceFile> source;
};

Imported import_text(const std::string& text) {
    Imported r;
    r.source = std::make_shared<SourceFile>("m.vm", text);
    r.model = import_vm(r.source, r.sink);
    return r;
}

}  // namespace

TEST_CASE("is_vm_path recognises the extension") {
    CHECK(is_vm_path("a/prospero.vm"));
    CHECK(is_vm_path("X.VM"));
    CHECK_FALSE(is_vm_path("a.fortu"));
    CHECK_FALSE(is_vm_path("vm"));
}

TEST_CASE("every shared .vm model imports") {
    const std::filesystem::path dir = std::filesystem::path(FORTU_SHARED_DIR) / "data";
    struct Expect { const char* name; std::size_t arguments; };
    for (Expect e : {Expect{"prospero.vm", 2}, Expect{"hi.vm", 2}, Expect{"quarter.vm", 2},
                     Expect{"bear.vm", 3}, Expect{"colonnade.vm", 3}, Expect{"tanglecube.vm", 3}}) {
        CAPTURE(e.name);
        std::string error;
        auto source = SourceFile::load((dir / e.name).string(), error);
        REQUIRE(source);
        DiagnosticSink sink;
        std::optional<Model> model = import_vm(source, sink);
        REQUIRE_MESSAGE(model, sink.render_all());
        CHECK(model->arguments.size() == e.arguments);
        CHECK(model->ranges[0]->min == -1.0);
        CHECK(model->ranges[1]->max == 1.0);
    }
}

TEST_CASE("quarter.vm: values are the negated .vm result") {
    Imported r = import_text("# A quarter-circle\ny var-y\nx var-x\nmxy max x y\ny2 square y\nx2 square x\n"
                             "r2 add x2 y2\nf const 0.5\ncircle sub r2 f\nout max mxy circle\n");
    REQUIRE_MESSAGE(r.model, r.sink.render_all());
    // At (-0.5, -0.25): max(x, y) = -0.25, r² - 0.5 = -0.1875; max = -0.1875; negated 0.1875.
    CHECK(evaluate_point(*r.model, {-0.5, -0.25, 0}, engine_named("voxel")).value == 0.1875);
    CHECK(evaluate_point(*r.model, {-0.5, -0.25, 0}, engine_named("classic")).value == 0.1875);
    CHECK(evaluate_point(*r.model, {0.5, 0.5, 0}, engine_named("voxel")).value == -0.5);
}

TEST_CASE("every .vm operation has the format's meaning") {
    Imported r = import_text("x var-x\ny var-y\nz var-z\na div x y\nb ln z\nc exp a\nd sin x\ne cos y\n"
                             "f abs b\ng sqrt z\nh neg g\ni mul c d\nj min e f\nk sub i j\nl add k h\n"
                             "m mul l z\n");
    REQUIRE_MESSAGE(r.model, r.sink.render_all());
    CHECK(r.model->arguments.size() == 3);
    const double x = 0.3, y = -0.7, z = 0.4;
    const double expected = -(((std::exp(x / y) * std::sin(x)) - std::min(std::cos(y), std::fabs(std::log(z))) +
                               -std::sqrt(z)) * z);
    CHECK(evaluate_point(*r.model, {x, y, z}, engine_named("voxel")).value == expected);
}

TEST_CASE("malformed .vm files: located diagnostics") {
    auto errors = [](const std::string& text) {
        Imported r = import_text(text);
        CHECK_FALSE(r.model);
        return r.sink.render_all();
    };
    CHECK(errors("x var-x\ny frob x\n") ==
          "m.vm:2:3: error: unknown operation 'frob'\n"
          "y frob x\n"
          "  ^~~~\n"
          "note: known: var-x var-y var-z const add sub mul div max min neg square sqrt abs exp ln sin cos\n");
    CHECK(errors("x var-x\ny add x q\n") ==
          "m.vm:2:9: error: unknown name 'q'\n"
          "y add x q\n"
          "        ^\n"
          "note: a value must be defined on an earlier line\n");
    CHECK(errors("x var-x\ny neg\n") ==
          "m.vm:2:6: error: 'neg' takes 1 operand, got 0\n"
          "y neg\n"
          "     ^\n");
    CHECK(errors("x var-x\ny neg x x\n") ==
          "m.vm:2:9: error: 'neg' takes 1 operand\n"
          "y neg x x\n"
          "        ^\n");
    CHECK(errors("c const 1e999\n") ==
          "m.vm:1:9: error: '1e999' is not a finite number\n"
          "c const 1e999\n"
          "        ^~~~~\n");
    CHECK(errors("x var-x\nx var-y\n") ==
          "m.vm:2:1: error: 'x' is defined twice\n"
          "x var-y\n"
          "^\n"
          "note: every value of the SSA format has its own name\n");
    CHECK(errors("lonely\n") ==
          "m.vm:1:7: error: expected an operation after 'lonely'\n"
          "lonely\n"
          "      ^\n"
          "note: each line is: NAME OP ARGS...\n");
    CHECK(errors("# nothing\n\n") ==
          "m.vm:1:1: error: the model has no values\n"
          "# nothing\n"
          "^\n"
          "note: a .vm model is lines NAME OP ARGS...; the last one is the result\n");
}

TEST_CASE("the R0 formula a + b - sqrt(a² + b²) becomes an R-conjunction with the same value") {
    Imported r = import_text("x var-x\ny var-y\ns add x y\na2 square x\nb2 square y\nq add a2 b2\n"
                             "r sqrt q\ng sub s r\n");
    REQUIRE_MESSAGE(r.model, r.sink.render_all());
    const ir::Node& neg = r.model->graph.node(r.model->root);
    REQUIRE(neg.op == ir::Op::Neg);
    CHECK(r.model->graph.node(neg.args[0]).op == ir::Op::RAnd);
    CHECK(r.model->graph.node(neg.args[0]).imm == 0.0);
    const double x = 0.3, y = -0.7;
    CHECK(evaluate_point(*r.model, {x, y, 0}, engine_named("voxel")).value == -((x + y) - std::sqrt(x * x + y * y)));
    // With other operands it stays arithmetic.
    Imported plain = import_text("x var-x\ny var-y\ns add x y\na2 square x\nb2 square x\nq add a2 b2\n"
                                 "r sqrt q\ng sub s r\n");
    REQUIRE(plain.model);
    CHECK(plain.model->graph.node(plain.model->graph.node(plain.model->root).args[0]).op == ir::Op::Sub);
}
