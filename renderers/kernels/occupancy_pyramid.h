#pragma once
// Empty-space skipping over a min–max octree: the classification's occupancy of
// ClassifiedVolume::kBlock³-voxel blocks (4³; block_occupied, level 0) and coarser levels of
// 8³, 16³, … voxels, each occupied when any of its eight children is. A ray in empty space
// jumps to the exit of the largest empty block around it, rather than from one block to the
// next: on the engine at 512² a ray crossed some 13 empty 8³ blocks one by one.

#include <cstdint>
#include <memory>
#include <vector>

#include "renderers/classification/classification.h"

namespace svr {

class OccupancyPyramid {
 public:
  explicit OccupancyPyramid(const ClassifiedVolume& cv);

  // The coarsest level whose block holding the voxel cell (x, y, z) is empty, or −1 when the
  // level-0 block is occupied (samples there must be taken). Coordinates are cell origins:
  // the floor of a sample position, clamped to the grid.
  int emptyLevel(int x, int y, int z) const {
    int level = -1;
    for (int l = 0; l < static_cast<int>(levels_.size()); ++l) {
      if (levels_[l].occupied(x >> levels_[l].shift, y >> levels_[l].shift, z >> levels_[l].shift))
        break;
      level = l;
    }
    return level;
  }
  // log2 of the edge, in voxels, of a block at `level`.
  int shift(int level) const { return levels_[level].shift; }

 private:
  struct Level {
    int shift = 0;
    Dims blocks{0, 0, 0};
    std::vector<std::uint8_t> occupancy;
    bool occupied(int bx, int by, int bz) const {
      bx = bx < blocks[0] ? bx : blocks[0] - 1;
      by = by < blocks[1] ? by : blocks[1] - 1;
      bz = bz < blocks[2] ? bz : blocks[2] - 1;
      return occupancy[(static_cast<std::size_t>(bz) * blocks[1] + by) * blocks[0] + bx] != 0;
    }
  };
  std::vector<Level> levels_;
};

// The pyramid of cv, built on first use and kept with the classification.
std::shared_ptr<const OccupancyPyramid> occupancyOf(const ClassifiedVolume& cv);

}  // namespace svr
