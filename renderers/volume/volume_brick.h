#pragma once
// Bricks of a volume for a distributed render (design.md §5b): a kd-split of the whole grid into N
// boxes, one per process, each held with the ghost layers its samples need. The order in which
// their images composite for a camera is renderers/render/brick_order.h.
//
// A brick owns the samples whose position p (voxel coordinates of the whole grid) lies in
// own.lo ≤ p < own.hi on every axis, except that the last brick along an axis also owns
// p = dims − 1. The boxes tile the grid, so every sample a whole-volume render takes is taken
// by exactly one brick, at the same position: composited in visibility order, the bricks' images
// are the whole render to the rounding of the compositing order.

#include <vector>

#include "renderers/volume/brick_box.h"
#include "renderers/volume/volume.h"

namespace svr {

// Ghost layers on each side: a sample's trilinear cell reaches one voxel past it, and central
// differences at its corners (precomputed or on the fly) one more.
inline constexpr int kGhostLayers = 2;

// One brick of a kd-split: its box and the kd tree's planes above it.
struct KdBrick {
  VoxelBox own;
  // The split planes from the root down: axis, plane index, and whether this brick lies on the
  // low side (index < plane).
  struct Split {
    int axis, plane;
    bool low;
  };
  std::vector<Split> path;
};

// Splits `dims` into `count` boxes: the box is cut across its longest axis (the lowest such axis
// on ties) into parts holding ⌊n/2⌋ and ⌈n/2⌉ bricks, at the plane that shares its voxels in that
// proportion — or, given a work estimate, its work, as long as no brick holds more than
// `max_share` times 1/count of the voxels (memory stays near 1/N). Throws svr::Error when
// count < 1 or an axis would get a brick under one voxel thick.
std::vector<KdBrick> kdSplit(const Dims& dims, int count, const WorkGrid* work = nullptr,
                             double max_share = 1.25);

// The brick as held by a process: `own` plus the ghost layers that lie inside the grid.
VolumeBrick brickOf(const Dims& whole, const VoxelBox& own);

// The own box in the index space of the stored voxels (what the brick's Volume indexes).
VoxelBox ownInStored(const VolumeBrick& brick);

// What bricks' ranges combine to: the whole volume's.
std::pair<double, double> mergeRanges(std::pair<double, double> a, std::pair<double, double> b);
FieldRange mergeRanges(const FieldRange& a, const FieldRange& b);

// The brick's stored voxels cut out of a whole volume, carrying the brick (procedural volumes,
// which are made whole, and tests).
Volume cropToBrick(const Volume& whole, const VolumeBrick& brick);

}  // namespace svr
