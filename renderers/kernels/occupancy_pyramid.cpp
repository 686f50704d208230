#include "renderers/kernels/occupancy_pyramid.h"

#include <bit>

namespace svr {

OccupancyPyramid::OccupancyPyramid(const ClassifiedVolume& cv) {
  static_assert(std::has_single_bit(static_cast<unsigned>(ClassifiedVolume::kBlock)));
  Level base;
  base.shift = std::countr_zero(static_cast<unsigned>(ClassifiedVolume::kBlock));
  base.blocks = cv.blocks;
  base.occupancy = cv.block_occupied;
  levels_.push_back(std::move(base));
  while (levels_.back().blocks[0] > 1 || levels_.back().blocks[1] > 1 ||
         levels_.back().blocks[2] > 1) {
    const Level& child = levels_.back();
    Level parent;
    parent.shift = child.shift + 1;
    for (int a = 0; a < 3; ++a) parent.blocks[a] = (child.blocks[a] + 1) / 2;
    parent.occupancy.assign(
        static_cast<std::size_t>(parent.blocks[0]) * parent.blocks[1] * parent.blocks[2], 0);
    for (int z = 0; z < child.blocks[2]; ++z)
      for (int y = 0; y < child.blocks[1]; ++y)
        for (int x = 0; x < child.blocks[0]; ++x)
          if (child.occupied(x, y, z))
            parent.occupancy[(static_cast<std::size_t>(z / 2) * parent.blocks[1] + y / 2) *
                                 parent.blocks[0] +
                             x / 2] = 1;
    levels_.push_back(std::move(parent));
  }
}

std::shared_ptr<const OccupancyPyramid> occupancyOf(const ClassifiedVolume& cv) {
  return cv.derived->get<OccupancyPyramid>(
      "occupancy pyramid", [&] { return std::make_shared<const OccupancyPyramid>(cv); });
}

}  // namespace svr
