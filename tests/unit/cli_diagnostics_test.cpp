// tests/unit/cli_diagnostics_test.cpp — malformed scripts: the exact diagnostic text
// (with source line and caret) and the exit status of `fortu check`, one golden file per
// script in tests/golden/errors/ (NAME.fortu → NAME.expected: `exit N`, then stderr).
// FORTU_UPDATE_GOLDEN=1 rewrites the expected files (review the diff before committing).
#include "cli_support.hpp"
#include "test_support.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <vector>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

using fortu::test::run_fortu;
using fortu::test::quote;
using fortu::test::read_file;

TEST_CASE("malformed scripts give exact diagnostics and exit status 1, never a crash") {
    const std::filesystem::path dir = std::filesystem::path(FORTU_SOURCE_DIR) / "tests" / "golden" / "errors";
    std::vector<std::filesystem::path> scripts;
    for (const auto& e : std::filesystem::directory_iterator(dir))
        if (e.path().extension() == ".fortu") scripts.push_back(e.path());
    std::sort(scripts.begin(), scripts.end());
    REQUIRE(scripts.size() >= 20);
    const bool update = std::getenv("FORTU_UPDATE_GOLDEN") != nullptr;
    int failing_scripts = 0;
    for (const auto& script : scripts) {
        CAPTURE(script.filename().string());
        const auto r = run_fortu("check " + quote(script.filename().string()), dir.string());
        const std::string actual = "exit " + std::to_string(r.status) + "\n" + r.out;
        std::filesystem::path expected_path = script;
        expected_path.replace_extension(".expected");
        if (update) {
            std::ofstream(expected_path, std::ios::binary) << actual;
            continue;
        }
        REQUIRE_MESSAGE(std::filesystem::exists(expected_path), "missing ", expected_path.string());
        CHECK(actual == read_file(expected_path));
        CHECK(r.status < 128);  // not killed by a signal
        failing_scripts += r.status == 1;
    }
    if (!update) CHECK(failing_scripts >= 20);
}
