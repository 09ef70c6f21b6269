// tests/unit/cli_unix_test.cpp — the Unix conventions of the command line: `-` for the script
// (standard input) and the output (standard output, with --format), several files for
// `check`, the INCLUDE search path (-I, FORTU_PATH) with the folders it searched in the
// note, and every command's own --help.
#include "cli_support.hpp"
#include "test_support.hpp"

#include <doctest/doctest.h>

#include <filesystem>

using fortu::test::quote;
using fortu::test::run_fortu;
using fortu::test::run_shell;

namespace {

const char* kDisc = "ARGUMENT X, Y;\nRETURN 0.25 - X*X - Y*Y;\n";

/// `fortu ARGS` in `cwd` with `input` on standard input; stdout and stderr as `redirect` says.
fortu::test::CommandResult fortu_with_input(const std::string& input_file, const std::string& args,
                                            const std::string& cwd, const std::string& redirect = " 2>&1") {
    return run_shell("cd " + quote(cwd) + " && " + quote(FORTU_BINARY) + " " + args + " < " + quote(input_file) +
                     redirect);
}

/// The build tree's stdlib, the last folder INCLUDE searches for a build-tree binary.
std::string build_stdlib() { return (std::filesystem::path(FORTU_BINARY).parent_path() / "stdlib").string(); }

}  // namespace

TEST_CASE("unix: `check -` and `run -` read the script from standard input, named <stdin>") {
    fortu::test::ScratchDir dir;
    const std::string disc = dir.write("disc.txt", kDisc);
    const auto check = fortu_with_input(disc, "check -", dir.path.string());
    CHECK(check.status == 0);
    CHECK(check.out == "<stdin>: ok (2 arguments, 7 nodes)\n");
    const std::string bad = dir.write("bad.txt", "ARGUMENT X, Y;\nRETURN X +;\n");
    const auto error = fortu_with_input(bad, "check -", dir.path.string());
    CHECK(error.status == 1);
    CHECK(error.out.rfind("<stdin>:2:", 0) == 0);
    const auto run = fortu_with_input(disc, "run - --size 4 -o v.npy", dir.path.string());
    CHECK(run.status == 0);
    CHECK(run.out == "wrote v.npy (4x4)\n");
    CHECK(std::filesystem::file_size(dir.path / "v.npy") == 128 + 16 * 8);
}

TEST_CASE("unix: standard input is bounded as script files are") {
    fortu::test::ScratchDir dir;
    const auto r = run_shell("head -c 5000000 /dev/zero | " + quote(FORTU_BINARY) + " check - 2>&1");
    CHECK(r.status == 1);
    CHECK(r.out == "fortu: error: cannot read '<stdin>': larger than 4 MiB, which no script needs\n");
}

TEST_CASE("unix: `-o -` and `-o /dev/stdout` write the output to standard output, byte for byte the file") {
    fortu::test::ScratchDir dir;
    dir.write("m.fortu", kDisc);
    const std::string cwd = dir.path.string();
    REQUIRE(run_fortu("run m.fortu --size 5 -o file.csv", cwd).status == 0);
    const auto csv = run_fortu("run m.fortu --size 5 -o - --format csv -q", cwd, /*with_stdout=*/true);
    CHECK(csv.status == 0);
    CHECK(csv.out == dir.read("file.csv"));
    REQUIRE(run_fortu("run m.fortu --size 5 -o file.png", cwd).status == 0);
    const auto png = run_shell("cd " + quote(cwd) + " && " + quote(FORTU_BINARY) +
                               " run m.fortu --size 5 -o /dev/stdout --format png > piped.png 2> err.txt");
    CHECK(png.status == 0);
    CHECK(dir.read("piped.png") == dir.read("file.png"));
    CHECK(dir.read("err.txt") == "wrote <stdout> (5x5)\n");
    // The report goes to standard error when standard output carries the file.
    const auto stats = run_shell("cd " + quote(cwd) + " && " + quote(FORTU_BINARY) +
                                 " run m.fortu --size 5 -o - --format npy --stats 2>/dev/null > piped.npy");
    CHECK(stats.status == 0);
    REQUIRE(run_fortu("run m.fortu --size 5 -o file.npy", cwd).status == 0);
    CHECK(dir.read("piped.npy") == dir.read("file.npy"));
    CHECK(dir.entries() == 7);   // m.fortu, file.{csv,png,npy}, piped.{png,npy}, err.txt: no temporaries
}

