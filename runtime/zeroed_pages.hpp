// runtime/zeroed_pages.hpp — an allocator whose memory starts as zero bytes without being
// written: fresh anonymous pages from mmap, in ordinary 4 KiB pages; and pages faulted in
// for writing ahead of the writes, in one call or on threads.
//
// Why: a sign volume is mostly background; when its encoding makes the background a zero
// byte, the kernel's page zeroing is its only initialisation. Writing the background over
// 16 MiB (tanglecube.vm 256³) had cost as much as the zeroing itself, a quarter of the render;
// pages the render never writes are never even faulted in for writing.
//
// Why not 2 MiB huge pages: a write anywhere in one makes the kernel zero all of it, so
// tanglecube.vm's 256³ render zeroed its whole 16 MiB (8 huge pages) where it writes 1.4 MB
// (347 small pages). On the Zen 4 of 2026-12-01 the two were within noise; on the Intel Xeon
// of 2026-12-02 huge pages took 2.4-4.8 ms to touch on one thread and up to 12 ms on two (a
// probe touching 16 MiB), and the render's medians were 3.78 → 3.22 ms on one thread and
// 2.76 → 2.21 ms on two with small pages (21 alternated runs; the two-thread maximum 11.8 →
// 4.1 ms), its peak memory 15.4 → 9.3 MiB. Elements are default-initialised (resize leaves
// them zero).
#pragma once

#include "runtime/parallel.hpp"

#include <sys/mman.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <new>
#include <utility>

namespace fortu {

/// Faults in the pages of [p, p + bytes) (p page-aligned, as ZeroedPageAllocator gives it)
/// for writing, in one call, still zero. Why: where a render will write most of them (a 2D
/// sign image: four 1024-byte rows to a page), the kernel maps them in one batch (1 MiB:
/// 0.09 ms on the Intel Xeon, model 167, of 2026-12-02) instead of trapping once a page
/// (0.19-0.35 ms); prospero.vm's 1024² sign image 7.13 → 6.94 ms. Best effort: false where
/// the kernel has no MADV_POPULATE_WRITE (before Linux 5.14), whose pages then fault in as
/// they are written.
inline bool populate_for_writing(void* p, std::size_t bytes) {
#ifdef MADV_POPULATE_WRITE
    return bytes == 0 || madvise(p, bytes, MADV_POPULATE_WRITE) == 0;
#else
    (void)p;
    (void)bytes;
    return false;
#endif
}

/// The pages this allocator and populate_whole_pages work in.
constexpr std::size_t kSmallPage = 4096;

/// Below this populate_whole_pages leaves the pages to fault in as they are written: too few
/// to share.
constexpr std::size_t kPopulateWholePagesFrom = std::size_t(1) << 20;

/// The whole 4 KiB pages inside [p, p + bytes) (p any address, as a std::vector gives it)
/// faulted in for writing by `threads` threads, a contiguous share each in one call. Why: a
/// field is filled before an engine writes it, and on a virtual machine each page's first
/// write traps to the kernel (2.1 µs on the Intel Xeon, model 207, of 2026-12-03), serially
/// on the filling thread.
inline void populate_whole_pages(void* p, std::size_t bytes, int threads) {
    constexpr std::uintptr_t kPage = kSmallPage;
    if (bytes < kPopulateWholePagesFrom) return;
    const std::uintptr_t first = (reinterpret_cast<std::uintptr_t>(p) + kPage - 1) / kPage * kPage;
    const std::uintptr_t end = (reinterpret_cast<std::uintptr_t>(p) + bytes) / kPage * kPage;
    const std::size_t pages = (end - first) / kPage;
    const std::size_t shares = static_cast<std::size_t>(worker_count(pages, threads));
    parallel_for(shares, threads, nullptr, [&](std::size_t i, int) {
        const std::size_t from = pages * i / shares, to = pages * (i + 1) / shares;
        populate_for_writing(reinterpret_cast<void*>(first + from * kPage), (to - from) * kPage);
    });
}

template <class T>
struct ZeroedPageAllocator {
    using value_type = T;
    static constexpr std::size_t kPage = kSmallPage;

    ZeroedPageAllocator() = default;
    template <class U>
    ZeroedPageAllocator(const ZeroedPageAllocator<U>&) noexcept {}

    T* allocate(std::size_t n) {
        if (n > (std::numeric_limits<std::size_t>::max() - kPage) / sizeof(T)) throw std::bad_array_new_length();
        void* p = mmap(nullptr, mapped_bytes(n), PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
        if (p == MAP_FAILED) throw std::bad_alloc();
        return static_cast<T*>(p);
    }
    void deallocate(T* p, std::size_t n) noexcept { munmap(p, mapped_bytes(n)); }
    template <class U>
    void construct(U* p) noexcept {
        ::new (static_cast<void*>(p)) U;
    }
    template <class U, class... Args>
    void construct(U* p, Args&&... args) {
        ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
    }
    friend bool operator==(const ZeroedPageAllocator&, const ZeroedPageAllocator&) { return true; }

private:
    /// Whole pages.
    static std::size_t mapped_bytes(std::size_t n) {
        const std::size_t bytes = std::max<std::size_t>(n * sizeof(T), 1);
        return (bytes + kPage - 1) / kPage * kPage;
    }
};

}  // namespace fortu
