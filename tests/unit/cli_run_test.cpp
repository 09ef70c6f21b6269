// tests/unit/cli_run_test.cpp — the command line end to end: usage errors (exit 2) before
// any work, outputs written in each format, the classic budget, eval and ir output.
#include "cli_support.hpp"
#include "interp_test_support.hpp"
#include "test_support.hpp"

#include "interp/limits.hpp"
#include "interp/tape_jit.hpp"
#include "runtime/image_table.hpp"
#include "runtime/output_formats.hpp"
#include "runtime/picture.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

using fortu::test::run_fortu;
using fortu::test::quote;
using namespace fortu;

namespace {

using TempDir = fortu::test::ScratchDir;


const char* kDisc = "ARGUMENT X, Y;\nRETURN 0.25 - X*X - Y*Y;\n";

}  // namespace

TEST_CASE("usage errors exit 2 with a clear message") {
    TempDir t;
    const std::string m = quote(t.write("disc.fortu", kDisc));
    CHECK(run_fortu("").status == 2);
    CHECK(run_fortu("").out == "fortu: error: no command given (try 'fortu --help')\n");
    CHECK(run_fortu("frobnicate x").out == "fortu: error: unknown command 'frobnicate' (try 'fortu --help')\n");
    CHECK(run_fortu("run " + m + " --size 0").out ==
          "fortu: error: --size: '0' is not a size (use N, WxH or WxHxD with whole numbers from 1 to 1000000)\n");
    CHECK(run_fortu("run " + m + " --size 100000x100000").out ==
          "fortu: error: --size: 100000x100000 is 10,000,000,000 points, more than the 268,435,456 fortu allocates\n");
    CHECK(run_fortu("run " + m + " --domain nan:1").out == "fortu: error: --domain: 'nan' is not a finite number\n");
    CHECK(run_fortu("run " + m + " --domain 1:0").out == "fortu: error: --domain: range '1:0' needs MIN < MAX\n");
    CHECK(run_fortu("run " + m + " --engine turbo").out == "fortu: error: --engine: unknown engine 'turbo' (use classic, voxel, voxel-f32, sign or fv)\n");
    CHECK(run_fortu("run " + m + " --rsystem alpha=3").status == 2);
    CHECK(run_fortu("run " + m + " -o out.xyz").status == 2);
    CHECK(run_fortu("run " + m + " --bogus").out == "fortu: error: unknown option '--bogus'\nsee fortu run --help\n");
    CHECK(run_fortu("eval " + m + " 0 0 --stats").out == "fortu: error: unknown option '--stats'\nsee fortu eval --help\n");
    CHECK(run_fortu("run " + m + " --size").out == "fortu: error: 'fortu run': --size needs a value\n");
    CHECK(run_fortu("run").out == "fortu: error: 'fortu run' needs a MODEL file\n");
    CHECK(run_fortu("eval " + m + " 1").out == "fortu: error: 'fortu eval' needs MODEL X Y [Z]\n");
    CHECK(run_fortu("eval " + m + " 1 abc").out == "fortu: error: 'fortu eval': 'abc' is not a finite coordinate\n");
    CHECK(run_fortu("--help", ".", true).status == 0);
}

TEST_CASE("--help and golden --help list the output formats of the table") {
    const std::string help = run_fortu("--help", ".", true).out;
    CHECK(help.find("  -o --output FILE            " + output_formats_usage(30) + "\n") != std::string::npos);
    std::string kinds;
    for (const std::string& kind : golden_output_kinds()) kinds += (kinds.empty() ? "" : " ") + kind;
    const std::string golden_help = run_fortu("golden --help", ".", true).out;
    CHECK(golden_help.find("references --update creates; KIND: " + kinds + "\n") != std::string::npos);
    for (const OutputFormat& format : output_formats()) {
        CAPTURE(format.name);
        CHECK(help.find(" ." + std::string(format.extension())) != std::string::npos);
    }
}

TEST_CASE("--stats counts the hoisted operations only for an engine that hoists") {
    TempDir t;
    const std::string m = quote(t.write("disc.fortu", kDisc));
    const std::string hoisted = " (3 of them once per grid column or row on a grid of 64+ columns)\n";
    CHECK(run_fortu("run " + m + " --size 9 --stats", ".", true).out.find("voxel: 4" + hoisted) != std::string::npos);
    CHECK(run_fortu("run " + m + " --size 9 --stats --precision float32", ".", true).out.find("voxel: 4" + hoisted) !=
          std::string::npos);
    for (const char* other : {" --no-hoist", " --engine classic", " --sign-only"}) {
        CAPTURE(other);
        const std::string out = run_fortu("run " + m + " --size 9 --stats" + other, ".", true).out;
        CHECK(out.find("voxel: 4\n") != std::string::npos);
    }
}

