#include "renderers/kernels/occupancy_pyramid.h"

#include <gtest/gtest.h>

namespace svr {
namespace {

// A 64³ grid of 4³ blocks (16³ of them) where only block (15, 0, 0) — voxels x 60..63 — is
// occupied: each level's block is empty exactly when it does not contain that one.
TEST(OccupancyPyramid, EmptyLevelIsTheLargestEmptyBlockAround) {
  ClassifiedVolume cv;
  const int B = ClassifiedVolume::kBlock;
  cv.dims = {64, 64, 64};
  cv.blocks = {64 / B, 64 / B, 64 / B};
  cv.block_occupied.assign(static_cast<std::size_t>(cv.blocks[0]) * cv.blocks[1] * cv.blocks[2], 0);
  cv.block_occupied[cv.blocks[0] - 1] = 1;
  const OccupancyPyramid pyramid(cv);
  EXPECT_EQ(pyramid.emptyLevel(61, 1, 1), -1);  // inside the occupied block
  // Voxel (0, 0, 0): its blocks of 4, 8, 16 and 32 voxels are empty; the 64-voxel one holds the
  // occupied block.
  const int level = pyramid.emptyLevel(0, 0, 0);
  ASSERT_GE(level, 0);
  EXPECT_EQ(1 << pyramid.shift(level), 32);
  // Voxel (56, 0, 0): the 4- and 8-voxel blocks (56..59, 56..63) — the 8 holds 60..63: so 4.
  EXPECT_EQ(1 << pyramid.shift(pyramid.emptyLevel(56, 0, 0)), B);
  // Far corner (63, 63, 63): its 32-voxel block (32..63)³ does not hold y = 0.
  EXPECT_EQ(1 << pyramid.shift(pyramid.emptyLevel(63, 63, 63)), 32);
}

}  // namespace
}  // namespace svr
