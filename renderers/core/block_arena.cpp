#include "renderers/core/block_arena.h"

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <new>

#include "renderers/core/huge_pages.h"

namespace svr {

void BlockArena::Free::operator()(std::byte* p) const { releaseHugePages(p); }

void* BlockArena::allocateBytes(std::size_t bytes, std::size_t align) {
  const std::size_t pad = (align - reinterpret_cast<std::uintptr_t>(next_) % align) % align;
  if (next_ == nullptr || pad + bytes > left_) {
    // Whole huge pages, aligned to one, so that every page of the block can be a huge one.
    const std::size_t size =
        (std::max(bytes, kBlockBytes) + kHugePage - 1) / kHugePage * kHugePage;
    auto* memory = static_cast<std::byte*>(allocateHugePages(size));
    blocks_.emplace_back(memory);
    next_ = memory, left_ = size;
    return allocateBytes(bytes, align);
  }
  std::byte* at = next_ + pad;
  next_ = at + bytes;
  left_ -= pad + bytes;
  return at;
}

void BlockArena::adopt(BlockArena&& other) {
  for (auto& b : other.blocks_) blocks_.push_back(std::move(b));
  other.blocks_.clear();
  other.next_ = nullptr, other.left_ = 0;
}

}  // namespace svr
