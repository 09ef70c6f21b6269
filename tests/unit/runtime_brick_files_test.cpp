// tests/unit/runtime_brick_files_test.cpp — the durable files of bricked runs: whole-row
// bricks, writes of many rows at once, the done map's batches, and the .pvti pieces.
#include "test_support.hpp"

#include "runtime/brick_files.hpp"
#include "runtime/brick_output.hpp"
#include "runtime/bricks.hpp"
#include "runtime/output_error.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <numeric>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

using namespace fortu;
namespace fs = std::filesystem;

namespace {

Grid grid3(int cols, int rows, int slices) {
    Grid g;
    g.dims = 3;
    g.x = {-1, 1, cols};
    g.y = {-1, 1, rows};
    g.z = {-1, 1, slices};
    return g;
}

/// A fresh folder under the system's temporary one.
fs::path scratch(const std::string& name) {
    const fs::path dir = fs::temp_directory_path() / ("fortu_brick_files_" + name);
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

}  // namespace

TEST_CASE("whole-row bricks span every column and hold about edge³ nodes") {
    const BrickLayout a = BrickLayout::whole_rows(grid3(512, 512, 512), 128);
    CHECK(a.shape == std::array<int, 3>{512, 64, 64});
    CHECK(a.counts == std::array<int, 3>{1, 8, 8});
    CHECK(a.brick_points() == 128u * 128 * 128);
    const BrickLayout b = BrickLayout::whole_rows(grid3(97, 97, 97), 8);   // 512 / 97 = 5.3 rows×slices
    CHECK(b.shape == std::array<int, 3>{97, 2, 2});
    CHECK(b.size() == 49u * 49);
    const BrickLayout c = BrickLayout::whole_rows(grid3(4, 3, 2), 128);   // a brick larger than the grid
    CHECK(c.shape == std::array<int, 3>{4, 3, 2});
    CHECK(c.size() == 1);
    CHECK(c.box(0).hi == std::array<int, 3>{3, 2, 1});
}

TEST_CASE("a partial file writes many pieces in one call, in order") {
    const fs::path dir = scratch("pieces");
    PartialFile file((dir / "part").string(), (dir / "out").string(), false);
    std::vector<std::string> rows;
    std::vector<PartialFile::Piece> pieces;
    for (int i = 0; i < 3000; ++i) rows.push_back(std::to_string(i % 10));   // more than IOV_MAX pieces
    for (const std::string& r : rows) pieces.push_back({r.data(), r.size()});
    file.write_at(5, pieces);
    file.commit();
    const std::string text = test::read_file(dir / "out");
    REQUIRE(text.size() == 5 + 3000);
    CHECK(text.substr(0, 5) == std::string(5, '\0'));
    CHECK(text.substr(5, 12) == "012345678901");
    CHECK(text.back() == '9');
}

TEST_CASE("the done map records batches of bricks after the output's sync, and only those") {
    const fs::path dir = scratch("recorder");
    const std::string destination = (dir / "out.vti").string();
    std::atomic<int> syncs{0};
    {
        DoneMap map(destination, "key", DoneMap::Mode::Fresh);
        DoneRecorder recorder(map, [&] { ++syncs; }, 3600.0, 4);   // batches by count only
        for (std::size_t b = 0; b < 4; ++b) recorder.finished(b);
        for (int wait = 0; wait < 2000 && test::read_file(destination + ".done") == "key\n"; ++wait)
            std::this_thread::sleep_for(std::chrono::milliseconds(5));
        CHECK(test::read_file(destination + ".done") == "key\n0\n1\n2\n3\n");
        CHECK(syncs == 1);
        recorder.finished(7);
        recorder.finished(5);
        recorder.flush();
        CHECK(syncs == 2);
        CHECK(test::read_file(destination + ".done") == "key\n0\n1\n2\n3\n7\n5\n");
        recorder.finished(9);   // never flushed: a kill here loses it, the map does not claim it
    }
    CHECK(test::read_file(destination + ".done") == "key\n0\n1\n2\n3\n7\n5\n");
    DoneMap resumed(destination, "key", DoneMap::Mode::Resume);
    CHECK(resumed.done() == std::set<std::size_t>{0, 1, 2, 3, 5, 7});
    CHECK_THROWS_AS(DoneMap(destination, "another key", DoneMap::Mode::Resume), OutputError);
}

TEST_CASE("a failed sync stops the recording and reaches the workers") {
    const fs::path dir = scratch("failing");
    DoneMap map((dir / "out.vti").string(), "key", DoneMap::Mode::Fresh);
    DoneRecorder recorder(map, [] { throw OutputError("out.vti", "disk full"); }, 3600.0, 1);
    recorder.finished(0);
    CHECK_THROWS_AS(recorder.flush(), OutputError);
    CHECK_THROWS_AS(recorder.finished(1), OutputError);
    CHECK(test::read_file(dir / "out.vti.done") == "key\n");
}

TEST_CASE("a .pvti's pieces tile the slices, each with its neighbour's first plane") {
    const fs::path dir = scratch("pvti");
    const Grid g = grid3(5, 4, 9);
    const BrickLayout layout(g, std::array<int, 3>{5, 4, 2});   // 5 layers of 2 slices
    const std::string path = (dir / "f.pvti").string();
    BrickOutputSpec spec{path, layout, 3.0, 0, true, 3};
    const std::unique_ptr<BrickOutput> out = open_brick_output(spec);
    std::vector<double> values;
    for (std::size_t b = 0; b < layout.size(); ++b) {
        const BrickBox box = layout.box(b);
        values.resize(box.points());
        for (int s = box.lo[2]; s <= box.hi[2]; ++s)
            for (int r = box.lo[1]; r <= box.hi[1]; ++r)
                for (int c = box.lo[0]; c <= box.hi[0]; ++c) values[box.local(c, r, s)] = g.index(c, r, s);
        out->write(b, box, values, {});
    }
    out->sync();
    out->close();
    out->finish(0);
    const std::string index = test::read_file(path);
    // Layers 0..4 split in 3: [0,1) [1,3) [3,5) → slices 0-2, 2-6, 6-8.
    CHECK(index.find("<Piece Extent=\"0 4 0 3 0 2\" Source=\"f_0.vti\"/>") != std::string::npos);
    CHECK(index.find("<Piece Extent=\"0 4 0 3 2 6\" Source=\"f_1.vti\"/>") != std::string::npos);
    CHECK(index.find("<Piece Extent=\"0 4 0 3 6 8\" Source=\"f_2.vti\"/>") != std::string::npos);
    const std::string piece = test::read_file(dir / "f_1.vti");
    CHECK(piece.find("WholeExtent=\"0 4 0 3 2 6\"") != std::string::npos);
    // The piece's first value: slice 2, volume row 0 (image row 3), column 0.
    const std::size_t data = piece.find('_', piece.find("<AppendedData")) + 1 + 8;
    double first = 0;
    std::memcpy(&first, piece.data() + data, 8);
    CHECK(first == double(g.index(0, 3, 2)));
    CHECK_FALSE(fs::exists(dir / ".f_1.vti.bricks"));
}
