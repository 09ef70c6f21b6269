// tests/unit/runtime_output_test.cpp — the extension table, atomic writes, and the byte-exact
// formats: npy (header bytes, size, payload), csv (lines), svg (the contour).
#include "test_support.hpp"
#include "runtime/atomic_file.hpp"
#include "runtime/contour.hpp"
#include "runtime/mesh_io.hpp"
#include "runtime/npy.hpp"
#include "runtime/output.hpp"
#include "runtime/output_error.hpp"
#include "runtime/output_formats.hpp"
#include "runtime/output_path.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <limits>
#include <sstream>

using namespace fortu;
namespace fs = std::filesystem;

namespace {

using fortu::test::ScratchDir;


std::string read_bytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::vector<std::string> read_lines(const std::string& path) {
    std::ifstream in(path);
    std::vector<std::string> lines;
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    return lines;
}

Field y_plus_x() {
    Field f;
    f.grid.x = {-1.0, 1.0, 3};
    f.grid.y = {-1.0, 1.0, 3};
    f.values = {0, 1, 2, -1, 0, 1, -2, -1, 0};
    return f;
}

Field sample2(int cols, int rows, const std::function<double(double, double)>& fn) {
    Field f;
    f.grid.x = {-1.0, 1.0, cols};
    f.grid.y = {-1.0, 1.0, rows};
    f.values.resize(f.grid.points());
    for (int r = 0; r < rows; ++r)
        for (int c = 0; c < cols; ++c) f.values[f.grid.index(c, r)] = fn(f.grid.x_at(c), f.grid.y_at(r));
    return f;
}

}  // namespace

TEST_CASE("output_format_for follows the extension, case-insensitively") {
    auto name = [](const char* path) {
        const OutputFormat* format = output_format_for(path);
        return format ? std::string(format->name) : std::string("none");
    };
    CHECK(name("out.png") == "PNG");
    CHECK(name("dir.d/OUT.PNG") == "PNG");
    CHECK(name("a.JPG") == "JPEG");
    CHECK(name("a.jpeg") == "JPEG");
    CHECK(name("a.tif") == "TIFF");
    CHECK(name("a.Tiff") == "TIFF");
    CHECK(name("a.bmp") == "BMP");
    CHECK(name("a.exr") == "OpenEXR");
    CHECK(name("a.npy") == "NumPy");
    CHECK(name("a.csv") == "CSV");
    CHECK(name("a.svg") == "SVG");
    CHECK(name("slice_%03d.png") == "PNG");
    CHECK(name("a.xyz") == "none");
    CHECK(name("noextension") == "none");
    CHECK(name("dir.png/file") == "none");
    CHECK(name("") == "none");
    CHECK(supported_output_extensions() ==
          std::vector<std::string>{"png", "jpg", "jpeg", "tif", "tiff", "bmp", "exr", "npy", "csv", "svg", "stl", "obj",
                                   "ply", "vti", "nrrd", "vdb", "pvti", "hdf", "vtkhdf"});
    CHECK(output_format_for("a.stl")->kind == OutputKind::Mesh);
    CHECK(output_format_for("a.PLY")->kind == OutputKind::Mesh);
    CHECK(output_format_for("a.vti")->kind == OutputKind::Volume);
    CHECK(output_format_for("a.vti")->takes_mimages);
    CHECK_FALSE(output_format_for("a.nrrd")->takes_mimages);
    CHECK(output_format_for("a.bmp")->kind == OutputKind::Picture);
    CHECK(output_format_for("a.exr")->kind == OutputKind::MImages);
    CHECK(output_format_for("a.npy")->kind == OutputKind::Field);
    CHECK(output_format_for("a.svg")->kind == OutputKind::Contour);
    CHECK(output_format_for("a.jpg")->lossy);
    CHECK_FALSE(output_format_for("a.png")->lossy);
}

