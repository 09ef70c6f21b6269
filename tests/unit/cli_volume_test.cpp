// tests/unit/cli_volume_test.cpp — 3D outputs end to end: .vti read back by an independent
// parse and .vdb by OpenVDB's own reader, both equal to the values fortu computed (its .npy);
// the .npy sidecar; slices as planes; shaded views; and the usage errors of these options.
#include "cli_support.hpp"
#include "test_support.hpp"

#include "runtime/image_io.hpp"
#include "runtime/npy.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <sstream>

#ifdef FORTU_HAVE_OPENVDB
#include <openvdb/openvdb.h>
#endif

using fortu::test::quote;
using fortu::test::run_fortu;
using namespace fortu;

namespace {

const std::string kSphere = std::string(FORTU_SOURCE_DIR) + "/examples/floz3_sphere80.fortu";

/// The numbers of an XML attribute `name="a b c"` in `text`.
std::vector<double> attribute(const std::string& text, const std::string& name) {
    const std::size_t at = text.find(name + "=\"");
    REQUIRE(at != std::string::npos);
    const std::size_t start = at + name.size() + 2;
    std::istringstream in(text.substr(start, text.find('"', start) - start));
    std::vector<double> out;
    for (double v; in >> v;) out.push_back(v);
    return out;
}

/// fortu's values of the sphere on `size`³ (its .npy), image order.
std::vector<double> sphere_values(const fortu::test::ScratchDir& t, int size, Grid& grid) {
    REQUIRE(run_fortu("run " + quote(kSphere) + " --size " + std::to_string(size) + " -o s.npy", t.path).status == 0);
    grid.dims = 3;
    grid.x = grid.y = grid.z = Axis{-1.25, 1.25, size};
    auto values = read_npy_values(t / "s.npy", grid);
    REQUIRE(values);
    return *values;
}

}  // namespace

TEST_CASE("a .vti of the FLOZ3 sphere holds origin, spacing and exactly the values fortu computed") {
    fortu::test::ScratchDir t;
    Grid grid;
    const std::vector<double> expected = sphere_values(t, 24, grid);
    REQUIRE(run_fortu("run " + quote(kSphere) + " --size 24 -o s.vti", t.path).status == 0);
    const std::string vti = t.read("s.vti");
    CHECK(attribute(vti, "WholeExtent") == std::vector<double>{0, 23, 0, 23, 0, 23});
    CHECK(attribute(vti, "Origin") == std::vector<double>{-1.25, -1.25, -1.25});
    CHECK(attribute(vti, "Spacing")[0] == doctest::Approx(2.5 / 23).epsilon(1e-15));
    const std::size_t data = vti.find('_', vti.find("<AppendedData")) + 1;
    std::uint64_t bytes = 0;
    std::memcpy(&bytes, vti.data() + data, 8);
    REQUIRE(bytes == 8u * 24 * 24 * 24);
    // VTK order: x fastest, y ascending; fortu's rows run from the largest y.
    int mismatches = 0;
    for (int k = 0; k < 24; ++k)
        for (int j = 0; j < 24; ++j)
            for (int i = 0; i < 24; ++i) {
                double v = 0;
                std::memcpy(&v, vti.data() + data + 8 + 8 * ((std::size_t(k) * 24 + j) * 24 + i), 8);
                mismatches += v != expected[grid.index(i, 23 - j, k)];
            }
    CHECK(mismatches == 0);
    CHECK(vti.substr(vti.size() - 30) == "\n  </AppendedData>\n</VTKFile>\n");

    // --mimages m.vti: the value and n1..n5 as point data.
    REQUIRE(run_fortu("run " + quote(kSphere) + " --size 8 --mimages m.vti", t.path).status == 0);
    const std::string m = t.read("m.vti");
    CHECK(m.find("Name=\"n5\" format=\"appended\" offset=\"20520\"") != std::string::npos);
}

