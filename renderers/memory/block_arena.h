#pragma once
// Memory for many arrays that are filled once and freed together (shear-warp's voxel records:
// tens of MiB a principal axis, in a few hundred slices; the encoder's gathered slices), taken
// from large blocks. The blocks are ordinary 4 KiB pages, not huge ones (huge_pages.h): they are
// written once, in order, where a huge page saves little, and under virtualisation the first
// touch of fresh huge pages can be slow and erratic (the host must supply 2 MiB blocks the guest
// had freed). docs/performance/2026-12-06-pic-and-huge-pages.md has the measurement: the
// frog's first frames against steady ones, with the records on huge pages and on 4 KiB pages.

#include <cstddef>
#include <memory>
#include <type_traits>
#include <vector>

namespace svr {

class BlockArena {
 public:
  static constexpr std::size_t kBlockBytes = std::size_t{4} << 20;  // larger requests get their own

  // Uninitialised room for n objects of a trivially destructible type; valid until the arena
  // (or the one that adopted it) is destroyed. Throws std::bad_alloc.
  template <class T>
  T* allocate(std::size_t n) {
    static_assert(std::is_trivially_destructible_v<T>);
    return static_cast<T*>(allocateBytes(n * sizeof(T), alignof(T)));
  }

  // Takes over other's blocks (e.g. each thread's arena, once the threads are done).
  void adopt(BlockArena&& other);

 private:
  void* allocateBytes(std::size_t bytes, std::size_t align);

  struct Free {
    void operator()(std::byte* p) const;
  };
  std::vector<std::unique_ptr<std::byte, Free>> blocks_;
  std::byte* next_ = nullptr;
  std::size_t left_ = 0;
};

}  // namespace svr
