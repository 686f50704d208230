#include "renderers/memory/block_arena.h"

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <new>

namespace svr {

void BlockArena::Free::operator()(std::byte* p) const { std::free(p); }

void* BlockArena::allocateBytes(std::size_t bytes, std::size_t align) {
  const std::size_t pad = (align - reinterpret_cast<std::uintptr_t>(next_) % align) % align;
  if (next_ == nullptr || pad + bytes > left_) {
    // Cache-line aligned, in whole lines (as aligned_alloc requires a multiple of the alignment).
    constexpr std::size_t kLine = 64;
    const std::size_t size = (std::max(bytes, kBlockBytes) + kLine - 1) / kLine * kLine;
    auto* memory = static_cast<std::byte*>(std::aligned_alloc(kLine, size));
    if (!memory) throw std::bad_alloc();
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