TEST_CASE("a 3D .npy has a sidecar with its first node and steps; .nrrd its header") {
    fortu::test::ScratchDir t;
    Grid grid;
    sphere_values(t, 5, grid);
    CHECK(t.read("s.npy.json") ==
          "{\n  \"shape\": [5, 5, 5],\n  \"axes\": [\"z\", \"y\", \"x\"],\n"
          "  \"first\": {\"x\": -1.25, \"y\": 1.25, \"z\": -1.25},\n"
          "  \"step\": {\"x\": 0.625, \"y\": -0.625, \"z\": 0.625},\n"
          "  \"note\": \"value[k][j][i] is at x = first.x + i*step.x, y = first.y + j*step.y, z = first.z + k*step.z "
          "(y decreases down the rows: image order)\"\n}\n");
    REQUIRE(run_fortu("run " + quote(kSphere) + " --size 5 -o s.nrrd", t.path).status == 0);
    const std::string nrrd = t.read("s.nrrd");
    CHECK(nrrd.substr(0, nrrd.find("\n\n") + 2) ==
          "NRRD0004\n# written by fortu: the model's value at every grid node\ntype: double\ndimension: 3\n"
          "sizes: 5 5 5\nspace dimension: 3\nspace directions: (0.625,0,0) (0,0.625,0) (0,0,0.625)\n"
          "space origin: (-1.25,-1.25,-1.25)\nendian: little\nencoding: raw\n\n");
    CHECK(nrrd.size() == nrrd.find("\n\n") + 2 + 8 * 125);
}

#ifdef FORTU_HAVE_OPENVDB
TEST_CASE("a .vdb read back with OpenVDB: the narrow band holds fortu's values, the rest the side's sign") {
    fortu::test::ScratchDir t;
    Grid grid;
    const std::vector<double> expected = sphere_values(t, 24, grid);
    REQUIRE(run_fortu("run " + quote(kSphere) + " --size 24 -o s.vdb --band 2", t.path).status == 0);
    openvdb::initialize();
    openvdb::io::File file(t / "s.vdb");
    file.open();
    auto grid_base = file.readGrid("value");
    file.close();
    auto vdb = openvdb::gridPtrCast<openvdb::FloatGrid>(grid_base);
    REQUIRE(vdb);
    const double step = 2.5 / 23, band = 2 * step;
    const openvdb::Vec3d world = vdb->indexToWorld(openvdb::Coord(3, 4, 5));
    CHECK(world.x() == doctest::Approx(-1.25 + 3 * step));
    CHECK(world.y() == doctest::Approx(-1.25 + 4 * step));
    CHECK(world.z() == doctest::Approx(-1.25 + 5 * step));
    auto accessor = vdb->getConstAccessor();
    int wrong = 0, active = 0;
    for (int k = 0; k < 24; ++k)
        for (int j = 0; j < 24; ++j)
            for (int i = 0; i < 24; ++i) {
                const double v = expected[grid.index(i, 23 - j, k)];
                const openvdb::Coord c(i, j, k);
                if (std::fabs(v) <= band) {
                    ++active;
                    wrong += !accessor.isValueOn(c) || accessor.getValue(c) != static_cast<float>(v);
                } else {
                    wrong += accessor.isValueOn(c) || (accessor.getValue(c) > 0) != (v > 0);
                }
            }
    CHECK(wrong == 0);
    CHECK(active > 0);
    CHECK(vdb->activeVoxelCount() == openvdb::Index64(active));
}
#endif

TEST_CASE("--slice evaluates one plane of any size; a shaded view otherwise") {
    fortu::test::ScratchDir t;
    REQUIRE(run_fortu("run " + quote(kSphere) + " --slice x=0.5 --size 40x30 -o p.npy", t.path).status == 0);
    CHECK(t.read("p.npy").size() == 128 + 8 * 40 * 30);   // (30, 40, 1): z planes of one column
    REQUIRE(run_fortu("run " + quote(kSphere) + " --slice z=0.3 --size 300x200 -o z.png", t.path).status == 0);
    std::string error;
    const auto z = read_image(t / "z.png", error);
    REQUIRE(z);
    CHECK(z->cols == 300);
    CHECK(z->rows == 200);
    REQUIRE(run_fortu("run " + quote(kSphere) + " --size 64 --view top -o v.png", t.path).status == 0);
    const auto v = read_image(t / "v.png", error);
    REQUIRE(v);
    CHECK(v->cols == 64);
    CHECK(v->rows == 64);
    const std::size_t corner = 0, centre = (32 * 64 + 32) * v->channels.size();
    CHECK(v->pixels[corner] == 1.0f);    // white background
    CHECK(v->pixels[centre] < 0.95f);    // the sphere, shaded
}

