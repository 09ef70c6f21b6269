// tests/unit/cli_kill_test.cpp — a `fortu run` killed at any moment (SIGKILL, or SIGTERM,
// SIGINT, SIGHUP) never leaves a partial file at the output path: the path holds the old
// complete file or the new one. SIGTERM/SIGINT/SIGHUP leave no temporary; SIGKILL may leave
// one, named with the dead pid, which the next run into the folder removes.
#include "cli_support.hpp"
#include "test_support.hpp"

#include "runtime/temp_files.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <csignal>
#include <filesystem>
#include <random>
#include <thread>

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

extern char** environ;

using fortu::test::run_fortu;
using namespace fortu;

namespace {

/// Starts `fortu run m.fortu ARGS...` in `dir`, stdout and stderr to /dev/null.
pid_t start_fortu(const std::string& dir, const std::vector<std::string>& args) {
    std::vector<std::string> argv_text{FORTU_BINARY, "run", dir + "/m.fortu"};
    argv_text.insert(argv_text.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (std::string& a : argv_text) argv.push_back(a.data());
    argv.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_addopen(&actions, 2, "/dev/null", O_WRONLY, 0);
    pid_t pid = -1;
    const int error = posix_spawn(&pid, FORTU_BINARY, &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    return error == 0 ? pid : -1;
}

/// The temporaries in `dir` (of process `owner` only when given).
std::vector<std::string> temporaries_in(const std::string& dir, pid_t owner = 0) {
    std::vector<std::string> out;
    for (const auto& e : std::filesystem::directory_iterator(dir)) {
        const auto pid = temporary_file_owner(e.path().filename().string());
        if (pid && (owner == 0 || *pid == owner)) out.push_back(e.path().filename().string());
    }
    return out;
}

}  // namespace

TEST_CASE("killed at random moments 100 times: never a partial output, no stray temporary") {
    test::ScratchDir dir;
    dir.write("m.fortu", "ARGUMENT X, Y;\nRETURN 0.25 - X*X - Y*Y + 0.1*SIN(20*X)*COS(20*Y);\n");
    const std::string folder = dir.path.string();
    // The complete files, to compare what a killed run leaves with. How long a run takes sets
    // the range of kill moments (to 1.3 runs), so on a fast machine as on a slow one most runs
    // are killed, some while writing, and some finish.
    const auto started = std::chrono::steady_clock::now();
    REQUIRE(run_fortu("run m.fortu --size 300 -o out.npy", folder).status == 0);
    const std::string full_npy = dir.read("out.npy");
    REQUIRE(run_fortu("run m.fortu --size 300 -o out.png", folder).status == 0);
    const std::string full_png = dir.read("out.png");
    const auto one_run = std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::steady_clock::now() - started) / 2;
    const int latest_kill = static_cast<int>(std::max<std::int64_t>(1'000, one_run.count() * 13 / 10));
    std::filesystem::remove(dir / "out.npy");
    std::filesystem::remove(dir / "out.png");

    std::mt19937 random(14);
    const int signals[] = {SIGKILL, SIGTERM, SIGKILL, SIGINT, SIGKILL, SIGHUP};
    int killed = 0, finished = 0;
    for (int round = 0; round < 100; ++round) {
        CAPTURE(round);
        const bool png = round % 2 == 1;
        const std::string out = png ? "out.png" : "out.npy";
        const pid_t pid = start_fortu(folder, {"--size", "300", "--threads", "1", "-o", folder + "/" + out});
        REQUIRE(pid > 0);
        std::this_thread::sleep_for(std::chrono::microseconds(std::uniform_int_distribution<int>(0, latest_kill)(random)));
        const int signal = signals[round % std::size(signals)];
        ::kill(pid, signal);
        int status = 0;
        REQUIRE(::waitpid(pid, &status, 0) == pid);
        if (WIFSIGNALED(status)) {
            ++killed;
            CHECK(WTERMSIG(status) == signal);
        } else {
            ++finished;
            CHECK(WEXITSTATUS(status) == 0);
        }
        // Absent, or complete: never a partial file.
        if (std::filesystem::exists(dir / out)) CHECK(dir.read(out) == (png ? full_png : full_npy));
        // (A SIGKILL'ed run before this one may have left its own, until a run writes here.)
        if (signal != SIGKILL) CHECK(temporaries_in(folder, pid).empty());
    }
    MESSAGE(killed << " runs killed, " << finished << " finished first");
    CHECK(killed > 30);
    // What SIGKILL left is named with a dead pid: the next run removes it.
    REQUIRE(run_fortu("run m.fortu --size 8 -o other.csv", folder).status == 0);
    for (const auto& e : std::filesystem::directory_iterator(folder)) {
        const std::string name = e.path().filename().string();
        CHECK_MESSAGE((name == "m.fortu" || name == "out.npy" || name == "out.png" || name == "other.csv"), name);
    }
}
