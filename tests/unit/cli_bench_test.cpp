// tests/unit/cli_bench_test.cpp — `fortu bench` end to end: usage errors (exit 2), the JSON
// and CSV documents' structure, an over-budget classic cell kept as skipped with its
// estimate, the plot, the float32 / sign / M-image variants, and `--performance` without its
// data. No assertion looks at how long anything took.
#include "cli/bench/bench_report.hpp"
#include "cli_support.hpp"
#include "test_support.hpp"

#include <doctest/doctest.h>

#include <filesystem>
#include <regex>
#include <fstream>
#include <sstream>
#include <vector>

using fortu::test::quote;
using fortu::test::run_fortu;

namespace {

using TempDir = fortu::test::ScratchDir;


// Classic cost: the R0 conjunction's 6 operations plus each argument read twice = 10 per point.
const char* kAnd = "ARGUMENT X, Y;\nRETURN X & Y;\n";

int count(const std::string& text, const std::string& what) {
    int n = 0;
    for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + what.size())) ++n;
    return n;
}

std::vector<std::string> lines_of(const std::string& text) {
    std::vector<std::string> lines;
    std::stringstream s(text);
    for (std::string line; std::getline(s, line);) lines.push_back(line);
    return lines;
}

}  // namespace

TEST_CASE("fortu bench: usage errors exit 2 before any work") {
    TempDir t;
    const std::string m = quote(t.write("and.fortu", kAnd));
    CHECK(run_fortu("bench").status == 2);
    CHECK(run_fortu("bench").out == "fortu: error: 'fortu bench': give at least one MODEL, or --paper, or --performance\n");
    CHECK(run_fortu("bench " + m + " --engines classic,gpu").out ==
          "fortu: error: --engines: unknown engine 'gpu' (classic, voxel, voxel-f32, sign, fv)\n");
    CHECK(run_fortu("bench " + m + " --sizes 100,1").out == "fortu: error: --sizes: '1' is not an integer in 2..20000\n");
    CHECK(run_fortu("bench " + m + " --sizes 10,").out == "fortu: error: --sizes: '' is not an integer in 2..20000\n");
    CHECK(run_fortu("bench " + m + " --repeat 0").out == "fortu: error: --repeat: '0' is not an integer in 1..1000\n");
    CHECK(run_fortu("bench " + m + " --budget -5").out ==
          "fortu: error: --budget: '-5' is not a positive number of operations\n");
    CHECK(run_fortu("bench " + m + " --budget nan").out ==
          "fortu: error: --budget: 'nan' is not a positive number of operations\n");
    CHECK(run_fortu("bench " + m + " --plot out.png").out ==
          "fortu: error: --plot: 'out.png' must end in .svg (fortu writes SVG plots)\n");
    CHECK(run_fortu("bench " + m + " --json").out == "fortu: error: 'fortu bench': --json needs a value\n");
    CHECK(run_fortu("bench " + m + " --frobnicate").out == "fortu: error: unknown option '--frobnicate'\nsee fortu bench --help\n");
    CHECK(run_fortu("bench " + m + " --quick").out ==
          "fortu: error: 'fortu bench': --quick, --out and --examples go with --paper or --performance\n");
    CHECK(run_fortu("bench --paper " + m).out ==
          "fortu: error: 'fortu bench --paper' runs the papers' models; give no MODEL with it\n");
    CHECK(run_fortu("bench --paper --sizes 100").out ==
          "fortu: error: 'fortu bench --paper' chooses its own sizes and writes its files to --out DIR\n");
    CHECK(run_fortu("bench " + m + " --sizes 20000").out ==
          "fortu: error: --sizes: 20000x20000 is 400,000,000 points, more than the 268,435,456 fortu allocates\n");
    const auto help = run_fortu("bench --help", ".", true);
    CHECK(help.status == 0);
    CHECK(help.out.starts_with("usage:\n  fortu bench MODEL... [options]   time each model x engine x size"));
    for (const char* args : {"--sizes 100,1", "--plot out.png", "--frobnicate"})
        CHECK(run_fortu("bench " + m + " " + args).status == 2);
}

