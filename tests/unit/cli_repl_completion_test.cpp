// tests/unit/cli_repl_completion_test.cpp — what Tab completes in `fortu repl`: commands,
// their arguments, file names after :load/:save/:render, and in FORTU text the session's
// names, keywords, built-ins and the stdlib's FUNCTIONs. (The key itself: tests/repl/, tmux.)
#include "cli/repl/repl_completion.hpp"

#include <doctest/doctest.h>

#include <string>
#include <vector>

using fortu::complete_repl_word;
using Words = std::vector<std::string>;

namespace {

const Words kStdlib = fortu::stdlib_function_names({std::string(FORTU_SOURCE_DIR) + "/stdlib"});

/// Completes the last word of `line` (words end at blanks and operators).
fortu::Completion complete(const std::string& line, const Words& names = {}) {
    const std::size_t start = line.find_last_of(" \t(,=+*^&|!<>;") == std::string::npos
                                  ? 0 : line.find_last_of(" \t(,=+*^&|!<>;") + 1;
    return complete_repl_word(line, start, names, kStdlib);
}

}  // namespace

TEST_CASE("Tab completes the REPL's commands and their arguments") {
    CHECK(complete(":re").words == Words{":render", ":reset"});
    CHECK(complete(":").words == fortu::repl_command_names());
    CHECK(complete(":q").words == Words{":quit"});
    CHECK(complete(":engine ").words == Words{"classic", "voxel"});
    CHECK(complete(":engine v").words == Words{"voxel"});
    CHECK(complete(":rsystem m").words == Words{"minmax"});
    CHECK(complete(":show --").words == Words{"--slice", "--view", "--up"});
    CHECK(complete(":render a.png --v").words == Words{"--view"});
    CHECK(complete(":render a.png --view ").words == Words{"top", "front", "side", "iso"});
    CHECK(complete(":show --up ").words == Words{"x", "y", "z"});
    CHECK(complete(":time ").words.empty());
    CHECK_FALSE(complete(":time ").files);
    for (const char* files : {":load ex", ":save ", ":render pic"}) {
        CAPTURE(files);
        CHECK(complete(files).files);
        CHECK(complete(files).words.empty());
    }
    CHECK_FALSE(complete(":render a.png --view ").files);
}

TEST_CASE("Tab completes FORTU names: the session's, keywords, built-ins and the stdlib's functions") {
    CHECK(kStdlib.size() >= 10);
    CHECK(complete("RETURN SQ").words == Words{"SQRT"});
    CHECK(complete("return sq").words == Words{"SQRT"});   // FORTU ignores case
    CHECK(complete("VAR").words == Words{"VARIABLE"});
    CHECK(complete("RETURN DI", {"X", "Y", "DISC", "DIAMOND"}).words == Words{"DISC", "DIAMOND"});
    CHECK(complete("RETURN 1 - FLOZ_P", {}).words == Words{"FLOZ_POLYGON", "FLOZ_POLYLINE"});
    CHECK(complete("RETURN 1 - FLOZ3").words == Words{"FLOZ3", "FLOZ3_MESH"});
    CHECK(complete("W = MAX(A, TRIANGLE_").words == Words{"TRIANGLE_AREA"});
    CHECK(complete("RETURN QQQ").words.empty());
    CHECK_FALSE(complete("RETURN SQ").files);
}