TEST_CASE("--stats of a shaded view counts its leaves and those on compiled tapes; --no-jit runs none so") {
    TempDir t;
    // A gyroid-like shell through sin and cos: many leaves along its surface, on few tapes.
    const std::string m = quote(t.write("shell.fortu", "ARGUMENT X, Y, Z;\n"
                                                       "RETURN 0.3 - ABS(SIN(4*X)*COS(4*Y) + SIN(4*Y)*COS(4*Z) + SIN(4*Z)*COS(4*X));\n"));
    auto counts = [&](const std::string& extra) {
        const std::string out =
            run_fortu("run " + m + " --size 96 --view front --threads 1 -o " + quote((t.path / "v.png").string()) + " --stats" + extra,
                      ".", true)
                .out;
        const std::size_t at = out.find("\nleaves: ");
        REQUIRE(at != std::string::npos);
        CHECK(out.find("\ntime: render ", at) != std::string::npos);
        std::string line = out.substr(at + 1, out.find('\n', at + 1) - at - 1);
        std::erase(line, ',');   // thousands separators: "leaves: 1,234 1,100 of them ..."
        long leaves = 0, compiled = 0;
        REQUIRE(std::sscanf(line.c_str(), "leaves: %ld %ld of them on compiled tapes", &leaves, &compiled) == 2);
        return std::pair{leaves, compiled};
    };
    const auto [leaves, compiled] = counts("");
    CHECK(leaves > 100);
    if (tape_jit_available()) CHECK(compiled * 2 > leaves);
    CHECK(counts(" --no-jit") == std::pair{leaves, 0L});
}

TEST_CASE("the option table: --opt=value, each command's --help, --version") {
    TempDir t;
    const std::string m = quote(t.write("disc.fortu", kDisc));
    const auto spaced = run_fortu("run " + m + " --size 9 --engine classic", ".", true);
    const auto joined = run_fortu("run " + m + " --size=9 --engine=classic", ".", true);
    CHECK(spaced.status == 0);
    CHECK(joined.out.substr(0, joined.out.find(" in ")) == spaced.out.substr(0, spaced.out.find(" in ")));
    CHECK(joined.out.find(" 9x9 with classic in ") != std::string::npos);
    CHECK(spaced.out.find(" 9x9 with classic in ") != std::string::npos);
    // Negative numbers are values, not options.
    CHECK(run_fortu("run " + m + " --domain -2:2,-1:1 --size 3", ".", true).status == 0);
    const auto run_help = run_fortu("run --help", ".", true);
    CHECK(run_help.status == 0);
    CHECK(run_help.out.starts_with("usage: fortu run MODEL.fortu [options]\n"));
    CHECK(run_help.out.find("\n  --engine NAME               the engine (default voxel):\n"
                            "                                classic     ") != std::string::npos);
    CHECK(run_help.out.find("\n  --stats ") != std::string::npos);
    const auto check_help = run_fortu("check --help", ".", true);
    CHECK(check_help.out.starts_with("usage: fortu check MODEL.fortu... [options]\n"));
    CHECK(check_help.out.find("--rsystem") != std::string::npos);
    CHECK(check_help.out.find("--engine") == std::string::npos);
    // fortu --help's command list and each command's usage come from the same row.
    const std::string help = run_fortu("--help", ".", true).out;
    CHECK(help.find("\n  fortu eval MODEL.fortu X Y [Z] [options]  value, gradient and M-image normal at a point\n") !=
          std::string::npos);
    CHECK(run_fortu("eval --help", ".", true).out.starts_with(
        "usage: fortu eval MODEL.fortu X Y [Z] [options]\n  value, gradient and M-image normal at a point\n"));
    CHECK(help.find("\n  fortu singular MODEL.fortu [options]      singular (corner) points: K = 0 and R = 0\n"
                    "                                            (search grid: --size, default 401x401 / 48^3)\n") !=
          std::string::npos);
    CHECK(run_fortu("--version", ".", true).out == "fortu 0.1.0\n");
    CHECK(run_fortu("-V", ".", true).out == "fortu 0.1.0\n");
    CHECK(run_fortu("repl --help", ".", true).out.starts_with("usage: fortu repl [MODEL.fortu]\n"));
    CHECK(run_fortu("golden --help", ".", true).out.find("\n  -j --jobs N ") != std::string::npos);
}

TEST_CASE("an unreadable model is a clear error, exit 1") {
    TempDir t;
    auto r = run_fortu("check " + quote((t.path / "missing.fortu").string()));
    CHECK(r.status == 1);
    CHECK(r.out.find("fortu: error: cannot read '") == 0);
    r = run_fortu("check " + quote(t.path.string()));
    CHECK(r.status == 1);
}