TEST_CASE("fortu bench: a model that does not load is a model error") {
    TempDir t;
    const auto r = run_fortu("bench " + quote((t.path / "missing.fortu").string()));
    CHECK(r.status == 1);
    CHECK(r.out.find("fortu: error: ") == 0);
    const std::string bad = quote(t.write("bad.fortu", "ARGUMENT X, Y;\nRETURN X +;\n"));
    CHECK(run_fortu("bench " + bad + " --sizes 10").status == 1);
    CHECK(!std::filesystem::exists(t.path / "out.json"));
}

TEST_CASE("fortu bench: the over-budget classic cell is printed as skipped with its estimate") {
    TempDir t;
    const std::string m = t.write("and.fortu", kAnd);
    const auto r = run_fortu("bench " + quote(m) + " --sizes 10 --budget 999 --repeat 1", ".", true);
    REQUIRE(r.status == 0);
    const auto lines = lines_of(r.out);
    REQUIRE(lines.size() == 4);
    // Models are named by their file's stem in the table (the JSON and CSV keep the path).
    const std::string prefix = "and    classic  10x10     100  skipped: 1e+03 operations, over the budget of 999; estimated ";
    CHECK(lines[1].starts_with(prefix));
    CHECK(lines[1].ends_with(" (10 operations per point)"));
    CHECK(lines[2].starts_with("and    voxel    10x10     100     1  "));
    CHECK(lines[3].starts_with("ratio classic/voxel, and 10x10: ≈ "));
    CHECK(lines[3].ends_with(" (estimated: classic skipped)"));
}