TEST_CASE("the usage text and the golden kinds are generated from the table") {
    CHECK(output_formats_usage(4) == "picture: .png .jpg .tif .bmp\n"
                                     "    M-images: .exr (value + n1..n4 channels)\n"
                                     "    values: .npy .csv (x,y[,z],value lines)\n"
                                     "    zero contour: .svg\n"
                                     "    mesh: .stl (binary; ASCII with --ascii) .obj (with normals) .ply (binary, float64)\n"
                                     "    volume: .vti (ParaView; value [+ n1..n5]) .nrrd .vdb (narrow band, --band) .pvti (.vti pieces, one per MPI rank) .hdf (VTKHDF, ParaView 5.10+)");
    CHECK(output_extensions_text() == ".png .jpg .tif .bmp .exr .npy .csv .svg .stl .obj .ply .vti .nrrd .vdb .pvti .hdf");
    CHECK(output_extensions_text(", ") == ".png, .jpg, .tif, .bmp, .exr, .npy, .csv, .svg, .stl, .obj, .ply, .vti, .nrrd, .vdb, .pvti, .hdf");
    CHECK(golden_output_kinds() == std::vector<std::string>{"png", "exr", "npy", "csv", "svg", "stl", "obj", "ply", "vti", "nrrd"});
    CHECK(golden_output_format("npy") == output_format_for("x.npy"));
    CHECK(golden_output_format("jpg") == nullptr);   // lossy: no golden comparator
    CHECK(golden_output_format("xyz") == nullptr);
    for (const OutputFormat& format : output_formats()) {
        CAPTURE(format.name);
        CHECK(static_cast<bool>(format.write) != (format.kind == OutputKind::Mesh));   // meshes: write_mesh
        CHECK(static_cast<bool>(format.write_mesh) == (format.kind == OutputKind::Mesh));
        CHECK_FALSE(format.extensions.empty());
        CHECK(output_format_for("a." + std::string(format.extension())) == &format);
    }
}

TEST_CASE("resolve_output: the format and whether the path is a series, decided once") {
    const OutputTarget one = resolve_output("dir/out.PNG");
    CHECK(one.path == "dir/out.PNG");
    CHECK(one.format == output_format_for("x.png"));
    CHECK_FALSE(one.series);
    CHECK(one.file(3) == "dir/out.PNG");
    const OutputTarget slices = resolve_output("slice_%03d.svg");
    CHECK(slices.format->name == "SVG");
    CHECK(slices.series);
    CHECK(slices.file(7) == "slice_007.svg");
    CHECK_THROWS_WITH_AS(resolve_output("out.xyz"),
                         "cannot write 'out.xyz': unknown output format '.xyz' (known: png, jpg, jpeg, tif, tiff, bmp, "
                         "exr, npy, csv, svg, stl, obj, ply, vti, nrrd, vdb, pvti, hdf, vtkhdf)",
                         OutputError);
}

TEST_CASE("file series: %d, %3d, %03d are number conversions; other % signs are kept") {
    CHECK(is_file_series("m_%d.png"));
    CHECK(is_file_series("slice_%03d.png"));
    CHECK(is_file_series("a%2db"));
    CHECK_FALSE(is_file_series("100%.png"));
    CHECK_FALSE(is_file_series("m_%s.png"));
    CHECK_FALSE(is_file_series("m_%123d.png"));
    CHECK(file_series_name("m_%d.png", 3) == "m_3.png");
    CHECK(file_series_name("slice_%03d.png", 7) == "slice_007.png");
    CHECK(file_series_name("s%3d.png", 42) == "s 42.png");
    CHECK(file_series_name("100%_%d.png", 1) == "100%_1.png");
    CHECK(file_series_name("%n%d", 5) == "%n5");
    CHECK(path_extension("a/b.c/Name.TXT") == "txt");
    CHECK(path_extension("a.b/name") == "");
}

TEST_CASE("npy: the header bytes are exactly NumPy's, the size is header + 8 per value") {
    const Field f = y_plus_x();
    const std::string dict = "{'descr': '<f8', 'fortran_order': False, 'shape': (3, 3), }";
    const std::string expected = std::string("\x93NUMPY\x01\x00\x76\x00", 10) + dict + std::string(58, ' ') + "\n";
    CHECK(npy_header(f.grid, false) == expected);
    CHECK(npy_header(f.grid, false).size() == 128);

    ScratchDir dir;
    write_field(f, dir / "y.npy");
    const std::string bytes = read_bytes(dir / "y.npy");
    REQUIRE(bytes.size() == 128 + 9 * 8);
    CHECK(bytes.substr(0, 128) == expected);
    for (int i = 0; i < 9; ++i) {
        double v = 0;
        std::memcpy(&v, bytes.data() + 128 + 8 * i, 8);
        CHECK(v == f.values[i]);
    }
    CHECK(dir.entries() == 1);
}