TEST_CASE("eval prints value, exact gradient and the M-image normal") {
    TempDir t;
    const std::string m = quote(t.write("disc.fortu", kDisc));
    for (const char* engine : {"voxel", "classic"}) {
        auto r = run_fortu("eval " + m + " 0.1 0.2 --engine " + engine, ".", true);
        CHECK(r.status == 0);
        CHECK(r.out.find("value: 0.19999999999999998\n") == 0);
        CHECK(r.out.find("gradient: -0.2 -0.4\n") != std::string::npos);
        CHECK(r.out.find("inside: yes\n") != std::string::npos);
    }
}

TEST_CASE("eval says where the gradient is undefined and labels the normal's components") {
    TempDir t;
    const std::string m = quote(t.write("cone.fortu", "ARGUMENT X, Y;\nRETURN 1 - SQRT(X*X + Y*Y);\n"));
    for (const char* engine : {"voxel", "classic"}) {
        CAPTURE(engine);
        auto r = run_fortu("eval " + m + " 0 0 --size 3 --engine " + engine, ".", true);
        CHECK(r.status == 0);
        CHECK(r.out == "value: 1\n"
                       "gradient: undefined (SQRT of 0)\n"
                       "normal: n1=0.5 n2=0.5 n3=0.5 n4=-0.5\n"
                       "inside: yes\n");
    }
}

namespace {

/// The disc evaluated in this process as `fortu run --size 17` evaluates it.
Field disc_field() {
    fortu::test::Compiled c = fortu::test::compile_text(kDisc);
    REQUIRE_MESSAGE(c.model, c.sink.render_all());
    return evaluate_grid(*c.model, model_grid(*c.model, {17, 17, 1}), engine_named("voxel"));
}

/// Checks the content of `path`, written by `format`'s writer from `field`: with the
/// format's golden comparator against the reference in tests/unit/data/outputs/, or, for a
/// picture format without one, its grey levels read back against the colours render_slice
/// gives (lossy formats on average). Returns what is wrong, "" if nothing.
std::string check_output_content(const OutputFormat& format, const std::string& path, const Field& field) {
    if (format.compare) {
        const std::string reference =
            std::string(FORTU_SOURCE_DIR) + "/tests/unit/data/outputs/disc17." + std::string(format.extension());
        if (!std::filesystem::exists(reference))
            return "no reference " + reference + " (write it with `fortu run` of the disc --size 17 and review it)";
        // Both ways round: a comparator may judge the reference by the field's values alone
        // (.npy), so the written file must also stand as the reference once.
        const std::string forward = format.compare(ComparedOutput{format, reference, path, field, 1e-12, 0}).difference;
        if (!forward.empty()) return forward;
        return format.compare(ComparedOutput{format, path, reference, field, 1e-12, 0}).difference;
    }
    // Volumes without a comparator are read back with their own library in cli_volume_test.cpp.
    if (format.kind == OutputKind::Volume) return std::filesystem::file_size(path) > 0 ? "" : "empty file";
    if (format.kind != OutputKind::Picture) return "no comparator and no other way to check the content";
    std::string error;
    const std::optional<ImageTable> table = read_image_table(path, error, std::size_t{1} << 20);
    if (!table) return error;
    if (table->width != field.grid.cols() || table->height != field.grid.rows()) return "wrong picture size";
    const std::vector<Rgb8> colours = render_slice(field, 0, colour_scale(field.values), OutputOptions{});
    double worst = 0, total = 0;
    for (std::size_t i = 0; i < colours.size(); ++i) {
        const double grey = (colours[i].r + colours[i].g + colours[i].b) / (3 * 255.0);
        worst = std::max(worst, std::fabs(grey - table->values[i]));
        total += std::fabs(grey - table->values[i]);
    }
    if (format.lossy ? total / colours.size() > 0.02 : worst > 1e-6)
        return "the grey levels differ from the rendered colours: worst " + std::to_string(worst) + ", mean " +
               std::to_string(total / colours.size());
    return "";
}

}  // namespace

