// tests/unit/runtime_brick_mimages_test.cpp — the M-images of a bricked run as the writers
// put them on disk: bricks written with their components (computed from each brick's reach)
// make the same bytes as the in-memory .vti writer, for cubes and whole rows, ragged bricks,
// and the .pvti's pieces carry every array at the offsets their headers name.
#include "test_support.hpp"

#include "runtime/brick_output.hpp"
#include "runtime/bricks.hpp"
#include "runtime/fv_model.hpp"
#include "runtime/output_formats.hpp"
#include "runtime/vti.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

using namespace fortu;
namespace fs = std::filesystem;

namespace {

fs::path scratch(const std::string& name) {
    const fs::path dir = fs::temp_directory_path() / ("fortu_brick_mimages_" + name);
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

Field sample(int cols, int rows, int slices) {
    Field f;
    f.grid.dims = 3;
    f.grid.x = {-1.0, 1.0, cols};
    f.grid.y = {-0.7, 1.3, rows};
    f.grid.z = {0.0, 2.0, slices};
    f.values.resize(f.grid.points());
    const Grid& g = f.grid;
    for (int s = 0; s < g.slices(); ++s)
        for (int r = 0; r < g.rows(); ++r)
            for (int c = 0; c < g.cols(); ++c)
                f.values[g.index(c, r, s)] = std::sin(2 * g.x_at(c)) * std::cos(g.y_at(r)) - 0.3 * g.z_at(s);
    f.values[g.index(3, 4, 5)] = std::nan("");   // an invalid point: NaN components around it
    return f;
}

/// Writes `field` brick by brick to `path` as a bricked run does: each brick's values from its
/// reach, its components from FvStencil::box.
void write_in_bricks(const Field& field, const BrickLayout& layout, const std::string& path, int pieces = 1) {
    const Grid& g = field.grid;
    BrickOutputSpec spec{path, layout, 3.0, 0, true, pieces};
    spec.mimages = true;
    const std::unique_ptr<BrickOutput> out = open_brick_output(spec);
    const FvStencil stencil(g);
    std::vector<double> held, values, components;
    for (std::size_t b = 0; b < layout.size(); ++b) {
        const BrickBox own = layout.box(b), reach = stencil.reach(own);
        held.assign(reach.points(), 0.0);
        for (int s = reach.lo[2]; s <= reach.hi[2]; ++s)
            for (int r = reach.lo[1]; r <= reach.hi[1]; ++r)
                for (int c = reach.lo[0]; c <= reach.hi[0]; ++c) held[reach.local(c, r, s)] = field.values[g.index(c, r, s)];
        values.resize(own.points());
        for (int s = own.lo[2]; s <= own.hi[2]; ++s)
            for (int r = own.lo[1]; r <= own.hi[1]; ++r)
                for (int c = own.lo[0]; c <= own.hi[0]; ++c) values[own.local(c, r, s)] = field.values[g.index(c, r, s)];
        components.resize(5 * own.points());
        double* n[5];
        for (int k = 0; k < 5; ++k) n[k] = components.data() + k * own.points();
        stencil.box(held.data(), reach, own, n);
        out->write(b, own, values, components);
    }
    out->sync();
    out->close();
    out->finish(0);
}

}  // namespace

TEST_CASE("bricks with their components write the in-memory --mimages .vti byte for byte") {
    const fs::path dir = scratch("vti");
    const Field field = sample(13, 11, 9);
    OutputOptions options;
    options.mimages = true;
    write_vti(field, resolve_output((dir / "memory.vti").string()), options);
    const std::string expected = test::read_file(dir / "memory.vti");
    REQUIRE(expected.size() > 6 * 8 * field.grid.points());
    write_in_bricks(field, BrickLayout(field.grid, 4), (dir / "cubes.vti").string());   // 4 x 3 x 3 bricks, ragged
    CHECK(test::read_file(dir / "cubes.vti") == expected);
    write_in_bricks(field, BrickLayout::whole_rows(field.grid, 5), (dir / "rows.vti").string());
    CHECK(test::read_file(dir / "rows.vti") == expected);
    write_in_bricks(field, BrickLayout(field.grid, std::array<int, 3>{13, 1, 1}), (dir / "thin.vti").string());
    CHECK(test::read_file(dir / "thin.vti") == expected);
}

TEST_CASE("a .pvti with M-images: each piece is a .vti of its slices with the six arrays, the index names them") {
    const fs::path dir = scratch("pvti");
    const Field field = sample(7, 6, 9);
    const BrickLayout layout(field.grid, std::array<int, 3>{7, 6, 2});   // 5 layers of 2 slices
    write_in_bricks(field, layout, (dir / "m.pvti").string(), 2);
    const std::string index = test::read_file(dir / "m.pvti");
    for (const char* name : {"value", "n1", "n2", "n3", "n4", "n5"})
        CHECK(index.find(std::string("<PDataArray type=\"Float64\" Name=\"") + name + "\"/>") != std::string::npos);
    // Layers [0,2) and [2,5): slices 0..4 (the next piece's first plane included) and 4..8.
    const std::string piece = test::read_file(dir / "m_1.vti");
    const std::string header = vti_piece_header(field.grid, 4, 8, true);
    REQUIRE(piece.compare(0, header.size(), header) == 0);
    const std::size_t points = 7 * 6 * 5, block = 8 + 8 * points;
    CHECK(header.find("Name=\"n5\" format=\"appended\" offset=\"" + std::to_string(5 * block) + "\"") != std::string::npos);
    CHECK(piece.size() == header.size() + 6 * block + vti_trailer().size());
    // n4 of node (col 2, image row 1, slice 6): volume row 6 - 1 - 1 = 4, piece slice 2.
    const FvModel fv(field);
    double n4 = 0;
    std::memcpy(&n4, piece.data() + header.size() + 4 * block + 8 + 8 * ((2 * 6 + 4) * 7 + 2), 8);
    CHECK(n4 == fv.n(4, field.grid.index(2, 1, 6)));
}
