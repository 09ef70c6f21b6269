// tests/unit/interp_domain_test.cpp — the domain a model gets: the RANOK header comment when
// the script gives no range (with its note), --size N as square cells, --domain auto.
#include "interp/domain_auto.hpp"
#include "interp/grid_size.hpp"
#include "interp/lower.hpp"

#include <doctest/doctest.h>

using namespace fortu;

namespace {

std::optional<Model> compile_text(const std::string& text, DiagnosticSink& sink) {
    static std::vector<std::shared_ptr<SourceFile>> keep;
    keep.push_back(std::make_shared<SourceFile>("m.fortu", text));
    return compile(keep.back(), CompileOptions{}, sink);
}

}  // namespace

TEST_CASE("the header comment sets the ranges, with a note, when the script gives none") {
    DiagnosticSink sink;
    const auto m = compile_text("//x=8, y=5,z=8;\nARGUMENT X,Y,Z;\nRETURN 1 - X*X;\n", sink);
    REQUIRE(m);
    REQUIRE(m->ranges[1]);
    CHECK(m->ranges[1]->min == -5);
    CHECK(m->ranges[1]->max == 5);
    CHECK(m->domain_note ==
          "m.fortu:1:1: note: the domain X [-8, 8], Y [-5, 5], Z [-8, 8] comes from this header comment "
          "(RANOK half-extents); --domain overrides it\n//x=8, y=5,z=8;\n^~~~~~~~~~~~~~~\n");
    CHECK(sink.render_all() == m->domain_note);
}

TEST_CASE("ARGUMENT ranges win over the header comment, silently") {
    DiagnosticSink sink;
    const auto m = compile_text("ARGUMENT X(6), Y(5), Z(5);\n//x : 6 ; y : 5 ; z : 4.5\nRETURN 1 - X*X;\n", sink);
    REQUIRE(m);
    CHECK(m->ranges[2]->max == 5);
    CHECK(m->domain_note.empty());
    CHECK(sink.diagnostics().empty());
}

TEST_CASE("--size N: N nodes along the longest axis, square cells") {
    DiagnosticSink sink;
    const auto m = compile_text("ARGUMENT X(-8, 8), Y(-5, 5), Z(-8, 8);\nRETURN 1 - X*X;\n", sink);
    REQUIRE(m);
    const Grid g = sized_grid(*m, {97});
    CHECK(g.cols() == 97);
    CHECK(g.slices() == 97);
    CHECK(g.rows() == 61);   // 10 / (16 / 96) = 60 cells
    CHECK(g.x.step() == doctest::Approx(g.y.step()).epsilon(1e-12));
    CHECK(g.y.min == doctest::Approx(-5.0));
    const Grid explicit_size = sized_grid(*m, {10, 20, 30});
    CHECK(explicit_size.rows() == 20);
    CHECK(explicit_size.y.min == -5);
}

TEST_CASE("--domain auto: a box around the solid, or why there is none") {
    DiagnosticSink sink;
    const auto ball = compile_text("ARGUMENT X,Y,Z;\nRETURN 0.25 - (X-3)^2 - Y*Y - Z*Z;\n", sink);
    const auto found = find_domain_auto(*ball);
    REQUIRE(std::holds_alternative<std::array<AxisRange, 3>>(found));
    const auto& box = std::get<std::array<AxisRange, 3>>(found);
    CHECK(box[0].min <= 2.5);
    CHECK(box[0].min > 2.4);
    CHECK(box[0].max >= 3.5);
    CHECK(box[0].max < 3.6);
    CHECK(box[1].min <= -0.5);
    CHECK(box[1].min > -0.6);
    const auto slab = compile_text("ARGUMENT X,Y,Z;\nRETURN 1 - X*X;\n", sink);
    CHECK(std::get<std::string>(find_domain_auto(*slab)) ==
          "--domain auto: the solid reaches the faces of every search cube up to [-1024, 1024]³: it is unbounded "
          "(or larger, or its intervals too loose to bound it); give --domain");
    const auto none = compile_text("ARGUMENT X,Y;\nRETURN -1 - X*X;\n", sink);
    CHECK(std::get<std::string>(find_domain_auto(*none)) ==
          "--domain auto: the model is negative everywhere in [-1024, 1024]² (interval arithmetic): the solid is "
          "empty; give --domain");
}
