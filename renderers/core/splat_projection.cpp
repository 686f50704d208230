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
  for (std::size_t i = 0; i < total; ++i)
    if (keep[i]) out.ids.push_back(static_cast<std::uint32_t>(i));
  sortByDepth(out.ids, depth);
  const std::size_t n = out.ids.size();
  out.position.resize(n);
  out.depth.resize(n);
  if (ortho) out.footprints = {any};
  else out.footprints.resize(n);
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
  for (std::size_t i = 0; i < n; ++i) {
    const float k = key[ids[i]] == 0.f ? 0.f : key[ids[i]];  // −0 sorts with +0
    const std::uint32_t u = std::bit_cast<std::uint32_t>(k);
    bits[i] = (u & 0x80000000u) ? ~u : (u | 0x80000000u);  // order-preserving for floats
  }
  for (int shift = 0; shift < 32; shift += 11) {
    std::vector<std::size_t> count(2049, 0);
    for (std::size_t i = 0; i < n; ++i) ++count[((bits[i] >> shift) & 2047u) + 1];
    for (int b = 0; b < 2048; ++b) count[b + 1] += count[b];
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t to = count[(bits[i] >> shift) & 2047u]++;
      other_ids[to] = ids[i];
      other_bits[to] = bits[i];
    }
    ids.swap(other_ids);
    bits.swap(other_bits);
  }
}

}  // namespace svr::splat