TEST_CASE("fortu bench: JSON and CSV documents have the documented structure") {
    TempDir t;
    const std::string m = t.write("and.fortu", kAnd);
    const auto r = run_fortu("bench " + quote(m) + " --sizes 8,12 --repeat 2 --budget 1000 --threads 1 --json " +
                             quote((t.path / "b.json").string()) + " --csv " + quote((t.path / "b.csv").string()) +
                             " --plot " + quote((t.path / "b.svg").string()));
    REQUIRE(r.status == 0);
    CHECK(r.out == "");

    const std::string json = t.read("b.json");
    CHECK(json.rfind("{\n  \"schema\": \"fortu-bench/1\",\n  \"machine\": {\"cpu\": ", 0) == 0);
    CHECK(json.find("\"options\": {\"repeat\": 2, \"repeat_cap_seconds\": 20, \"threads\": 1, \"budget_operations\": "
                    "1000, \"memory_method\": ") != std::string::npos);
    CHECK(count(json, "\"engine\": \"classic\"") == 2);
    CHECK(count(json, "\"engine\": \"voxel\"") == 2);
    // 8x8 = 64 points x 10 operations fits the budget; 12x12 = 1440 operations does not.
    CHECK(json.find("      \"model\": " + std::string("\"") + m + "\",\n      \"engine\": \"classic\",\n"
                    "      \"size\": [8, 8],\n      \"points\": 64,\n      \"operations_per_point\": 10,\n"
                    "      \"status\": \"measured\",\n      \"seconds\": [") != std::string::npos);
    CHECK(json.find("      \"engine\": \"classic\",\n      \"size\": [12, 12],\n      \"points\": 144,\n"
                    "      \"operations_per_point\": 10,\n      \"status\": \"skipped\",\n"
                    "      \"skip_reason\": \"1.44e+03 operations, over the budget of 1e+03\",\n"
                    "      \"estimated_operations\": 1440,\n      \"estimated_seconds\": ") != std::string::npos);
    CHECK(json.find("      \"engine\": \"voxel\",\n      \"size\": [12, 12],\n      \"points\": 144,\n"
                    "      \"operations_per_point\": 1,\n      \"status\": \"measured\",\n") != std::string::npos);
    CHECK(count(json, "\"median_seconds\": ") == 3);
    CHECK(count(json, "\"peak_rss_bytes\": ") == 3);
    CHECK(count(json, "\"cpu_seconds\": [") == 3);
    CHECK(count(json, "\"median_cpu_seconds\": ") == 3);
    CHECK(count(json, "\"mimages\": 0\n") == 3);   // measured cells; --mimages not given
    CHECK(json.find("\"mimages\": false}") != std::string::npos);
    CHECK(json.find("mimages_seconds") == std::string::npos);
    CHECK(count(json, "\"estimated\": false}") == 1);
    CHECK(count(json, "\"estimated\": true}") == 1);
    CHECK(json.substr(json.size() - 6) == "  ]\n}\n");

    const auto csv = lines_of(t.read("b.csv"));
    REQUIRE(csv.size() == 5);
    CHECK(csv[0] == "model,engine,cols,rows,slices,points,status,runs,min_s,median_s,max_s,s_per_point,"
                    "ops_per_point,peak_rss_bytes,estimated_s,mimages,mimages_median_s");
    CHECK(csv[1].rfind(m + ",classic,8,8,1,64,measured,2,", 0) == 0);
    CHECK(csv[3].rfind(m + ",classic,12,12,1,144,skipped,0,,,,,10,,", 0) == 0);
    CHECK(csv[3].ends_with(",0,"));   // no M-images, no M-image time
    CHECK(csv[4].rfind(m + ",voxel,12,12,1,144,measured,2,", 0) == 0);
    CHECK(csv[4].ends_with(",,0,"));   // no estimate, no M-images
    for (const std::string& row : csv) CHECK(count(row, ",") == 16);

    const std::string svg = t.read("b.svg");
    CHECK(svg.rfind("<?xml", 0) == 0);
    CHECK(count(svg, "<g class=\"series\"") == 2);   // classic (8x8 only) and voxel
    CHECK(svg.find(">and (classic)</text>") != std::string::npos);
    CHECK(svg.find(">and (voxel)</text>") != std::string::npos);
    CHECK(svg.find(">grid points (log scale)</text>") != std::string::npos);
    CHECK(svg.find(">wall time (s) (log scale)</text>") != std::string::npos);
}

TEST_CASE("fortu bench: an unwritable output is an error and leaves nothing behind") {
    TempDir t;
    const std::string m = t.write("and.fortu", kAnd);
    const auto r = run_fortu("bench " + quote(m) + " --sizes 8 --engines voxel --json " +
                             quote((t.path / "no" / "such" / "b.json").string()));
    CHECK(r.status == 1);
    CHECK(r.out.find("fortu: error: ") != std::string::npos);
    CHECK(!std::filesystem::exists(t.path / "no"));
}

TEST_CASE("fortu bench: the variants' and the suites' options") {
    TempDir t;
    const std::string m = quote(t.write("and.fortu", kAnd));
    auto error = [](const std::string& args) {
        const auto r = run_fortu("bench " + args);
        CHECK(r.status == 2);
        return r.out;
    };
    CHECK(error(m + " --data /tmp") == "fortu: error: 'fortu bench': --data goes with --performance\n");
    CHECK(error("--paper --data /tmp") == "fortu: error: 'fortu bench': --data goes with --performance\n");
    CHECK(error("--paper --performance") ==
          "fortu: error: 'fortu bench': --paper and --performance are two runs; give one\n");
    CHECK(error("--performance " + m) ==
          "fortu: error: 'fortu bench --performance' runs its own suite of models; give no MODEL with it\n");
    CHECK(error("--performance --sizes 100") ==
          "fortu: error: 'fortu bench --performance' chooses its own sizes and writes its files to --out DIR\n");
    CHECK(error("--performance --json x.json") ==
          "fortu: error: 'fortu bench --performance' chooses its own sizes and writes its files to --out DIR\n");
    CHECK(error("--performance --engines sign") ==
          "fortu: error: 'fortu bench --performance' chooses what it times; --engines and --mimages go with MODEL...\n");
    CHECK(error("--paper --mimages") ==
          "fortu: error: 'fortu bench --paper' chooses what it times; --engines and --mimages go with MODEL...\n");
    CHECK(error("--performance --out ''") == "fortu: error: --out: give a folder name\n");
    CHECK(error("--performance --data") == "fortu: error: 'fortu bench': --data needs a value\n");
    CHECK(error(m + " --engines voxel-f64") ==
          "fortu: error: --engines: unknown engine 'voxel-f64' (classic, voxel, voxel-f32, sign, fv)\n");
    const auto help = run_fortu("bench --help", ".", true);
    CHECK(help.out.find("  fortu bench --performance [--quick] [--data DIR]") != std::string::npos);
    CHECK(help.out.find("  --mimages ") != std::string::npos);
}

