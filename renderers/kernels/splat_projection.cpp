#include "renderers/kernels/splat_projection.h"

#include <bit>
#include <utility>

namespace svr::splat {

glm::dvec3 voxelWorld(const ClassifiedVolume& cv, std::uint32_t index) {
  const Dims& d = cv.dims;
  const glm::dvec3 centre = 0.5 * glm::dvec3(d[0] - 1, d[1] - 1, d[2] - 1);
  const std::uint32_t x = index % d[0], y = (index / d[0]) % d[1], z = index / (d[0] * d[1]);
  return (glm::dvec3(x, y, z) - centre) * cv.spacing;
}

void projectInListOrder(const SplatVoxels& voxels, const ClassifiedVolume& cv,
                        const Projector& projector, int width, int height, VoxelProjection& out) {
  const auto list = voxels.voxels();
  const bool ortho = projector.orthographic();
  const Footprint any = projector.footprint(glm::dvec3(0.0));
  const std::size_t total = list.size();
  out.depth.resize(total);
  out.position.resize(total);
  out.footprints.resize(ortho ? 1 : total);
  if (ortho) out.footprints[0] = any;
  std::vector<std::uint8_t>& keep = out.keep;
  keep.resize(total);
  // An orthographic projection is affine in the voxel's grid coordinates: the image of the
  // first voxel plus a step per axis (in double, so the positions equal project()'s to well
  // within float rounding), where project() took a world position from three divisions.
  const Dims& d = cv.dims;
  const glm::dvec3 origin = projector.project(voxelWorld(cv, 0));
  const glm::dvec3 step[3] = {
      d[0] > 1 ? projector.project(voxelWorld(cv, 1)) - origin : glm::dvec3(0.0),
      d[1] > 1 ? projector.project(voxelWorld(cv, d[0])) - origin : glm::dvec3(0.0),
      d[2] > 1 ? projector.project(voxelWorld(cv, d[0] * d[1])) - origin : glm::dvec3(0.0)};
  const std::uint32_t nx = d[0], nxy = d[0] * d[1];
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < total; ++i) {
    const std::uint32_t index = list[i].index;
    glm::dvec3 pos;
    Footprint fp = any;
    if (ortho) {
      const std::uint32_t z = index / nxy, rest = index - z * nxy, y = rest / nx, x = rest - y * nx;
      pos = origin + static_cast<double>(x) * step[0] + static_cast<double>(y) * step[1] +
            static_cast<double>(z) * step[2];
    } else {
      const glm::dvec3 world = voxelWorld(cv, index);
      pos = projector.project(world);
      fp = projector.footprint(world);
      out.footprints[i] = fp;
    }
    keep[i] = (ortho || pos.z > 0.0) && !(pos.x + fp.half_w < 0 || pos.x - fp.half_w > width ||
                                          pos.y + fp.half_h < 0 || pos.y - fp.half_h > height);
    out.depth[i] = static_cast<float>(pos.z);
    out.position[i] = {static_cast<float>(pos.x), static_cast<float>(pos.y)};
  }
  keptIndices(keep, out.order);
  sortByDepth(out.order, out.depth, out.sort);
}

ProjectedVoxels projectVoxels(const SplatVoxels& voxels, const ClassifiedVolume& cv,
                              const Projector& projector, int width, int height) {
  VoxelProjection projection;
  projectInListOrder(voxels, cv, projector, width, height, projection);
  ProjectedVoxels out;
  out.ids = std::move(projection.order);
  const std::size_t n = out.ids.size();
  const bool ortho = projection.footprints.size() == 1;
  out.position.resize(n);
  out.depth.resize(n);
  if (ortho) out.footprints = {projection.footprints[0]};
  else out.footprints.resize(n);
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t id = out.ids[i];
    out.position[i] = projection.position[id];
    out.depth[i] = projection.depth[id];
    if (!ortho) out.footprints[i] = projection.footprints[id];
  }
  return out;
}

