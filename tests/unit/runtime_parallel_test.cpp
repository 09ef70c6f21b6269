// tests/unit/runtime_parallel_test.cpp — parallel_for hands out every item once and rethrows
// an item's exception; its threads (SpreadThread) run their work and end up free to run on
// every core the process may, however they were started.
#include "runtime/parallel.hpp"
#include "runtime/spread_thread.hpp"

#include <doctest/doctest.h>

#include <sched.h>

#include <atomic>
#include <chrono>
#include <stdexcept>
#include <thread>
#include <vector>

using namespace fortu;

namespace {

cpu_set_t own_affinity() {
    cpu_set_t set;
    CPU_ZERO(&set);
    REQUIRE(sched_getaffinity(0, sizeof set, &set) == 0);
    return set;
}

}  // namespace

TEST_CASE("parallel_for calls every item exactly once, from workers numbered below the thread count") {
    for (const int threads : {1, 2, 4}) {
        CAPTURE(threads);
        std::vector<std::atomic<int>> calls(1000);
        std::atomic<bool> worker_in_range{true};
        parallel_for(calls.size(), threads, nullptr, [&](std::size_t i, int worker) {
            if (worker < 0 || worker >= threads) worker_in_range = false;
            ++calls[i];
        });
        CHECK(worker_in_range);
        int wrong = 0;
        for (const auto& c : calls) wrong += c != 1;
        CHECK(wrong == 0);
    }
}

TEST_CASE("parallel_for rethrows an item's exception after its threads stopped") {
    std::atomic<int> started{0};
    CHECK_THROWS_WITH_AS(parallel_for(100, 2, nullptr,
                                      [&](std::size_t i, int) {
                                          ++started;
                                          if (i == 3) throw std::runtime_error("item 3");
                                      }),
                         "item 3", std::runtime_error);
    CHECK(started >= 4);
    CHECK(started <= 100);
}

TEST_CASE("parallel_for returns once every item has ended, and nothing runs an item after it returned") {
    std::vector<std::atomic<int>> calls(64);
    parallel_for(calls.size(), 4, nullptr, [&](std::size_t i, int) {
        std::this_thread::sleep_for(std::chrono::microseconds(200));
        ++calls[i];
    });
    int wrong = 0;
    for (const auto& c : calls) wrong += c != 1;
    CHECK(wrong == 0);
    std::this_thread::sleep_for(std::chrono::milliseconds(20));   // no worker outlived the call
    for (const auto& c : calls) wrong += c != 1;
    CHECK(wrong == 0);
}

TEST_CASE("parallel_for runs no item after the cancel flag is set") {
    std::atomic<bool> cancel{false};
    std::atomic<int> ran{0}, after_cancel{0};
    parallel_for(10000, 2, &cancel, [&](std::size_t i, int) {
        if (cancel.load()) ++after_cancel;
        ++ran;
        if (i == 100) cancel = true;
    });
    CHECK(ran >= 101);
    CHECK(ran < 10000);
    CHECK(after_cancel <= 1);   // the other thread may have taken one item as the flag was set
}

TEST_CASE("a SpreadThread runs its work with the process's whole affinity, started elsewhere or not") {
    const cpu_set_t process = own_affinity();
    cpu_set_t seen;
    CPU_ZERO(&seen);
    bool ran = false;
    {
        SpreadThread thread([&] {
            seen = own_affinity();
            ran = true;
        });
        thread.join();
        thread.join();   // the second join does nothing
    }
    CHECK(ran);
    CHECK(CPU_EQUAL(&seen, &process));

    // A creator limited to one core: nothing to leave out, the thread starts there.
    int one = 0;
    while (!CPU_ISSET(one, &process)) ++one;
    cpu_set_t single;
    CPU_ZERO(&single);
    CPU_SET(one, &single);
    REQUIRE(sched_setaffinity(0, sizeof single, &single) == 0);
    ran = false;
    SpreadThread([&] {
        seen = own_affinity();
        ran = true;
    }).join();
    REQUIRE(sched_setaffinity(0, sizeof process, &process) == 0);
    CHECK(ran);
    CHECK(CPU_EQUAL(&seen, &single));
}
