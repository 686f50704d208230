#pragma once
// The box a brick of a distributed render owns and holds (renderers/volume/volume_brick.h makes
// them), kept on its Volume and ClassifiedVolume so that backends sample it in the whole grid's
// coordinates.

#include <array>
#include <cstddef>
#include <optional>
#include <utility>
#include <vector>

namespace svr {

using Dims = std::array<int, 3>;

// Voxels lo ≤ index < hi on every axis.
struct VoxelBox {
  Dims lo{0, 0, 0}, hi{0, 0, 0};
  Dims size() const { return {hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]}; }
  std::size_t voxels() const {
    const Dims s = size();
    return static_cast<std::size_t>(s[0]) * s[1] * s[2];
  }
  bool operator==(const VoxelBox&) const = default;
};

// The whole grid's range of the field a brick's gradients quantise to (GradientVolume), so that
// every brick quantises as the whole volume would.
struct FieldRange {
  float lo = 0.f, hi = 0.f;  // of the shading field
  float largest = 0.f;       // the largest gradient component
};

// Where a render's work lies: the samples a ray caster shades, counted per cell of a coarse
// lattice of the grid (the lattice of latticeIndices(dims, cells), renderers/volume/volume_io.h;
// render/work_estimate.h makes it). kdSplit shares this out instead of voxels.
struct WorkGrid {
  Dims cells{0, 0, 0};
  std::vector<float> cost;  // per cell, x fastest
};

struct VolumeBrick {
  Dims whole{0, 0, 0};  // dims of the whole grid
  VoxelBox own;         // the voxels whose samples this brick renders
  VoxelBox stored;      // the voxels it holds: own plus kGhost layers inside the grid
  // Set by the distribution once every brick is read: the whole volume's value range (the
  // classification's bins) and, once classified, its shading field's range (the gradients).
  std::optional<std::pair<double, double>> whole_range;
  std::optional<FieldRange> whole_field;
};

}  // namespace svr