TEST_CASE("run writes every output format, atomically, and reports invalid points") {
    TempDir t;
    const std::string m = quote(t.write("disc.fortu", kDisc));
    const Field field = disc_field();
    int written = 0;
    for (const OutputFormat& format : output_formats()) {
        if (format.kind == OutputKind::Mesh) continue;  // 3D models only: cli_mesh_test.cpp
        ++written;
        const std::string name = "out." + std::string(format.extension());
        CAPTURE(name);
        auto r = run_fortu("run " + m + " --size 17 -o " + quote((t.path / name).string()));
        CHECK(r.status == 0);
        CHECK(check_output_content(format, (t.path / name).string(), field) == "");
    }
    auto r = run_fortu("run " + m + " --size 17 --mimages " + quote((t.path / "m_%d.png").string()));
    CHECK(r.status == 0);
    for (int k = 1; k <= 4; ++k) CHECK(std::filesystem::exists(t.path / ("m_" + std::to_string(k) + ".png")));
    // only the outputs asked for (and the .pvti's one piece): no temporaries left behind
    int files = 0;
    for (const auto& e : std::filesystem::directory_iterator(t.path)) files += e.is_regular_file();
    CHECK(std::filesystem::exists(t.path / "out_0.vti"));
    CHECK(files == 1 + written + 1 + 4);

    const std::string inv = quote(t.write("inv.fortu", "ARGUMENT X, Y;\nRETURN 1/X;\n"));
    r = run_fortu("run " + inv + " --size 3 -o " + quote((t.path / "inv.png").string()));
    CHECK(r.status == 0);
    CHECK(r.out == "fortu: note: 3 invalid points (non-finite values)\nwrote " + (t.path / "inv.png").string() +
                   " (3x3)\n");

    r = run_fortu("run " + m + " --size 5 -o " + quote((t.path / "no_such_dir" / "x.png").string()));
    CHECK(r.status == 1);
    CHECK(r.out.find("fortu: error: cannot write '") == 0);
}

TEST_CASE("the classic engine refuses runs over its budget, with the estimate and a hint") {
    TempDir t;
    std::string text = "ARGUMENT X, Y;\nVARIABLE W = X & Y;\n";
    for (int i = 0; i < 30; ++i) text += "W = W & X;\n";
    const std::string m = quote(t.write("deep.fortu", text + "RETURN W;\n"));
    auto r = run_fortu("run " + m + " --engine classic --size 100");
    CHECK(r.status == 2);
    CHECK(r.out ==
          "fortu: error: the classic engine would need 19,327,352,824 operations per point x 10,000 points = "
          "1.93e+14 operations (budget 1e+10)\n"
          "note: use --engine voxel (31 operations per point), a smaller --size, a larger --budget, or --force\n");
    CHECK(run_fortu("run " + m + " --engine voxel --size 100").status == 0);
    auto ir = run_fortu("ir " + m, ".", true);
    CHECK(ir.out.find("; classic: 19,327,352,824 operations per point\n") != std::string::npos);
    CHECK(ir.out.find("; voxel: 31 operations per point\n") != std::string::npos);
}

TEST_CASE("3D models write a chosen slice or a stack of slices") {
    TempDir t;
    const std::string m = quote(t.write("ball.fortu", "ARGUMENT X, Y, Z;\nRETURN 0.5 - X*X - Y*Y - Z*Z;\n"));
    CHECK(run_fortu("run " + m + " --size 9 --slice 4 -o " + quote((t.path / "s.png").string())).status == 0);
    CHECK(run_fortu("run " + m + " --size 9 -o " + quote((t.path / "s_%02d.png").string())).status == 0);
    for (int k = 0; k < 9; ++k) {
        char name[16];
        std::snprintf(name, sizeof name, "s_%02d.png", k);
        CHECK(std::filesystem::exists(t.path / name));
    }
    CHECK(run_fortu("run " + m + " --size 9 --slice 9 -o " + quote((t.path / "bad.png").string())).status == 2);
}

TEST_CASE("--limit: changes a compile-time budget; the README's table is the generated one") {
    TempDir t;
    const std::string m = quote(t.write("loop.fortu", "ARGUMENT X, Y;\nCONSTANT S = 0;\nFOR I = 1, 100\n"
                                                      "CONSTANT S = S + 1;\nEND FOR\nRETURN X + Y - S;\n"));
    CHECK(run_fortu("check " + m).status == 0);
    const auto low = run_fortu("check " + m + " --limit work=50");
    CHECK(low.status == 1);
    CHECK(low.out.find("note: the limit 'work' is 50; raise it with --limit work=N\n") != std::string::npos);
    CHECK(run_fortu("check " + m + " --limit work=50 --limit work=1000").status == 0);
    CHECK(run_fortu("check " + m + " --limit speed=1").out ==
          "fortu: error: --limit: unknown limit 'speed' (names: work, nodes, array, loop, nesting, include-depth, "
          "image-pixels)\n");
    const std::string readme = fortu::test::read_file(std::string(FORTU_SOURCE_DIR) + "/README.md");
    CHECK(readme.find("```\n" + limits_usage(0) + "\n```\n") != std::string::npos);
}
