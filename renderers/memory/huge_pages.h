#pragma once
// Memory that the kernel is asked to back with transparent huge pages (Linux's usual mode is
// madvise: only memory advised so gets them), for arrays read across their rows: a walk that
// crosses a row of a large image at every step (shear-warp's warp under rotation) touches a new
// 4 KiB page at most steps, and each TLB miss costs a page walk (a nested one under
// virtualisation); with 2 MiB pages the whole image takes a few TLB entries
// (docs/performance/2026-12-06-pic-and-huge-pages.md gives what 4 KiB pages cost the warp). Not for memory written once and read in order
// (block_arena.h): the first touch of fresh huge pages can be slow and erratic.
// Requests under one huge page come from malloc as usual.

#include <cstddef>

namespace svr {

inline constexpr std::size_t kHugePage = std::size_t{2} << 20;

// At least `bytes`, aligned to a huge page and rounded up to whole ones when one or more (so
// every page of it can be huge); release with releaseHugePages. Throws std::bad_alloc.
void* allocateHugePages(std::size_t bytes);
void releaseHugePages(void* p);

// For std::vector and the like: large arrays on huge pages.
template <class T>
struct HugePageAllocator {
  using value_type = T;
  HugePageAllocator() = default;
  template <class U>
  HugePageAllocator(const HugePageAllocator<U>&) {}
  T* allocate(std::size_t n) { return static_cast<T*>(allocateHugePages(n * sizeof(T))); }
  void deallocate(T* p, std::size_t) { releaseHugePages(p); }
  template <class U>
  bool operator==(const HugePageAllocator<U>&) const {
    return true;
  }
};

}  // namespace svr