TEST_CASE("npy: float32, 3D shape (slices, rows, cols), NaN and inf kept") {
    Field f;
    f.grid.dims = 3;
    f.grid.x = {0.0, 1.0, 4};
    f.grid.y = {0.0, 1.0, 3};
    f.grid.z = {0.0, 1.0, 2};
    f.values.assign(f.grid.points(), 0.5);
    f.values[1] = std::nan("");
    f.values[2] = -std::numeric_limits<double>::infinity();
    const std::string header = npy_header(f.grid, true);
    CHECK(header.substr(10, 62) == "{'descr': '<f4', 'fortran_order': False, 'shape': (2, 3, 4), }");
    CHECK(header.size() % 64 == 0);
    CHECK(header.back() == '\n');

    ScratchDir dir;
    OutputOptions options;
    options.npy_float32 = true;
    write_field(f, dir / "v.npy", options);
    const std::string bytes = read_bytes(dir / "v.npy");
    REQUIRE(bytes.size() == header.size() + 24 * 4);
    CHECK(bytes.substr(0, header.size()) == header);
    float v[3];
    std::memcpy(v, bytes.data() + header.size(), sizeof v);
    CHECK(v[0] == 0.5f);
    CHECK(std::isnan(v[1]));
    CHECK(v[2] == -std::numeric_limits<float>::infinity());
}

TEST_CASE("csv: header, one line per node in image order, %.17g, nan/inf/-inf") {
    Field f = y_plus_x();
    f.values[1] = 0.1;
    f.values[2] = std::nan("");
    f.values[3] = std::numeric_limits<double>::infinity();
    f.values[4] = -std::numeric_limits<double>::infinity();
    f.values[5] = -std::nan("");
    ScratchDir dir;
    write_field(f, dir / "y.csv");
    const auto lines = read_lines(dir / "y.csv");
    REQUIRE(lines.size() == 10);
    CHECK(lines[0] == "x,y,value");
    CHECK(lines[1] == "-1,1,0");
    CHECK(lines[2] == "0,1,0.10000000000000001");
    CHECK(lines[3] == "1,1,nan");
    CHECK(lines[4] == "-1,0,inf");
    CHECK(lines[5] == "0,0,-inf");
    CHECK(lines[6] == "1,0,nan");
    CHECK(lines[9] == "1,-1,0");
}

TEST_CASE("csv: every value and coordinate is printf's %.17g, from subnormals to the largest double") {
    // Values that print differently in every notation %g has: subnormal, tiny, exponents at
    // the switch between fixed and scientific, halves, -0, the extremes; and a grid whose
    // coordinates are not short decimals.
    const std::vector<double> values{5e-324, -2.2250738585072014e-308, 1e-300, 0.0001, 0.00001, -0.0,
                                     0.5, 1.0 / 3, 12345678901234567.0, 1e16, 1e17, -1.7976931348623157e308,
                                     2.5e-5, 999999999999999.9, 0.1 + 0.2, 7.0, 123.456, -9.87654321e-10,
                                     6.02214076e23, 42.0, 3.0e-7};
    Field f;
    f.grid.x = {-0.7, 1.3, 7};
    f.grid.y = {0.1, 0.4, 3};
    REQUIRE(f.grid.points() == values.size());
    f.values = values;
    ScratchDir dir;
    write_field(f, dir / "numbers.csv");
    const auto lines = read_lines(dir / "numbers.csv");
    REQUIRE(lines.size() == values.size() + 1);
    auto printed = [](double v) {
        char text[64];
        std::snprintf(text, sizeof text, "%.17g", v);
        return std::string(text);
    };
    for (int r = 0; r < f.grid.rows(); ++r)
        for (int c = 0; c < f.grid.cols(); ++c) {
            const std::size_t i = f.grid.index(c, r);
            CHECK(lines[1 + i] == printed(f.grid.x_at(c)) + "," + printed(f.grid.y_at(r)) + "," + printed(values[i]));
        }
}

TEST_CASE("csv: 3D lines carry z; coordinates with 17 digits") {
    Field f;
    f.grid.dims = 3;
    f.grid.x = {0.0, 1.0, 4};
    f.grid.y = {0.0, 1.0, 2};
    f.grid.z = {-1.0, 1.0, 2};
    f.values.assign(f.grid.points(), -2.5);
    ScratchDir dir;
    write_field(f, dir / "v.csv");
    const auto lines = read_lines(dir / "v.csv");
    REQUIRE(lines.size() == 17);
    CHECK(lines[0] == "x,y,z,value");
    CHECK(lines[1] == "0,1,-1,-2.5");
    CHECK(lines[2] == "0.33333333333333331,1,-1,-2.5");
    CHECK(lines[16] == "1,0,1,-2.5");
}

