#include "renderers/core/volume_brick.h"

#include <fmt/format.h>

#include <algorithm>
#include <glm/geometric.hpp>
#include <numeric>

#include "spectral/error.h"

namespace svr {
namespace {

void split(const VoxelBox& box, int count, std::vector<KdBrick::Split>& path,
           std::vector<KdBrick>& out) {
  if (count == 1) {
    out.push_back({box, path});
    return;
  }
  const Dims size = box.size();
  int axis = 0;
  for (int a = 1; a < 3; ++a)
    if (size[a] > size[axis]) axis = a;
  const int low_count = count / 2;
  // The plane shares the voxels in the proportion of the bricks on either side.
  const int plane =
      box.lo[axis] + static_cast<int>((static_cast<long>(size[axis]) * low_count) / count);
  VoxelBox low = box, high = box;
  low.hi[axis] = plane;
  high.lo[axis] = plane;
  path.push_back({axis, plane, true});
  split(low, low_count, path, out);
  path.back().low = false;
  split(high, count - low_count, path, out);
  path.pop_back();
}

// Whether brick a's image lies in front of brick b's: decided at the first plane that separates
// them (they share the path above it).
bool inFront(const KdBrick& a, const KdBrick& b, const Camera& camera, const RayGenerator& rays,
             const Dims& whole, const glm::dvec3& spacing) {
  for (std::size_t i = 0; i < std::min(a.path.size(), b.path.size()); ++i) {
    if (a.path[i].low == b.path[i].low) continue;
    const int axis = a.path[i].axis;
    // The plane in world space (DESIGN §7: voxel i at (i − (dims − 1)/2) · spacing).
    const double plane = (a.path[i].plane - 0.5 * (whole[axis] - 1)) * spacing[axis];
    const bool low_first = camera.orthographic() ? rays.forward()[axis] >= 0.0
                                                 : camera.eye[axis] <= plane;
    return a.path[i].low == low_first;
  }
  return false;
}

}  // namespace

std::vector<KdBrick> kdSplit(const Dims& dims, int count) {
  if (count < 1) throw Error(fmt::format("bricks: cannot split a volume into {} bricks", count));
  std::vector<KdBrick> out;
  std::vector<KdBrick::Split> path;
  split({{0, 0, 0}, dims}, count, path, out);
  for (const KdBrick& b : out)
    for (int a = 0; a < 3; ++a)
      if (b.own.hi[a] <= b.own.lo[a])
        throw Error(fmt::format("bricks: a {}×{}×{} volume is too small for {} bricks (a brick "
                                "would hold no voxels along {})",
                                dims[0], dims[1], dims[2], count, "xyz"[a]));
  return out;
}

VolumeBrick brickOf(const Dims& whole, const VoxelBox& own) {
  VolumeBrick brick;
  brick.whole = whole;
  brick.own = own;
  for (int a = 0; a < 3; ++a) {
    brick.stored.lo[a] = std::max(own.lo[a] - kGhostLayers, 0);
    brick.stored.hi[a] = std::min(own.hi[a] + kGhostLayers, whole[a]);
  }
  return brick;
}

VoxelBox ownInStored(const VolumeBrick& brick) {
  VoxelBox box;
  for (int a = 0; a < 3; ++a) {
    box.lo[a] = brick.own.lo[a] - brick.stored.lo[a];
    box.hi[a] = brick.own.hi[a] - brick.stored.lo[a];
  }
  return box;
}

std::pair<double, double> mergeRanges(std::pair<double, double> a, std::pair<double, double> b) {
  return {std::min(a.first, b.first), std::max(a.second, b.second)};
}

FieldRange mergeRanges(const FieldRange& a, const FieldRange& b) {
  return {std::min(a.lo, b.lo), std::max(a.hi, b.hi), std::max(a.largest, b.largest)};
}

Volume cropToBrick(const Volume& whole, const VolumeBrick& brick) {
  const std::size_t w = bytesPerVoxel(whole.type());
  const VoxelBox& box = brick.stored;
  const Dims size = box.size();
  std::vector<std::byte> bytes(box.voxels() * w);
  std::byte* dest = bytes.data();
  for (int z = box.lo[2]; z < box.hi[2]; ++z)
    for (int y = box.lo[1]; y < box.hi[1]; ++y) {
      const std::byte* src = whole.data().data() + whole.index(box.lo[0], y, z) * w;
      std::copy(src, src + size[0] * w, dest);
      dest += size[0] * w;
    }
  Volume out(size, whole.spacing(), whole.type(), std::move(bytes), whole.source());
  out.setBrick(brick);
  return out;
}

std::vector<int> visibilityOrder(const std::vector<KdBrick>& bricks, const Camera& camera,
                                 const Dims& whole, const glm::dvec3& spacing) {
  const RayGenerator rays(camera, 1, 1);
  std::vector<int> order(bricks.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return inFront(bricks[a], bricks[b], camera, rays, whole, spacing);
  });
  return order;
}

}  // namespace svr