TEST_CASE("fortu bench: float32, sign and M-image cells in the JSON, CSV and table") {
    TempDir t;
    const std::string m = std::string(FORTU_SOURCE_DIR) + "/examples/s1_fig3a_floz.fortu";
    const auto r = run_fortu("bench " + quote(m) + " --engines voxel-f32,sign --mimages --sizes 16 --repeat 2 --json " +
                                 quote((t.path / "b.json").string()) + " --csv " + quote((t.path / "b.csv").string()),
                             ".", true);
    REQUIRE(r.status == 0);
    const auto lines = lines_of(r.out);
    REQUIRE(lines.size() == 3);   // header and two cells; no classic/voxel ratio
    CHECK(lines[0].starts_with("model"));
    CHECK(lines[0].find("  M-images      peak memory (growth)") != std::string::npos);
    CHECK(lines[1].starts_with("s1_fig3a_floz  voxel-f32  16x16     256     2  "));
    CHECK(lines[1].find("  4 in ") != std::string::npos);
    CHECK(lines[2].starts_with("s1_fig3a_floz  sign       16x16     256     2  "));
    CHECK(lines[2].find("  -             ") != std::string::npos);   // a sign image has no M-images

    const std::string json = t.read("b.json");
    CHECK(json.find("\"memory_method\": ") != std::string::npos);
    CHECK(json.find("\"mimages\": true}") != std::string::npos);
    CHECK(count(json, "\"engine\": ") == 2);
    const auto f32 = json.find("      \"engine\": \"voxel-f32\",\n      \"size\": [16, 16],\n      \"points\": 256,\n"
                               "      \"operations_per_point\": 293,\n      \"status\": \"measured\",\n");
    const auto sign = json.find("      \"engine\": \"sign\",\n      \"size\": [16, 16],\n      \"points\": 256,\n"
                                "      \"operations_per_point\": 293,\n      \"status\": \"measured\",\n");
    REQUIRE(f32 != std::string::npos);
    REQUIRE(sign != std::string::npos);
    CHECK(f32 < sign);   // in the order of --engines
    const std::string f32_cell = json.substr(f32, sign - f32), sign_cell = json.substr(sign);
    CHECK(f32_cell.find("\"mimages\": 4,\n      \"mimages_seconds\": [") != std::string::npos);
    CHECK(count(f32_cell, "\"median_mimages_seconds\": ") == 1);
    const auto runs = f32_cell.find("\"mimages_seconds\": [");
    CHECK(count(f32_cell.substr(runs, f32_cell.find(']', runs) - runs), ",") == 1);   // one per run
    CHECK(sign_cell.find("\"mimages\": 0\n") != std::string::npos);   // a sign image has no M-images
    CHECK(sign_cell.find("mimages_seconds") == std::string::npos);
    CHECK(json.find("  \"ratios\": [\n  ]\n}\n") != std::string::npos);

    const auto csv = lines_of(t.read("b.csv"));
    REQUIRE(csv.size() == 3);
    CHECK(csv[1].rfind(m + ",voxel-f32,16,16,1,256,measured,2,", 0) == 0);
    CHECK(csv[1].find(",,4,") != std::string::npos);
    CHECK(csv[2].rfind(m + ",sign,16,16,1,256,measured,2,", 0) == 0);
    CHECK(csv[2].ends_with(",,0,"));
}

