// tests/unit/cli_sweep_test.cpp — `--set` sweeps: the values an axis reads, the file names
// they make, and how run_sweep shares the runs out on one process (the first alone, the
// rest side by side on the threads, each run exactly once, errors carried back).
#include "cli/sweep.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <iostream>
#include <sstream>
#include <mutex>
#include <thread>

using namespace fortu;

namespace {

std::string usage_error_of(const std::string& text) {
    try {
        parse_sweep(text);
    } catch (const UsageError& e) {
        return e.what();
    }
    return "";
}

/// What run_sweep asked of run_one: the R of every run in call order, the threads each got,
/// and how many ran at once at most.
struct Recorder {
    std::mutex mutex;
    std::vector<double> values;
    std::vector<int> threads;
    std::atomic<int> running{0}, most_at_once{0};
    bool overlapped_first = false;

    int operator()(const CliOptions& point, int status = 0) {
        const int now = ++running;
        for (int m = most_at_once.load(); now > m && !most_at_once.compare_exchange_weak(m, now);) {}
        {
            const std::lock_guard lock(mutex);
            values.push_back(point.constants.at(0).second);
            threads.push_back(point.threads);
        }
        // Long enough for the other threads to start theirs if they were allowed to.
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
        if (point.constants.at(0).second == 0.0 && running.load() > 1) overlapped_first = true;
        --running;
        return status;
    }
};

CliOptions sweep_of(const std::string& set, int threads) {
    CliOptions o;
    o.sets = {set};
    o.threads = threads;
    o.output = "out_%R.npy";
    return o;
}

}  // namespace

TEST_CASE("sweep: an axis's values are the script's numbers, the last included within rounding") {
    CHECK(parse_sweep("R=0.1:0.5:0.1").values == std::vector<double>{0.1, 0.2, 0.3, 0.4, 0.5});
    CHECK(parse_sweep("N=3").values == std::vector<double>{3});
    CHECK(parse_sweep("A=1:0:-0.25").values == std::vector<double>{1, 0.75, 0.5, 0.25, 0});
    CHECK(usage_error_of("R") == "--set: 'R' is not NAME=VALUE or NAME=FIRST:LAST:STEP");
    CHECK(usage_error_of("R=1:2") == "--set: 'R=1:2' is not NAME=VALUE or NAME=FIRST:LAST:STEP");
    CHECK(usage_error_of("R=0:1:-1") == "--set: the step of 'R=0:1:-1' does not go from 0 to 1");
    CHECK(usage_error_of("R=0:1:1e-9") == "--set: 'R=0:1:1e-9' has 1000000001 values, more than 100000");
    CHECK(sweep_path("out_%R_%RR.png", {{"R", 0.3}, {"RR", 2}}) == "out_0.3_2.png");
}

TEST_CASE("sweep: on one process the first run goes alone on every thread, the rest side by side, each once") {
    Recorder runs;
    const int status = run_sweep(sweep_of("R=0:1.1:0.1", 4), [&](const CliOptions& p) {
        return runs(p, p.constants[0].second == 0.5 ? 3 : 0);
    });
    CHECK(status == 3);   // the worst run's status
    REQUIRE(runs.values.size() == 12);
    CHECK(runs.values.front() == 0.0);
    CHECK(runs.threads.front() == 4);
    CHECK_FALSE(runs.overlapped_first);
    CHECK(std::all_of(runs.threads.begin() + 1, runs.threads.end(), [](int t) { return t == 1; }));
    CHECK(runs.most_at_once.load() == 4);
    std::vector<double> sorted = runs.values;
    std::sort(sorted.begin(), sorted.end());
    CHECK(std::adjacent_find(sorted.begin(), sorted.end()) == sorted.end());
}

TEST_CASE("sweep: one thread, or bricked runs (--memory, M-images to .hdf), one after another in order") {
    for (const std::string why : {"one thread", "--memory", "--mimages .hdf"}) {
        CAPTURE(why);
        Recorder runs;
        CliOptions o = sweep_of("R=0:0.3:0.1", why == "one thread" ? 1 : 0);
        if (why == "--memory") o.memory = std::size_t(1) << 30;
        if (why == "--mimages .hdf") o.mimages = "m_%R.hdf";
        CHECK(run_sweep(o, [&](const CliOptions& p) { return runs(p, p.constants[0].second == 0.2 ? 1 : 0); }) == 1);
        CHECK(runs.values == std::vector<double>{0, 0.1, 0.2, 0.3});   // a later failure does not stop it
        CHECK(runs.most_at_once.load() == 1);
        CHECK(runs.threads == std::vector<int>(4, o.threads));
    }
}

TEST_CASE("sweep: a failed first run ends the sweep, with a note") {
    Recorder runs;
    std::ostringstream err;
    std::streambuf* saved = std::cerr.rdbuf(err.rdbuf());
    const int status = run_sweep(sweep_of("R=0:0.3:0.1", 2), [&](const CliOptions& p) { return runs(p, 1); });
    std::cerr.rdbuf(saved);
    CHECK(status == 1);
    CHECK(runs.values == std::vector<double>{0});
    CHECK(err.str() == "fortu: note: the sweep stops: its first run failed (3 more not started)\n");
}

TEST_CASE("sweep: a run's usage error ends the sweep, is carried to the caller, and no run starts twice") {
    Recorder runs;
    std::string message;
    try {
        run_sweep(sweep_of("R=0:2:0.1", 2), [&](const CliOptions& p) {
            runs(p);
            if (p.constants[0].second == 0.3) throw UsageError("--slice: z=9 is outside z [-1, 1]");
            return 0;
        });
    } catch (const UsageError& e) {
        message = e.what();
    }
    CHECK(message == "--slice: z=9 is outside z [-1, 1]");
    std::vector<double> sorted = runs.values;
    std::sort(sorted.begin(), sorted.end());
    CHECK(std::adjacent_find(sorted.begin(), sorted.end()) == sorted.end());
    CHECK(runs.values.size() < 21);   // the sweep stopped handing out runs
}