TEST_CASE("atomic write: a missing directory is a clear OutputError and leaves nothing") {
    ScratchDir dir;
    const std::string path = dir / "missing/out.png";
    try {
        write_field(y_plus_x(), path);
        FAIL("expected an OutputError");
    } catch (const OutputError& e) {
        CHECK(std::string(e.what()) == "cannot write '" + path + "': directory '" + (dir / "missing") +
                                           "' does not exist");
        CHECK(e.path() == path);
    }
    CHECK(dir.entries() == 0);
}

TEST_CASE("atomic write: a failing writer leaves the destination untouched and no temporary") {
    ScratchDir dir;
    const std::string path = dir / "keep.csv";
    { std::ofstream(path) << "old\n"; }
    std::string seen_temp;
    CHECK_THROWS_WITH_AS(write_atomically(path,
                                          [&](const std::string& temp) {
                                              seen_temp = temp;
                                              std::ofstream(temp) << "half";
                                              throw std::runtime_error("disk on fire");
                                          }),
                         ("cannot write '" + path + "': disk on fire").c_str(), OutputError);
    CHECK(read_bytes(path) == "old\n");
    CHECK(dir.entries() == 1);
    // The temporary keeps the real extension last and sits next to the destination.
    CHECK(fs::path(seen_temp).parent_path() == dir.path);
    CHECK(fs::path(seen_temp).filename().string().starts_with(".keep.csv.tmp"));
    CHECK(fs::path(seen_temp).extension() == ".csv");
    CHECK_FALSE(fs::exists(seen_temp));

    SUBCASE("and a successful one replaces it") {
        write_field(y_plus_x(), path);
        CHECK(read_lines(path).at(0) == "x,y,value");
        CHECK(dir.entries() == 1);
    }
}

TEST_CASE("write_field: unknown extension, directory as destination, empty grid") {
    ScratchDir dir;
    CHECK_THROWS_WITH_AS(write_field(y_plus_x(), dir / "out.xyz"),
                         ("cannot write '" + (dir / "out.xyz") +
                          "': unknown output format '.xyz' (known: png, jpg, jpeg, tif, tiff, bmp, exr, npy, csv, svg, stl, obj, ply, vti, nrrd, vdb, pvti, hdf, vtkhdf)")
                             .c_str(),
                         OutputError);
    fs::create_directory(dir / "taken.csv");
    CHECK_THROWS_AS(write_field(y_plus_x(), dir / "taken.csv"), OutputError);
    Field empty;
    empty.grid.x.nodes = 0;
    CHECK_THROWS_WITH_AS(write_field(empty, dir / "e.npy"),
                         ("cannot write '" + (dir / "e.npy") + "': the grid has no points").c_str(), OutputError);
    CHECK(dir.entries() == 1);   // only the directory we made
}

TEST_CASE("zero contour of a circle: one closed polyline on the circle") {
    const double radius = 0.6;
    const Field f = sample2(41, 41, [&](double x, double y) { return radius * radius - x * x - y * y; });
    const auto lines = zero_contour(f);
    REQUIRE(lines.size() == 1);
    CHECK(lines[0].closed);
    CHECK(lines[0].points.size() > 40);
    for (const auto& p : lines[0].points) CHECK(std::hypot(p[0], p[1]) == doctest::Approx(radius).epsilon(0.01));
}

TEST_CASE("zero contour: a line across the grid is one open polyline, exact for a linear field") {
    const Field f = sample2(11, 7, [](double x, double y) { return y - 0.5 * x - 0.1; });
    const auto lines = zero_contour(f);
    REQUIRE(lines.size() == 1);
    CHECK_FALSE(lines[0].closed);
    for (const auto& p : lines[0].points) CHECK(p[1] - 0.5 * p[0] - 0.1 == doctest::Approx(0.0).epsilon(1e-14));
    const auto& ends = lines[0].points;
    CHECK(std::min(ends.front()[0], ends.back()[0]) == -1.0);
    CHECK(std::max(ends.front()[0], ends.back()[0]) == 1.0);
}

