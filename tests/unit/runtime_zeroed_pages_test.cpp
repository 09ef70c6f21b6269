// tests/unit/runtime_zeroed_pages_test.cpp — ZeroedPageAllocator's memory starts as zero
// bytes, populate_for_writing makes every page resident without changing a byte (and
// populate_whole_pages the whole pages of any range, on threads), and a field filled on
// threads holds its fill.
#include "runtime/field.hpp"
#include "runtime/zeroed_pages.hpp"

#include <doctest/doctest.h>

#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <vector>

using namespace fortu;

namespace {

/// Pages of [p, p + bytes) the kernel has resident (mincore).
std::size_t resident_pages(const void* p, std::size_t bytes) {
    const std::size_t page = static_cast<std::size_t>(sysconf(_SC_PAGESIZE));
    std::vector<unsigned char> in_core((bytes + page - 1) / page);
    REQUIRE(mincore(const_cast<void*>(p), bytes, in_core.data()) == 0);
    return static_cast<std::size_t>(std::count_if(in_core.begin(), in_core.end(), [](unsigned char c) { return c & 1; }));
}

}  // namespace

TEST_CASE("zeroed pages: fresh, untouched, then populated for writing, still zero") {
    constexpr std::size_t kBytes = std::size_t(1) << 20, kPage = ZeroedPageAllocator<int8_t>::kPage;
    std::vector<int8_t, ZeroedPageAllocator<int8_t>> codes;
    codes.resize(kBytes);
    REQUIRE(reinterpret_cast<std::uintptr_t>(codes.data()) % kPage == 0);
    CHECK(resident_pages(codes.data(), kBytes) == 0);   // resize writes nothing
    if (!populate_for_writing(codes.data(), kBytes)) {
        MESSAGE("this kernel has no MADV_POPULATE_WRITE: nothing to check");
        return;
    }
    CHECK(resident_pages(codes.data(), kBytes) == kBytes / kPage);
    CHECK(std::all_of(codes.begin(), codes.end(), [](int8_t c) { return c == 0; }));
    codes[kBytes - 1] = 5;
    CHECK(codes[kBytes - 1] == 5);
}

TEST_CASE("zeroed pages: populating nothing succeeds") {
    std::vector<int8_t, ZeroedPageAllocator<int8_t>> codes;
    codes.resize(1);
    CHECK(populate_for_writing(codes.data(), 0));
}

TEST_CASE("zeroed pages: the whole pages of a range populated by two threads, the partial ones at its ends left") {
    constexpr std::size_t kPage = ZeroedPageAllocator<int8_t>::kPage, kPages = 768;   // 3 MiB
    std::vector<int8_t, ZeroedPageAllocator<int8_t>> codes;
    codes.resize(kPages * kPage);
    int8_t* start = codes.data() + 100;
    const std::size_t bytes = (kPages - 1) * kPage;   // ends 100 bytes into the last page
    std::vector<int8_t, ZeroedPageAllocator<int8_t>> probe;
    probe.resize(kPage);
    if (!populate_for_writing(probe.data(), kPage)) {
        MESSAGE("this kernel has no MADV_POPULATE_WRITE: nothing to check");
        return;
    }
    populate_whole_pages(start, bytes, 2);
    CHECK(resident_pages(codes.data(), kPage) == 0);                      // the first, partial page
    CHECK(resident_pages(codes.data() + kPage, (kPages - 2) * kPage) == kPages - 2);
    CHECK(resident_pages(codes.data() + (kPages - 1) * kPage, kPage) == 0);  // the last, partial page
    CHECK(std::all_of(codes.begin(), codes.end(), [](int8_t c) { return c == 0; }));
}

TEST_CASE("zeroed pages: below a mebibyte nothing is populated") {
    constexpr std::size_t kPage = ZeroedPageAllocator<int8_t>::kPage;
    std::vector<int8_t, ZeroedPageAllocator<int8_t>> codes;
    codes.resize(kPopulateWholePagesFrom - kPage);
    populate_whole_pages(codes.data(), codes.size(), 2);
    CHECK(resident_pages(codes.data(), codes.size()) == 0);
}

TEST_CASE("fields: filled on one, two or all threads, every value the fill") {
    Grid grid;
    grid.dims = 3;
    grid.x.nodes = 65, grid.y.nodes = 64, grid.z.nodes = 33;   // 1.05 MiB of values: populated
    for (int threads : {1, 2, 0}) {
        CAPTURE(threads);
        const Field field = Field::filled(grid, -2.5, threads);
        REQUIRE(field.values.size() == std::size_t(65) * 64 * 33);
        CHECK(std::all_of(field.values.begin(), field.values.end(), [](double v) { return v == -2.5; }));
    }
    grid.z.nodes = 1;
    grid.dims = 2;
    const Field small = Field::filled(grid, 7.0, 2);
    CHECK(small.values == std::vector<double>(std::size_t(65) * 64, 7.0));
}