TEST_CASE("unix: `-o -` leaves no temporary, also when the reader stops early (SIGPIPE, as Unix filters)") {
    fortu::test::ScratchDir dir;
    dir.write("m.fortu", kDisc);
    std::filesystem::create_directories(dir.path / "tmp");
    const std::string env = "cd " + quote(dir.path.string()) + " && TMPDIR=tmp " + quote(FORTU_BINARY);
    const auto whole = run_shell(env + " run m.fortu --size 300 -o - --format csv -q | wc -l");
    CHECK(whole.out == "90001\n");
    const auto early = run_shell("bash -c " + quote(env + " run m.fortu --size 300 -o - --format csv 2>err.txt | "
                                                          "head -c 9; echo \" ${PIPESTATUS[0]}\""));
    CHECK(early.out == "x,y,value 141\n");   // 128 + SIGPIPE, and no error message
    CHECK(dir.read("err.txt") == "wrote <stdout> (300x300)\n");
    const auto failed = run_shell(env + " run m.fortu --size 4 -o - --format png --limit nodes=1 2>/dev/null | wc -c");
    CHECK(failed.out == "0\n");
    CHECK(std::filesystem::is_empty(dir.path / "tmp"));
}

TEST_CASE("unix: `-o -` needs --format, --format needs `-o -`, and binary is not sent to a terminal") {
    fortu::test::ScratchDir dir;
    dir.write("m.fortu", kDisc);
    const std::string cwd = dir.path.string();
    const auto missing = run_fortu("run m.fortu -o -", cwd);
    CHECK(missing.status == 2);
    CHECK(missing.out == "fortu: error: -o -: give the format with --format "
                         "(png|jpg|tif|bmp|exr|npy|csv|svg|stl|obj|ply|vti|nrrd|vdb|pvti|hdf)\n");
    const auto pieces = run_fortu("run m.fortu -o - --format pvti", cwd);
    CHECK(pieces.status == 2);
    CHECK(pieces.out == "fortu: error: -o -: a .pvti names piece files beside it; give it a path (-o f.pvti)\n");
    const auto unknown = run_fortu("run m.fortu -o - --format gif", cwd);
    CHECK(unknown.status == 2);
    CHECK(unknown.out == "fortu: error: --format: unknown output format 'gif' (use "
                         "png|jpg|tif|bmp|exr|npy|csv|svg|stl|obj|ply|vti|nrrd|vdb|pvti|hdf)\n");
    const auto stray = run_fortu("run m.fortu -o x.png --format png", cwd);
    CHECK(stray.status == 2);
    CHECK(stray.out == "fortu: error: --format applies to -o - (standard output); 'x.png' names its format by its "
                       "extension\n");
    const auto singular = run_fortu("singular m.fortu -o -", cwd);
    CHECK(singular.status == 2);
    CHECK(singular.out == "fortu: error: -o -: 'fortu singular' writes files only (standard output: fortu run)\n");
    // A terminal on standard output: script(1) gives the command a pseudo-terminal.
    const auto terminal = run_shell("cd " + quote(cwd) + " && script -qec " +
                                    quote(quote(FORTU_BINARY) + " run m.fortu -o - --format png") + " /dev/null");
    CHECK(terminal.status == 2);
    CHECK(terminal.out == "fortu: error: -o -: PNG is binary and standard output is a terminal; redirect it to a "
                          "file or a pipe (fortu run MODEL -o - --format png > out.png)\r\n");
    const std::string csv_run = quote(FORTU_BINARY) + " run m.fortu --size 2 -o - --format csv -q";
    const auto text = run_shell("cd " + quote(cwd) + " && script -qec " + quote(csv_run) + " /dev/null");
    CHECK(text.status == 0);
    CHECK(text.out == "x,y,value\r\n-1,1,-1.75\r\n1,1,-1.75\r\n-1,-1,-1.75\r\n1,-1,-1.75\r\n");
}

TEST_CASE("unix: `check` takes several files; the exit status is the worst") {
    fortu::test::ScratchDir dir;
    dir.write("a.fortu", kDisc);
    dir.write("b.fortu", "ARGUMENT X, Y;\nRETURN Q;\n");
    const auto r = run_fortu("check a.fortu b.fortu missing.fortu a.fortu", dir.path.string(), true);
    CHECK(r.status == 1);
    CHECK(r.out.find("a.fortu: ok (2 arguments, 7 nodes)\n") == 0);
    CHECK(r.out.find("b.fortu:2:8: error: unknown name 'Q'") != std::string::npos);
    CHECK(r.out.find("fortu: error: cannot read 'missing.fortu': No such file or directory\n") != std::string::npos);
    CHECK(r.out.rfind("a.fortu: ok (2 arguments, 7 nodes)\n") == r.out.size() - 35);
    CHECK(run_fortu("check a.fortu a.fortu", dir.path.string()).status == 0);
}

