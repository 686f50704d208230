#pragma once
// The view-dependent half of splatting that both splat backends share (splat on the CPU, gl on
// OpenGL): every voxel of the classification's splat list projected to the image with the
// Projector, culled to the image (and to the front of the eye), and put in depth order front
// to back, ties broken by list order, so the order never depends on threads and both backends
// composite the same splats in the same order.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/vec2.hpp>

#include "renderers/classification/classification.h"
#include "renderers/kernels/splat_footprint.h"
#include "renderers/kernels/splat_voxels.h"

namespace svr::splat {

struct ProjectedVoxels {
  std::vector<std::uint32_t> ids;   // indices into SplatVoxels::voxels(), front to back
  std::vector<glm::vec2> position;  // image position (pixels) of ids[i]
  std::vector<float> depth;         // along the view axis (world units), ascending
  std::vector<Footprint> footprints;  // one (orthographic) or one per id
  const Footprint& footprint(std::size_t i) const {
    return footprints.size() == 1 ? footprints[0] : footprints[i];
  }
};

// World position of voxel `index` (x + y·nx + z·nx·ny), the volume centred on the origin.
glm::dvec3 voxelWorld(const ClassifiedVolume& cv, std::uint32_t index);

// sortByDepth's working arrays, kept between frames by a caller that renders many.
struct DepthSortScratch {
  std::vector<std::uint32_t> bits, other_ids, other_bits;
  std::vector<std::size_t> offsets;
};

// Every listed voxel projected, in list order, and the front-to-back order of those kept; with
// the arrays that took, so that a caller rendering many frames reuses them (a frame's first
// touch of fresh memory costs a page fault per 4 KiB: some 60 ms of a 1.4 M-splat frame here).
struct VoxelProjection {
  std::vector<glm::vec2> position;    // image position (pixels) of voxels()[i]
  std::vector<float> depth;           // along the view axis (world units)
  std::vector<Footprint> footprints;  // one (orthographic) or one per listed voxel
  std::vector<std::uint32_t> order;   // the kept voxels' indices, front to back
  std::vector<std::uint8_t> keep;
  DepthSortScratch sort;
};
void projectInListOrder(const SplatVoxels& voxels, const ClassifiedVolume& cv,
                        const Projector& projector, int width, int height, VoxelProjection& out);

// The same, gathered into depth order.
ProjectedVoxels projectVoxels(const SplatVoxels& voxels, const ClassifiedVolume& cv,
                              const Projector& projector, int width, int height);

// [0, n) cut into a count of chunks that depends on n alone (64 at most, of at least 65536 items
// where n allows): loops over chunks in parallel — each chunk counting, then each placing its own
// items — give the sequential result whatever the thread count.
struct FixedChunks {
  explicit FixedChunks(std::size_t items)
      : n(items), count(std::clamp<std::size_t>(items / 65536, 1, 64)) {}
  std::size_t begin(std::size_t chunk) const { return n * chunk / count; }
  std::size_t end(std::size_t chunk) const { return begin(chunk + 1); }
  std::size_t n, count;
};

// Stable sort of `ids` by key[id] ascending (LSD radix on the float bits; −0 sorts with +0).
void sortByDepth(std::vector<std::uint32_t>& ids, const std::vector<float>& key,
                 DepthSortScratch& scratch);
inline void sortByDepth(std::vector<std::uint32_t>& ids, const std::vector<float>& key) {
  DepthSortScratch scratch;
  sortByDepth(ids, key, scratch);
}

// The positions i where keep[i] is non-zero, ascending, into ids.
void keptIndices(const std::vector<std::uint8_t>& keep, std::vector<std::uint32_t>& ids);
inline std::vector<std::uint32_t> keptIndices(const std::vector<std::uint8_t>& keep) {
  std::vector<std::uint32_t> ids;
  keptIndices(keep, ids);
  return ids;
}

}  // namespace svr::splat