TEST_CASE("--up stands a shaded view on Y (the default) or on another axis") {
    // A rod along Y: seen from the side it stands upright with Y up and lies flat with Z up.
    fortu::test::ScratchDir t;
    const std::string rod = t.write("rod.fortu", "ARGUMENT X(-1, 1), Y(-1, 1), Z(-1, 1);\n"
                                                 "RETURN (0.04 - X*X - Z*Z) & (0.81 - Y*Y);\n");
    // The extent of the drawn (non-white) pixels along the picture's columns and rows.
    auto extent = [&](const std::string& args) {
        const std::string png = "rod.png";
        REQUIRE(run_fortu("run " + quote(rod) + " --size 64 --view side " + args + " -o " + png, t.path).status == 0);
        std::string error;
        const auto image = read_image(t / png, error);
        REQUIRE(image);
        const std::size_t channels = image->channels.size();
        int col_lo = image->cols, col_hi = -1, row_lo = image->rows, row_hi = -1;
        for (int row = 0; row < image->rows; ++row)
            for (int col = 0; col < image->cols; ++col)
                if (image->pixels[(std::size_t(row) * image->cols + col) * channels] < 0.99f) {
                    col_lo = std::min(col_lo, col), col_hi = std::max(col_hi, col);
                    row_lo = std::min(row_lo, row), row_hi = std::max(row_hi, row);
                }
        return std::pair<int, int>{col_hi - col_lo + 1, row_hi - row_lo + 1};
    };
    const auto [y_wide, y_tall] = extent("");
    CHECK(y_tall > 3 * y_wide);
    const auto [z_wide, z_tall] = extent("--up z");
    CHECK(z_wide > 3 * z_tall);
    const auto [x_wide, x_tall] = extent("--up X");   // X up, side from +Y: along the rod, a disc
    CHECK(x_wide == x_tall);
    const auto [xf_wide, xf_tall] = extent("--up X --view front");   // front from -Z: Y runs across
    CHECK(xf_wide > 3 * xf_tall);
    CHECK(run_fortu("run " + quote(rod) + " --up w -o a.png", t.path).out == "fortu: error: --up: 'w' is not x, y or z\n");
}

TEST_CASE("slice, size and view usage errors exit 2") {
    fortu::test::ScratchDir t;
    const std::string m = quote(kSphere);
    CHECK(run_fortu("run " + m + " --slice 3 -o 's_%d.png'", t.path).out ==
          "fortu: error: -o: 's_%d.png' writes every z slice (%d); it does not combine with --slice\n");
    auto r = run_fortu("run " + m + " --size 64x64 -o a.npy", t.path);
    CHECK(r.status == 2);
    CHECK(r.out == "fortu: error: --size: '64x64' has 2 numbers but the model has 3 arguments; give N, WxHxD, or "
                   "a plane with --slice\n");
    CHECK(run_fortu("run " + m + " --slice z=7 -o a.png", t.path).out ==
          "fortu: error: --slice: z=7 is outside the domain's Z [-1.25, 1.25]\n");
    CHECK(run_fortu("run " + m + " --slice w=1", t.path).out ==
          "fortu: error: --slice: 'w=1' is not a slice (use z=0.3, x=-1.2, y=0, or a z slice number K)\n");
    CHECK(run_fortu("run " + m + " --view 10,95 -o a.png", t.path).out ==
          "fortu: error: --view: '10,95' is not top, front, side, iso or AZ,EL in degrees (EL from -90 to 90)\n");
    CHECK(run_fortu("run " + m + " --slice 99 -o a.png", t.path).out == "fortu: error: --slice: 99 is outside 0..63\n");
}