TEST_CASE("fortu bench --performance: without prospero.vm its rows say Not run, the others run, exit 1") {
    TempDir t;
    std::filesystem::create_directories(t.path / "empty");
    const std::string empty = (t.path / "empty").string();
    const auto r = run_fortu("bench --performance --quick --repeat 1 --data " + quote(empty) + " --out " +
                                 quote((t.path / "perf").string()),
                             ".", true);
    CHECK(r.status == 1);
    CHECK(r.out.find("fortu: error: prospero.vm not found in " + empty + "; give --data DIR") != std::string::npos);
    const std::string md = t.read("perf/results.md");
    CHECK(md.starts_with("# fortu bench --performance --quick\n"));
    CHECK(r.out.find(md) != std::string::npos);   // printed as written
    CHECK(count(md, "| Not run: prospero.vm not found in " + empty + " |") == 3);
    CHECK(md.find("| prospero.vm 128² sign image | Not run: ") != std::string::npos);
    CHECK(md.find("| 64-segment FLOZ (floz64.vm) 100² full field, float32 | ") != std::string::npos);
    CHECK(md.find("| S1 Fig. 3a FLOZ contour 100² field and its four M-images, float32 | ") != std::string::npos);
    CHECK(md.find(" (M-images ") != std::string::npos);
    CHECK(count(md, "(not comparable: --quick)") == 3);   // measured rows with a target
    CHECK(count(md, "| Not run: bear.vm not found in " + empty + " |") == 4);
    CHECK(count(md, "| Not run: tanglecube.vm not found in " + empty + " |") == 4);
    CHECK(md.find("| bear.vm 32³ sign volume | Not run: ") != std::string::npos);
    CHECK(md.find("Instruction sets: lane loops ") != std::string::npos);
    CHECK(count(md, "\n| ") == 17);   // the header and sixteen rows

    const std::string json = t.read("perf/results.json");
    CHECK(json.starts_with("{\n  \"schema\": \"fortu-bench-performance/1\",\n  \"machine\": {\"cpu\": "));
    CHECK(json.find("\"options\": {\"quick\": true, \"repeat\": 1, ") != std::string::npos);
    CHECK(json.find("\"data_dir\": " + std::string("\"") + empty + "\"}") != std::string::npos);
    CHECK(count(json, "\"status\": \"not run\",\n      \"met\": null,\n      \"reason\": \"prospero.vm not found in ") == 3);
    CHECK(count(json, "\"cell\": null") == 11);
    CHECK(count(json, "\"status\": \"measured\",\n      \"met\": null,\n      \"reason\": null,\n      \"cell\": {") == 5);
    CHECK(count(json, "\"mimages\": true,") == 2);
    CHECK(count(json, "\"median_mimages_seconds\": ") == 2);
}