void sortByDepth(std::vector<std::uint32_t>& ids, const std::vector<float>& key,
                 DepthSortScratch& scratch) {
  const std::size_t n = ids.size();
  std::vector<std::uint32_t>&bits = scratch.bits, &other_ids = scratch.other_ids,
                             &other_bits = scratch.other_bits;
  bits.resize(n);
  other_ids.resize(n);
  other_bits.resize(n);
  std::uint32_t lowest = ~0u, highest = 0;
#pragma omp parallel for schedule(static) reduction(min : lowest) reduction(max : highest)
  for (std::size_t i = 0; i < n; ++i) {
    const float k = key[ids[i]] == 0.f ? 0.f : key[ids[i]];  // −0 sorts with +0
    const std::uint32_t u = std::bit_cast<std::uint32_t>(k);
    bits[i] = (u & 0x80000000u) ? ~u : (u | 0x80000000u);  // order-preserving for floats
    lowest = std::min(lowest, bits[i]);
    highest = std::max(highest, bits[i]);
  }
  // Sorted on the keys less the lowest: depths of one sign within a factor of two or four of
  // each other (a volume seen from outside it) span fewer than 2^24 of them, two passes.
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) bits[i] -= lowest;
  const std::uint32_t span = n > 0 ? highest - lowest : 0;
  // Each pass is a stable counting sort on 12 bits over fixed chunks: every chunk counts its
  // digits, the offsets run digit by digit and within a digit chunk by chunk, and every chunk
  // then scatters its own keys in order.
  constexpr int kBits = 12, kDigits = 1 << kBits;
  const FixedChunks chunks(n);
  std::vector<std::size_t>& offset = scratch.offsets;
  offset.resize(chunks.count * kDigits);
  for (int shift = 0; shift < 32 && (span >> shift) != 0; shift += kBits) {
    std::fill(offset.begin(), offset.end(), 0);
#pragma omp parallel for schedule(static)
    for (std::size_t c = 0; c < chunks.count; ++c)
      for (std::size_t i = chunks.begin(c); i < chunks.end(c); ++i)
        ++offset[c * kDigits + ((bits[i] >> shift) & (kDigits - 1))];
    std::size_t sum = 0;
    for (int d = 0; d < kDigits; ++d)
      for (std::size_t c = 0; c < chunks.count; ++c) {
        const std::size_t count = offset[c * kDigits + d];
        offset[c * kDigits + d] = sum;
        sum += count;
      }
#pragma omp parallel for schedule(static)
    for (std::size_t c = 0; c < chunks.count; ++c)
      for (std::size_t i = chunks.begin(c); i < chunks.end(c); ++i) {
        const std::size_t to = offset[c * kDigits + ((bits[i] >> shift) & (kDigits - 1))]++;
        other_ids[to] = ids[i];
        other_bits[to] = bits[i];
      }
    ids.swap(other_ids);
    bits.swap(other_bits);
  }
}

void keptIndices(const std::vector<std::uint8_t>& keep, std::vector<std::uint32_t>& ids) {
  const FixedChunks chunks(keep.size());
  std::vector<std::size_t> start(chunks.count + 1, 0);
#pragma omp parallel for schedule(static)
  for (std::size_t c = 0; c < chunks.count; ++c)
    for (std::size_t i = chunks.begin(c); i < chunks.end(c); ++i) start[c + 1] += keep[i];
  for (std::size_t c = 0; c < chunks.count; ++c) start[c + 1] += start[c];
  ids.resize(start[chunks.count]);
#pragma omp parallel for schedule(static)
  for (std::size_t c = 0; c < chunks.count; ++c) {
    std::size_t to = start[c];
    for (std::size_t i = chunks.begin(c); i < chunks.end(c); ++i)
      if (keep[i]) ids[to++] = static_cast<std::uint32_t>(i);
  }
}

}  // namespace svr::splat
