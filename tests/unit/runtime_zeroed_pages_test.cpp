// tests/unit/runtime_zeroed_pages_test.cpp — ZeroedPageAllocator's memory starts as zero
// bytes, and populate_for_writing makes every page resident without changing a byte.
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