TEST_CASE("E4's fit of time against points leaves a skipped cell out and says so") {
    using fortu::BenchCell;
    auto cell = [](int nodes, double median, bool skipped) {
        BenchCell c;
        c.grid.x.nodes = c.grid.y.nodes = nodes;
        c.median = median;   // a skipped cell's median stays 0: it was never run
        c.skipped = skipped;
        if (skipped) c.estimated_seconds = 1e6;
        return c;
    };
    // 10 ns per point plus 1 ms; the 800x800 cell was skipped by the deadline.
    const std::vector<BenchCell> cells{cell(100, 1e-3 + 1e-4, false), cell(200, 1e-3 + 4e-4, false),
                                       cell(400, 1e-3 + 16e-4, false), cell(800, 0, true)};
    const fortu::PointsFit fit = fortu::fit_time_per_point(cells);
    CHECK(fit.cells == 4);
    CHECK(fit.skipped == 1);
    REQUIRE(fit.fit);
    CHECK(fit.fit->points == 3);
    CHECK(fit.fit->slope == doctest::Approx(1e-8).epsilon(1e-9));
    CHECK(fit.fit->r2 == doctest::Approx(1.0));
    CHECK(fortu::points_fit_text("classic", fit) ==
          "- classic: time = 10.0 ns per point (+ 1.00 ms), straight-line fit R² 1.0000; fit over 3 of 4 sizes, "
          "1 skipped over budget\n");

    const fortu::PointsFit none = fortu::fit_time_per_point({cells[0], cells[3], cells[3], cells[3]});
    CHECK_FALSE(none.fit);
    CHECK(fortu::points_fit_text("classic", none) == "- classic: no fit: 1 of 4 sizes measured, 3 skipped over budget\n");
    const fortu::PointsFit all = fortu::fit_time_per_point({cells[0], cells[1]});
    CHECK(fortu::points_fit_text("voxel", all).ends_with("straight-line fit R² 1.0000\n"));
}

namespace {

/// A table line's columns: the text between runs of two or more spaces.
std::vector<std::string> columns_of(const std::string& line) {
    static const std::regex gap(" {2,}");
    std::vector<std::string> out;
    for (std::sregex_token_iterator it(line.begin(), line.end(), gap, -1), end; it != end; ++it)
        if (!it->str().empty()) out.push_back(*it);
    return out;
}

/// Where each column of `line` ends (its last character + 1), in displayed characters.
std::vector<std::size_t> column_ends(const std::string& line) {
    static const std::regex column("\\S+( \\S+)*");
    std::vector<std::size_t> ends;
    for (std::sregex_iterator it(line.begin(), line.end(), column), end; it != end; ++it) {
        const std::size_t bytes = std::size_t(it->position() + it->length());
        std::size_t shown = 0;   // UTF-8 continuation bytes (µ's second) take no column
        for (std::size_t i = 0; i < bytes; ++i) shown += (static_cast<unsigned char>(line[i]) & 0xC0) != 0x80;
        ends.push_back(shown);
    }
    return ends;
}

}  // namespace