TEST_CASE("unix: INCLUDE searches the script's folder, -I folders, FORTU_PATH, then the stdlib, in that order") {
    fortu::test::ScratchDir dir;
    std::filesystem::create_directories(dir.path / "models");
    std::filesystem::create_directories(dir.path / "first");
    std::filesystem::create_directories(dir.path / "second");
    std::filesystem::create_directories(dir.path / "env");
    dir.write("models/m.fortu", "INCLUDE 'lib.fortu';\nARGUMENT X, Y;\nRETURN R;\n");
    dir.write("first/lib.fortu", "R = 1;\n");
    dir.write("second/lib.fortu", "R = 2;\n");
    dir.write("env/lib.fortu", "R = 3;\n");
    const std::string cwd = dir.path.string();
    auto value = [&](const std::string& prefix, const std::string& options) {
        const auto r = run_shell("cd " + quote(cwd) + " && " + prefix + quote(FORTU_BINARY) +
                                 " eval models/m.fortu 0 0 " + options + " 2>&1");
        return r.out.substr(0, r.out.find('\n'));
    };
    CHECK(value("", "-I second -I first") == "value: 2");
    CHECK(value("", "--include-dir first --include-dir=second") == "value: 1");
    CHECK(value("FORTU_PATH=env:first ", "-I second") == "value: 2");
    CHECK(value("FORTU_PATH=:env:first ", "") == "value: 3");
    dir.write("models/lib.fortu", "R = 4;\n");   // the script's own folder comes first
    CHECK(value("FORTU_PATH=env ", "-I first") == "value: 4");

    dir.write("models/n.fortu", "INCLUDE 'nowhere.fortu';\nARGUMENT X, Y;\nRETURN 1;\n");
    const auto missing = run_shell("cd " + quote(cwd) + " && FORTU_PATH=env::/p " + quote(FORTU_BINARY) +
                                   " check models/n.fortu -I first 2>&1");
    CHECK(missing.status == 1);
    CHECK(missing.out == "models/n.fortu:1:1: error: cannot find 'nowhere.fortu' to include\n"
                         "INCLUDE 'nowhere.fortu';\n"
                         "^~~~~~~~~~~~~~~~~~~~~~~\n"
                         "note: searched: models, first, env, /p, " + build_stdlib() + "\n");
    const auto empty = run_fortu("check models/m.fortu --include-dir=", cwd);
    CHECK(empty.status == 2);
    CHECK(empty.out == "fortu: error: 'fortu check': --include-dir needs a value\n");
}

TEST_CASE("unix: every command's --help lists its own options; -V and --size=N work") {
    const auto run = run_fortu("run --help", ".", true);
    CHECK(run.status == 0);
    CHECK(run.out.rfind("usage: fortu run MODEL.fortu [options]\n", 0) == 0);
    for (const char* option : {"--contour FILE.svg", ".svg", "--format EXT", "-q --quiet", "-I --include-dir DIR",
                               "--slice", "--stats"})
        CHECK_MESSAGE(run.out.find(option) != std::string::npos, option);
    const auto check = run_fortu("check --help", ".", true);
    CHECK(check.out.rfind("usage: fortu check MODEL.fortu... [options]\n", 0) == 0);
    CHECK(check.out.find("-I --include-dir DIR") != std::string::npos);
    CHECK(check.out.find("--size") == std::string::npos);
    for (const char* command : {"eval", "ir", "singular", "golden", "bench", "repl"}) {
        const auto help = run_fortu(std::string(command) + " --help", ".", true);
        CHECK(help.status == 0);
        CHECK_MESSAGE(help.out.find(std::string("fortu ") + command) != std::string::npos, command);
        CHECK_MESSAGE(help.out.find("run's options") == std::string::npos, command);
    }
    CHECK(run_fortu("-V", ".", true).out == "fortu 0.1.0\n");
    CHECK(run_fortu("--version", ".", true).out == "fortu 0.1.0\n");
}
