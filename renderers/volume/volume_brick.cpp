#include "renderers/volume/volume_brick.h"

#include <fmt/format.h>

#include <algorithm>
#include <glm/geometric.hpp>
#include <numeric>

#include "renderers/volume/volume_io.h"
#include "base/error.h"

namespace svr {
namespace {

// The estimated work of each slab of `box` across `axis` (one entry per voxel index from
// box.lo): each cell whose centre lies in the box on the other axes spreads its cost evenly over
// the voxels between the midpoints to its neighbours along `axis`.
std::vector<double> workProfile(const WorkGrid& work, const Dims& whole, const VoxelBox& box,
                                int axis) {
  const LatticeIndices at = latticeIndices(whole, work.cells);
  const int u = (axis + 1) % 3, v = (axis + 2) % 3;
  std::vector<double> profile(box.size()[axis], 0.0);
  const int n = static_cast<int>(at[axis].size());
  for (int m = 0; m < n; ++m) {
    const int from = m == 0 ? 0 : (at[axis][m - 1] + at[axis][m] + 1) / 2;
    const int to = m == n - 1 ? whole[axis] : (at[axis][m] + at[axis][m + 1] + 1) / 2;
    const int lo = std::max(from, box.lo[axis]), hi = std::min(to, box.hi[axis]);
    if (lo >= hi) continue;
    double slab = 0.0;
    for (std::size_t j = 0; j < at[u].size(); ++j) {
      if (at[u][j] < box.lo[u] || at[u][j] >= box.hi[u]) continue;
      for (std::size_t k = 0; k < at[v].size(); ++k) {
        if (at[v][k] < box.lo[v] || at[v][k] >= box.hi[v]) continue;
        std::array<std::size_t, 3> c{};
        c[axis] = m, c[u] = j, c[v] = k;
        slab += work.cost[(c[2] * work.cells[1] + c[1]) * work.cells[0] + c[0]];
      }
    }
    for (int i = lo; i < hi; ++i) profile[i - box.lo[axis]] += slab / (to - from);
  }
  return profile;
}

struct SplitRule {
  Dims whole;
  const WorkGrid* work;
  double max_voxels;  // per brick
};

// Where to cut `box` across `axis` so that the low side holds low_count of count bricks: the
// voxels' proportion, or the work's within the voxel cap.
int planeFor(const VoxelBox& box, int axis, int low_count, int count, const SplitRule& rule) {
  const Dims size = box.size();
  const int lo = box.lo[axis];
  const int by_voxels = lo + static_cast<int>((static_cast<long>(size[axis]) * low_count) / count);
  if (!rule.work) return by_voxels;
  const std::vector<double> profile = workProfile(*rule.work, rule.whole, box, axis);
  double total = 0.0;
  for (double w : profile) total += w;
  if (!(total > 0.0)) return by_voxels;
  // Each side holds at least a voxel per brick, and at most max_voxels per brick.
  const double slab_voxels = static_cast<double>(box.voxels()) / size[axis];
  const int earliest = std::max(lo + low_count,
      box.hi[axis] - static_cast<int>(rule.max_voxels * (count - low_count) / slab_voxels));
  const int latest = std::min(box.hi[axis] - (count - low_count),
      lo + static_cast<int>(rule.max_voxels * low_count / slab_voxels));
  if (earliest > latest) return by_voxels;
  const double target = total * low_count / count;
  double below = 0.0;
  int plane = lo;
  while (plane < box.hi[axis] && below + profile[plane - lo] <= target) below += profile[plane++ - lo];
  return std::clamp(plane, earliest, latest);
}

void split(const VoxelBox& box, int count, const SplitRule& rule,
           std::vector<KdBrick::Split>& path, std::vector<KdBrick>& out) {
  if (count == 1) {
    out.push_back({box, path});
    return;
  }
  const Dims size = box.size();
  int axis = 0;
  for (int a = 1; a < 3; ++a)
    if (size[a] > size[axis]) axis = a;
  const int low_count = count / 2;
  const int plane = planeFor(box, axis, low_count, count, rule);
  VoxelBox low = box, high = box;
  low.hi[axis] = plane;
  high.lo[axis] = plane;
  path.push_back({axis, plane, true});
  split(low, low_count, rule, path, out);
  path.back().low = false;
  split(high, count - low_count, rule, path, out);
  path.pop_back();
}

}  // namespace

std::vector<KdBrick> kdSplit(const Dims& dims, int count, const WorkGrid* work,
                             double max_share) {
  if (count < 1) throw Error(fmt::format("bricks: cannot split a volume into {} bricks", count));
  if (work) {
    bool fits = work->cost.size() ==
                static_cast<std::size_t>(work->cells[0]) * work->cells[1] * work->cells[2];
    for (int a = 0; a < 3; ++a) fits = fits && work->cells[a] >= 1 && work->cells[a] <= dims[a];
    if (!fits) throw Error("bricks: the work estimate is not of this volume");
  }
  std::vector<KdBrick> out;
  std::vector<KdBrick::Split> path;
  const VoxelBox whole{{0, 0, 0}, dims};
  split(whole, count, {dims, work, max_share * static_cast<double>(whole.voxels()) / count}, path, out);
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

}  // namespace svr
