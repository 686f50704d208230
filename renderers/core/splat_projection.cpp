#include "renderers/core/splat_projection.h"

#include <bit>

namespace svr::splat {

glm::dvec3 voxelWorld(const ClassifiedVolume& cv, std::uint32_t index) {
  const Dims& d = cv.dims;
  const glm::dvec3 centre = 0.5 * glm::dvec3(d[0] - 1, d[1] - 1, d[2] - 1);
  const std::uint32_t x = index % d[0], y = (index / d[0]) % d[1], z = index / (d[0] * d[1]);
  return (glm::dvec3(x, y, z) - centre) * cv.spacing;
}

ProjectedVoxels projectVoxels(const SplatVoxels& voxels, const ClassifiedVolume& cv,
                              const Projector& projector, int width, int height) {
  const auto list = voxels.voxels();
  const bool ortho = projector.orthographic();
  const Footprint any = projector.footprint(glm::dvec3(0.0));
  const std::size_t total = list.size();
  std::vector<float> depth(total);
  std::vector<glm::vec2> position(total);
  std::vector<Footprint> footprint(ortho ? 0 : total);
  std::vector<std::uint8_t> keep(total);
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < total; ++i) {
    const glm::dvec3 world = voxelWorld(cv, list[i].index);
    const glm::dvec3 pos = projector.project(world);
    const Footprint fp = ortho ? any : projector.footprint(world);
    keep[i] = (ortho || pos.z > 0.0) && !(pos.x + fp.half_w < 0 || pos.x - fp.half_w > width ||
                                          pos.y + fp.half_h < 0 || pos.y - fp.half_h > height);
    depth[i] = static_cast<float>(pos.z);
    position[i] = {static_cast<float>(pos.x), static_cast<float>(pos.y)};
    if (!ortho) footprint[i] = fp;
  }
  ProjectedVoxels out;
  out.ids = keptIndices(keep);
  sortByDepth(out.ids, depth);
  const std::size_t n = out.ids.size();
  out.position.resize(n);
  out.depth.resize(n);
  if (ortho) out.footprints = {any};
  else out.footprints.resize(n);
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t id = out.ids[i];
    out.position[i] = position[id];
    out.depth[i] = depth[id];
    if (!ortho) out.footprints[i] = footprint[id];
  }
  return out;
}

void sortByDepth(std::vector<std::uint32_t>& ids, const std::vector<float>& key) {
  const std::size_t n = ids.size();
  std::vector<std::uint32_t> bits(n), other_ids(n), other_bits(n);
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    const float k = key[ids[i]] == 0.f ? 0.f : key[ids[i]];  // −0 sorts with +0
    const std::uint32_t u = std::bit_cast<std::uint32_t>(k);
    bits[i] = (u & 0x80000000u) ? ~u : (u | 0x80000000u);  // order-preserving for floats
  }
  // Each pass is a stable counting sort on 11 bits over fixed chunks: every chunk counts its
  // digits, the offsets run digit by digit and within a digit chunk by chunk, and every chunk
  // then scatters its own keys in order.
  constexpr int kDigits = 2048;
  const FixedChunks chunks(n);
  std::vector<std::size_t> offset(chunks.count * kDigits);
  for (int shift = 0; shift < 32; shift += 11) {
    std::fill(offset.begin(), offset.end(), 0);
#pragma omp parallel for schedule(static)
    for (std::size_t c = 0; c < chunks.count; ++c)
      for (std::size_t i = chunks.begin(c); i < chunks.end(c); ++i)
        ++offset[c * kDigits + ((bits[i] >> shift) & 2047u)];
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
        const std::size_t to = offset[c * kDigits + ((bits[i] >> shift) & 2047u)]++;
        other_ids[to] = ids[i];
        other_bits[to] = bits[i];
      }
    ids.swap(other_ids);
    bits.swap(other_bits);
  }
}

std::vector<std::uint32_t> keptIndices(const std::vector<std::uint8_t>& keep) {
  const FixedChunks chunks(keep.size());
  std::vector<std::size_t> start(chunks.count + 1, 0);
#pragma omp parallel for schedule(static)
  for (std::size_t c = 0; c < chunks.count; ++c)
    for (std::size_t i = chunks.begin(c); i < chunks.end(c); ++i) start[c + 1] += keep[i];
  for (std::size_t c = 0; c < chunks.count; ++c) start[c + 1] += start[c];
  std::vector<std::uint32_t> ids(start[chunks.count]);
#pragma omp parallel for schedule(static)
  for (std::size_t c = 0; c < chunks.count; ++c) {
    std::size_t to = start[c];
    for (std::size_t i = chunks.begin(c); i < chunks.end(c); ++i)
      if (keep[i]) ids[to++] = static_cast<std::uint32_t>(i);
  }
  return ids;
}

}  // namespace svr::splat
