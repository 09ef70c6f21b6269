// tests/unit/runtime_resources_test.cpp — number formatting, the stopwatch, peak memory, the
// progress bar, and field statistics.
#include "runtime/field_stats.hpp"
#include "runtime/progress.hpp"
#include "runtime/resources.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <thread>
#include <vector>

using namespace fortu;

TEST_CASE("format_count puts thousands separators") {
    CHECK(format_count(0) == "0");
    CHECK(format_count(999) == "999");
    CHECK(format_count(1000) == "1,000");
    CHECK(format_count(397393719) == "397,393,719");
    CHECK(format_count(18446744073709551615ull) == "18,446,744,073,709,551,615");
}

TEST_CASE("format_bytes uses binary units with one decimal") {
    CHECK(format_bytes(0) == "0 B");
    CHECK(format_bytes(1023) == "1023 B");
    CHECK(format_bytes(1024) == "1.0 KiB");
    CHECK(format_bytes(1536) == "1.5 KiB");
    CHECK(format_bytes(397393719) == "379.0 MiB");
    CHECK(format_bytes(std::size_t{5} << 30) == "5.0 GiB");
    CHECK(format_bytes((std::size_t{1} << 20) - 1) == "1.0 MiB");   // not "1024.0 KiB"
}

TEST_CASE("format_duration reads like the papers' timings") {
    CHECK(format_duration(0.000850) == "850 µs");
    CHECK(format_duration(0.0123) == "12.3 ms");
    CHECK(format_duration(0.9996) == "1.00 s");
    CHECK(format_duration(2.345) == "2.35 s");
    CHECK(format_duration(59.4) == "59.4 s");
    CHECK(format_duration(111.0) == "1 min 51 s");
    CHECK(format_duration(17 * 60 + 29.2) == "17 min 29 s");
    CHECK(format_duration(2 * 3600 + 5 * 60) == "2 h 05 min");
    CHECK(format_duration(-1.0) == "?");
    CHECK(format_duration(std::nan("")) == "?");
}

TEST_CASE("Stopwatch and peak_rss_bytes") {
    Stopwatch watch;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    const double elapsed = watch.seconds();
    CHECK(elapsed >= 0.019);
    CHECK(elapsed < 5.0);
    watch.restart();
    CHECK(watch.seconds() < elapsed);
    std::vector<char> touch(8 << 20, 1);
    CHECK(peak_rss_bytes() >= touch.size());
}

TEST_CASE("Progress counts from many threads and draws nothing when not asked to") {
    Progress progress("work", 40000, nullptr, 0.0);
    std::vector<std::thread> threads;
    for (int t = 0; t < 4; ++t)
        threads.emplace_back([&] {
            for (int i = 0; i < 10000; ++i) progress.advance();
        });
    for (auto& t : threads) t.join();
    CHECK(progress.done() == 40000);
    CHECK(progress.total() == 40000);
    progress.finish();
    progress.finish();   // idempotent
}

TEST_CASE("Progress draws a bar after its delay and clears the line at finish") {
    std::FILE* out = std::tmpfile();
    REQUIRE(out);
    {
        Progress progress("sampling", 200, out, 0.0);
        progress.advance(50);
        std::this_thread::sleep_for(std::chrono::milliseconds(350));
        progress.finish();
    }
    std::rewind(out);
    std::string text;
    for (int c; (c = std::fgetc(out)) != EOF;) text += static_cast<char>(c);
    std::fclose(out);
    CHECK(text.starts_with("\rsampling ["));
    CHECK(text.find(" 25%  50/200  ") != std::string::npos);
    CHECK(text.ends_with("\r\033[K"));
}

TEST_CASE("Progress stays silent before its delay") {
    std::FILE* out = std::tmpfile();
    REQUIRE(out);
    {
        Progress progress("quick", 10, out, 60.0);
        progress.advance(10);
    }
    CHECK(std::ftell(out) == 0);
    std::fclose(out);
}

TEST_CASE("field_stats: range and mean over finite values, counts by sign, invalid points") {
    Field f;
    f.grid.x = {0.0, 1.0, 8};
    f.values = {1.0, -2.0, 0.0, 4.0, std::nan(""), std::numeric_limits<double>::infinity(), 0.0, -1.0};
    const FieldStats s = field_stats(f);
    CHECK(s.points == 8);
    CHECK(s.invalid == 2);
    CHECK(s.positive == 2);
    CHECK(s.zero == 2);
    CHECK(s.negative == 2);
    CHECK(s.min == -2.0);
    CHECK(s.max == 4.0);
    CHECK(s.mean == 2.0 / 6.0);

    SUBCASE("no finite value: NaN range") {
        const FieldStats none = field_stats(std::vector<double>{std::nan(""), -std::numeric_limits<double>::infinity()});
        CHECK(none.invalid == 2);
        CHECK(std::isnan(none.min));
        CHECK(std::isnan(none.max));
        CHECK(std::isnan(none.mean));
    }
    SUBCASE("the mean is compensated") {
        std::vector<double> v{1e16, 1.0, -1e16};
        for (int i = 0; i < 9; ++i) v.push_back(1.0);
        CHECK(field_stats(v).mean == 10.0 / 12.0);
    }
}
