// tests/unit/grammar_domain_comment_test.cpp — the RANOK header comment's spellings, as the
// 56 RANOK scripts use them: half-extents with `=` or `:`, `,` or `.` decimals, ranges
// `X=[0;7]`, half-extents then a centre on separate lines; and what is not a header.
#include "grammar/domain_comment.hpp"

#include <doctest/doctest.h>

using namespace fortu;

namespace {

std::optional<DomainComment> read(const std::string& text) {
    static std::vector<std::unique_ptr<SourceFile>> keep;
    keep.push_back(std::make_unique<SourceFile>("t.fortu", text));
    return read_domain_comment(*keep.back());
}

void check_range(const DomainComment& c, int axis, double lo, double hi) {
    REQUIRE(c.ranges[axis].has_value());
    CHECK((*c.ranges[axis])[0] == lo);
    CHECK((*c.ranges[axis])[1] == hi);
}

}  // namespace

TEST_CASE("half-extents on the first line, '=' and ',' between entries (Chainik)") {
    const auto c = read("//x=8, y=5,z=8;\n\nARGUMENT X,Y,Z;\nRETURN X;\n");
    REQUIRE(c);
    check_range(*c, 0, -8, 8);
    check_range(*c, 1, -5, 5);
    check_range(*c, 2, -8, 8);
    CHECK(c->where.begin.line == 1);
    CHECK(c->where.begin.column == 1);
}

TEST_CASE("':' and ';' with decimal commas and points after ARGUMENT (Bone, Lopatka, Pawn1)") {
    auto c = read("ARGUMENT X0,Y0,Z0;\n\n//x : 3,5 ; y : 3,5 ; z : 3,5\n\nVARIABLE X=X0;\n");
    REQUIRE(c);
    check_range(*c, 0, -3.5, 3.5);
    check_range(*c, 2, -3.5, 3.5);
    CHECK(c->where.begin.line == 3);
    c = read("ARGUMENT XARG,YARG,ZARG;\n//x : 7 ; y : 27.5 ; z : 7\n");
    check_range(*c, 1, -27.5, 27.5);
    c = read("ARGUMENT XARG,YARG,ZARG;\n//x : 4 ; y :4.5 ; z : 4\n");
    check_range(*c, 1, -4.5, 4.5);
}

TEST_CASE("ranges X=[0;7] (economy)") {
    const auto c = read("ARGUMENT X,Y,Z;\n\n//X=[0;7] Y=[0;7] Z=[0;7]\n\nVARIABLE f=X+7;\n");
    REQUIRE(c);
    check_range(*c, 0, 0, 7);
    check_range(*c, 2, 0, 7);
}

TEST_CASE("half-extents, then the centre, one entry a line under headings (ConceptLopatka)") {
    const auto c = read("ARGUMENT XARG,YARG,ZARG;\n\n//Lengths of the scene's basis vectors:\n//x=12\n//y=37,5\n"
                        "//z=12\n\n//Centre of the scene:\n//x=0\n//y=0\n//z=140\n\n\nCONSTANT PI=3.14;\n");
    REQUIRE(c);
    check_range(*c, 0, -12, 12);
    check_range(*c, 1, -37.5, 37.5);
    check_range(*c, 2, 128, 152);
    CHECK(c->where.begin.line == 4);
}

TEST_CASE("not a header: comments after the first statement, other text, non-positive extents") {
    CHECK(!read("ARGUMENT X,Y,Z;\nVARIABLE A = X;\n//x : 3 ; y : 3 ; z : 3\nRETURN A;\n"));
    CHECK(!read("//VARIABLE X=X1+TettaX;\nARGUMENT X,Y;\n"));
    CHECK(!read("//x is the width\nARGUMENT X,Y;\n"));
    CHECK(!read("//x=0, y=2\nARGUMENT X,Y;\n"));
    CHECK(!read("ARGUMENT X,Y;\nRETURN X;\n"));
}
