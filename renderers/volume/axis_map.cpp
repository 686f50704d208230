#include "renderers/volume/axis_map.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <numbers>

#include "base/error.h"

namespace svr {

bool AxisMap::identity() const {
  return file_axis == std::array<int, 3>{0, 1, 2} && flip == std::array<bool, 3>{};
}

Dims AxisMap::outputDims(const Dims& file_dims) const {
  return {file_dims[file_axis[0]], file_dims[file_axis[1]], file_dims[file_axis[2]]};
}

glm::dvec3 AxisMap::outputSpacing(const glm::dvec3& file_spacing) const {
  return {file_spacing[file_axis[0]], file_spacing[file_axis[1]], file_spacing[file_axis[2]]};
}

VoxelBox AxisMap::fileBox(const VoxelBox& out_box, const Dims& file_dims) const {
  VoxelBox box;
  for (int a = 0; a < 3; ++a) {
    const int p = file_axis[a], n = file_dims[p];
    box.lo[p] = flip[a] ? n - out_box.hi[a] : out_box.lo[a];
    box.hi[p] = flip[a] ? n - out_box.lo[a] : out_box.hi[a];
  }
  return box;
}

LatticeIndices AxisMap::fileLattice(const LatticeIndices& out, const Dims& file_dims) const {
  LatticeIndices at;
  for (int a = 0; a < 3; ++a) {
    const int p = file_axis[a];
    at[p] = out[a];
    if (flip[a]) {
      for (int& i : at[p]) i = file_dims[p] - 1 - i;
      std::reverse(at[p].begin(), at[p].end());
    }
  }
  return at;
}

std::vector<std::byte> AxisMap::reorder(const std::vector<std::byte>& file_order,
                                        const Dims& file_size, std::size_t width) const {
  if (identity()) return file_order;
  const Dims out = outputDims(file_size);
  // The file-order stride of a step along each output axis, and where output voxel 0 lies.
  const std::array<std::int64_t, 3> file_stride{1, file_size[0],
                                                std::int64_t{file_size[0]} * file_size[1]};
  std::array<std::int64_t, 3> step{};
  std::int64_t origin = 0;
  for (int a = 0; a < 3; ++a) {
    const std::int64_t s = file_stride[file_axis[a]];
    step[a] = flip[a] ? -s : s;
    if (flip[a]) origin += s * (out[a] - 1);
  }
  std::vector<std::byte> result(file_order.size());
  std::byte* dest = result.data();
  for (int z = 0; z < out[2]; ++z)
    for (int y = 0; y < out[1]; ++y) {
      std::int64_t from = origin + z * step[2] + y * step[1];
      for (int x = 0; x < out[0]; ++x, from += step[0])
        dest = std::copy_n(file_order.data() + from * static_cast<std::int64_t>(width), width, dest);
    }
  return result;
}

OrientedAxes axesToRas(const std::array<glm::dvec3, 3>& directions, const std::string& source) {
  std::array<glm::dvec3, 3> unit;
  for (int c = 0; c < 3; ++c) {
    const double length = glm::length(directions[c]);
    if (!std::isfinite(length) || length <= 0)
      throw Error(fmt::format("{}: the orientation's axis {} is ({}, {}, {}); it must be finite "
                              "and non-zero",
                              source, "ijk"[c], directions[c].x, directions[c].y,
                              directions[c].z));
    unit[c] = directions[c] / length;
  }
  if (std::abs(glm::dot(glm::cross(unit[0], unit[1]), unit[2])) < 1e-3)
    throw Error(fmt::format("{}: the orientation's axes are (nearly) coplanar", source));
  OrientedAxes result;
  result.file_axes = "???";
  std::array<bool, 3> file_used{}, world_used{};
  // Greedy on the largest cosine, so that an oblique grid keeps its nearest axes.
  for (int round = 0; round < 3; ++round) {
    int best_c = 0, best_w = 0;
    double best = -1.0;
    for (int c = 0; c < 3; ++c)
      for (int w = 0; w < 3; ++w)
        if (!file_used[c] && !world_used[w] && std::abs(unit[c][w]) > best)
          best = std::abs(unit[c][w]), best_c = c, best_w = w;
    file_used[best_c] = world_used[best_w] = true;
    const bool backwards = unit[best_c][best_w] < 0;
    result.map.file_axis[best_w] = best_c;
    result.map.flip[best_w] = backwards;
    result.file_axes[best_c] = backwards ? "LPI"[best_w] : "RAS"[best_w];
    result.oblique_degrees =
        std::max(result.oblique_degrees, std::acos(std::min(1.0, best)) * 180 / std::numbers::pi);
  }
  return result;
}

}  // namespace svr