TEST_CASE("zero contour: two circles, and a hole of invalid points") {
    Field f = sample2(60, 60, [](double x, double y) {
        return std::max(0.1 - (x - 0.5) * (x - 0.5) - y * y, 0.1 - (x + 0.5) * (x + 0.5) - y * y);
    });
    CHECK(zero_contour(f).size() == 2);
    // Invalid points across the right circle cut its loop open.
    for (int r = 0; r < 60; ++r) f.values[f.grid.index(45, r)] = std::nan("");
    const auto lines = zero_contour(f);
    int open = 0;
    for (const auto& l : lines) open += !l.closed;
    CHECK(open == 2);
}

TEST_CASE("svg: header with a viewBox of the picture's pixels, one polyline per chain") {
    Field f = sample2(21, 21, [](double x, double y) { return 0.25 - x * x - y * y; });
    f.grid.x = {-2.0, 2.0, 21};
    ScratchDir dir;
    write_field(f, dir / "c.svg");
    const auto lines = read_lines(dir / "c.svg");
    REQUIRE(lines.size() >= 5);
    CHECK(lines[0] == "<?xml version=\"1.0\" encoding=\"UTF-8\"?>");
    CHECK(lines[1] == "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"21\" height=\"21\" viewBox=\"0 0 21 21\">");
    CHECK(lines[3] == "<metadata><fortu-domain xmlns=\"urn:fortu:domain\" x0=\"-2\" x1=\"2\" y0=\"-1\" y1=\"1\" "
                      "dx=\"0.2\" dy=\"0.1\"/></metadata>");
    int polylines = 0;
    for (const auto& l : lines) polylines += l.starts_with("<polyline");
    CHECK(polylines == 1);
    CHECK(lines.back() == "</svg>");
}

TEST_CASE("a mesh format takes a mesh, not grid values") {
    fortu::test::ScratchDir dir;
    CHECK_THROWS_WITH_AS(write_field(y_plus_x(), dir / "m.stl"),
                         ("cannot write '" + dir / "m.stl" +
                          "': STL holds a mesh, made from the model by 'fortu run', not grid values").c_str(),
                         OutputError);
    CHECK(dir.entries() == 0);
}

TEST_CASE("ascii STL: a facet's normal and vertices as printf's %.9g, the solid named fortu") {
    // One triangle whose coordinates print in fixed, scientific and integer form.
    Mesh mesh;
    mesh.vertices = {{0.0, 0.0, 0.0}, {1.0 / 3, 2.5e-7, -1234567.891}, {0.0, 1e-300, 7.0}};
    mesh.triangles = {{0, 1, 2}};
    fortu::test::ScratchDir dir;
    OutputOptions options;
    options.ascii = true;
    write_stl(mesh, dir / "t.stl", options);
    const auto lines = read_lines(dir / "t.stl");
    REQUIRE(lines.size() == 9);
    auto printed = [](double a, double b, double c) {
        char text[128];
        std::snprintf(text, sizeof text, "%.9g %.9g %.9g", a, b, c);
        return std::string(text);
    };
    const auto& v = mesh.vertices;
    const std::array<double, 3> e1{v[1][0] - v[0][0], v[1][1] - v[0][1], v[1][2] - v[0][2]};
    const std::array<double, 3> e2{v[2][0] - v[0][0], v[2][1] - v[0][1], v[2][2] - v[0][2]};
    CHECK(lines[0] == "solid fortu");
    CHECK(lines[1].starts_with("facet normal "));
    CHECK(lines[2] == " outer loop");
    for (int k = 0; k < 3; ++k) CHECK(lines[3 + k] == "  vertex " + printed(v[k][0], v[k][1], v[k][2]));
    CHECK(lines[6] == " endloop");
    CHECK(lines[7] == "endfacet");
    CHECK(lines[8] == "endsolid fortu");
    // The normal: the unit cross product, each component as %.9g.
    std::array<double, 3> n{e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
    double components[3];
    REQUIRE(std::sscanf(lines[1].c_str(), "facet normal %lg %lg %lg", &components[0], &components[1], &components[2]) == 3);
    const double length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    for (int k = 0; k < 3; ++k) CHECK(components[k] == doctest::Approx(n[k] / length).epsilon(1e-8));
    CHECK(lines[1] == "facet normal " + printed(components[0], components[1], components[2]));
}
