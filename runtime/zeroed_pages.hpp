// runtime/zeroed_pages.hpp — an allocator whose memory starts as zero bytes without being
// written: fresh anonymous pages from mmap, in 2 MiB transparent huge pages where the kernel
// has them (madvise(MADV_HUGEPAGE): a 256³ volume is then 8 page faults, not 4,096).
//
// Why: a sign volume is mostly background; when its encoding makes the background a zero
// byte, the kernel's page zeroing is its only initialisation. Writing the background over
// 16 MiB (tanglecube.vm 256³) had cost as much as the zeroing itself, a quarter of the render;
// pages the render never writes are never even faulted in for writing. Elements are
// default-initialised (resize leaves them zero).
#pragma once

#include <sys/mman.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <new>
#include <utility>

namespace fortu {

/// Asks for transparent huge pages over the whole 2 MiB lines inside [p, p + bytes), before
/// anything touches them: memory then faults in 2 MiB at a time. Worth it for the sign volumes
/// (most of their pages are never touched); not for full fields, which touch every page and
/// can wait on the kernel compacting memory for them (field.hpp).
inline void advise_huge_pages(void* p, std::size_t bytes) {
#ifdef MADV_HUGEPAGE
    constexpr std::uintptr_t kLine = std::uintptr_t{2} << 20;
    const auto start = reinterpret_cast<std::uintptr_t>(p);
    const std::uintptr_t first = (start + kLine - 1) / kLine * kLine, end = (start + bytes) / kLine * kLine;
    if (end > first) madvise(reinterpret_cast<void*>(first), end - first, MADV_HUGEPAGE);
#else
    (void)p;
    (void)bytes;
#endif
}

template <class T>
struct ZeroedPageAllocator {
    using value_type = T;
    static constexpr std::size_t kHugePage = std::size_t{2} << 20;

    ZeroedPageAllocator() = default;
    template <class U>
    ZeroedPageAllocator(const ZeroedPageAllocator<U>&) noexcept {}

    T* allocate(std::size_t n) {
        if (n > (std::numeric_limits<std::size_t>::max() - 2 * kHugePage) / sizeof(T)) throw std::bad_array_new_length();
        const std::size_t bytes = mapped_bytes(n);
        if (bytes < kHugePage) {
            void* p = mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
            if (p == MAP_FAILED) throw std::bad_alloc();
            return static_cast<T*>(p);
        }
        // Over-map by one huge page, then unmap the ends so the block starts on a 2 MiB line.
        const std::size_t span = bytes + kHugePage;
        void* raw = mmap(nullptr, span, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
        if (raw == MAP_FAILED) throw std::bad_alloc();
        const auto start = reinterpret_cast<std::uintptr_t>(raw);
        const std::uintptr_t aligned = (start + kHugePage - 1) / kHugePage * kHugePage;
        if (aligned > start) munmap(raw, aligned - start);
        const std::size_t tail = start + span - (aligned + bytes);
        if (tail > 0) munmap(reinterpret_cast<void*>(aligned + bytes), tail);
        advise_huge_pages(reinterpret_cast<void*>(aligned), bytes);
        return reinterpret_cast<T*>(aligned);
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
    /// Whole 4 KiB pages below 2 MiB, whole huge pages above.
    static std::size_t mapped_bytes(std::size_t n) {
        const std::size_t bytes = std::max<std::size_t>(n * sizeof(T), 1);
        const std::size_t unit = bytes < kHugePage ? 4096 : kHugePage;
        return (bytes + unit - 1) / unit * unit;
    }
};

}  // namespace fortu