TEST_CASE("fortu bench: the table parsed back has its columns apart, each time in its own unit") {
    TempDir t;
    // A long folder name: the table and the plot name the model by its stem.
    const std::string deep = (t.path / "a_rather_long_folder_name_for_the_examples").string();
    std::filesystem::create_directories(deep);
    std::string text = fortu::test::read_file(std::string(FORTU_SOURCE_DIR) + "/examples/nested_discs.fortu");
    text.replace(text.find("CONSTANT N = 12;"), 16, "CONSTANT N = 8;");   // a quick classic cell
    const std::string m = deep + "/nested_discs.fortu";
    std::ofstream(m) << text;
    const auto r = run_fortu("bench " + quote(m) + " " + quote(t.write("and.fortu", kAnd)) +
                                 " --sizes 12,40 --repeat 2 --threads 1 --plot " + quote((t.path / "b.svg").string()),
                             ".", true);
    REQUIRE(r.status == 0);
    const auto lines = lines_of(r.out);
    REQUIRE(lines.size() == 1 + 8 + 4);   // header, 2 models x 2 sizes x 2 engines, 4 ratios
    const std::vector<std::string> header{"model", "engine", "size", "points", "runs", "min", "median", "max",
                                          "per point", "ops/point", "peak memory (growth)"};
    CHECK(columns_of(lines[0]) == header);
    const std::regex time("[0-9]+(\\.[0-9]+)? (ns|µs|ms|s)");
    const std::regex count("[0-9]{1,3}(,[0-9]{3})*");
    const std::regex memory("[0-9.]+ (B|KiB|MiB|GiB) \\(\\+[0-9.]+ (B|KiB|MiB|GiB)\\)");
    const std::vector<std::size_t> header_ends = column_ends(lines[0]);
    for (std::size_t i = 1; i <= 8; ++i) {
        CAPTURE(lines[i]);
        const auto c = columns_of(lines[i]);
        REQUIRE(c.size() == header.size());
        CHECK(c[0] == (i <= 4 ? "nested_discs" : "and"));
        CHECK(c[1] == (i % 2 ? "classic" : "voxel"));
        CHECK(c[2] == ((i - 1) % 4 < 2 ? "12x12" : "40x40"));
        CHECK(c[3] == ((i - 1) % 4 < 2 ? "144" : "1,600"));
        CHECK(c[4] == "2");
        for (int k : {5, 6, 7, 8}) CHECK_MESSAGE(std::regex_match(c[k], time), c[k]);
        CHECK(std::regex_match(c[9], count));
        CHECK(std::regex_match(c[10], memory));
        // The numbers are right-aligned under their headings.
        const auto ends = column_ends(lines[i]);
        for (int k = 3; k <= 9; ++k) CHECK(ends[k] == header_ends[k]);
    }
    CHECK(columns_of(lines[1])[9] == "8,424");   // nested_discs' classic cost with N = 8
    CHECK(lines[9] == "ratio classic/voxel, nested_discs 12x12: " + lines[9].substr(41));

    // The plot's legend names each line by the model's stem and is not cut at the picture's edge.
    const std::string svg = t.read("b.svg");
    for (const char* name : {"nested_discs (classic)", "nested_discs (voxel)", "and (classic)", "and (voxel)"})
        CHECK(svg.find(std::string(">") + name + "</text>") != std::string::npos);
    const std::smatch width = [&] {
        std::smatch m;
        std::regex_search(svg, m, std::regex("<svg [^>]*width=\"([0-9.]+)\""));
        return m;
    }();
    REQUIRE(width.size() == 2);
    std::smatch legend;
    REQUIRE(std::regex_search(svg, legend, std::regex("<text class=\"legend\" x=\"([0-9.]+)\"")));
    CHECK(std::stod(legend[1]) + 7.5 * std::string("nested_discs (classic)").size() <= std::stod(width[1]));
}

TEST_CASE("bench durations: three significant digits in the unit that suits each value") {
    CHECK(fortu::duration_text(41.94e-9) == "41.9 ns");
    CHECK(fortu::duration_text(2.0770105e-3) == "2.08 ms");
    CHECK(fortu::duration_text(999.7e-9) == "1.00 µs");
    CHECK(fortu::duration_text(123.4e-6) == "123 µs");
    CHECK(fortu::duration_text(2.35) == "2.35 s");
    CHECK(fortu::duration_text(111) == "1 min 51 s");
    CHECK(fortu::duration_text(-1) == "?");
    CHECK(fortu::model_labels({"/a/x/s1.fortu", "/a/y/s1.fortu", "b/tor.vm"}) ==
          std::vector<std::string>{"/a/x/s1.fortu", "/a/y/s1.fortu", "tor"});
}

TEST_CASE("fortu bench on a terminal: the header at once, a progress line per cell that its row replaces") {
    TempDir t;
    const std::string m = t.write("and.fortu", kAnd);
    // script(1) gives fortu a pseudo-terminal; its output is what the terminal received.
    const auto r = fortu::test::run_shell("script -qec " +
                                          quote(quote(FORTU_BINARY) + " bench " + quote(m) + " --sizes 8 --repeat 1") +
                                          " /dev/null");
    REQUIRE(r.status == 0);
    const auto lines = lines_of(r.out);
    REQUIRE(lines.size() == 4);
    CHECK(lines[0].starts_with("model  engine   size  points  runs"));
    CHECK(lines[1].starts_with("timing classic 8x8 and...\r\x1b[Kand    classic  8x8       64     1  "));
    CHECK(lines[2].starts_with("timing voxel 8x8 and...\r\x1b[Kand    voxel    8x8       64     1  "));
    CHECK(lines[3].starts_with("ratio classic/voxel, and 8x8: "));
}
