#include "renderers/shearwarp/rle_volume.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "spectral/error.h"

namespace svr::shearwarp {
namespace {

std::size_t indexOf(const Dims& d, int x, int y, int z) {
  return (static_cast<std::size_t>(z) * d[1] + y) * d[0] + x;
}

// Central differences of the shading field at a voxel, with the raycaster's clamping at the
// border, in world units: bilinear interpolation of these inside a slice equals the
// raycaster's central difference of the trilinear field at the same point.
void gradientAt(const ClassifiedVolume& cv, const int p[3], float g[3]) {
  for (int a = 0; a < 3; ++a) {
    int lo[3] = {p[0], p[1], p[2]}, hi[3] = {p[0], p[1], p[2]};
    lo[a] = std::max(p[a] - 1, 0);
    hi[a] = std::min(p[a] + 1, cv.dims[a] - 1);
    const float f1 = cv.shadingField()[indexOf(cv.dims, hi[0], hi[1], hi[2])];
    const float f0 = cv.shadingField()[indexOf(cv.dims, lo[0], lo[1], lo[2])];
    g[a] = static_cast<float>((f1 - f0) * 0.5 / cv.spacing[a]);
  }
}

}  // namespace

std::vector<int> nonzeroOpacityPrefix(const ClassifiedVolume& cv) {
  std::vector<int> prefix(cv.entries + 1, 0);
  for (int e = 0; e < cv.entries; ++e) prefix[e + 1] = prefix[e] + (cv.alpha[e] > 0.f);
  return prefix;
}

bool cellOccupied(const ClassifiedVolume& cv, std::span<const int> nonzero_prefix, int x, int y,
                  int z, int a, int b) {
  float vmin = INFINITY, vmax = -INFINITY;
  for (int n = 0; n < 4; ++n) {
    int p[3] = {x, y, z};
    p[a] += n & 1;
    p[b] += (n >> 1) & 1;
    const std::size_t i = indexOf(cv.dims, p[0], p[1], p[2]);
    if (cv.labels) {
      if (cv.alpha[cv.label[i]] > 0.f) return true;
    } else {
      vmin = std::min(vmin, cv.values[i]);
      vmax = std::max(vmax, cv.values[i]);
    }
  }
  if (cv.labels) return false;
  // Every bilinear sample lies in [vmin, vmax]; its table lookup blends bins floor..ceil (a
  // bin hit exactly takes its upper neighbour with weight 0).
  const int last = cv.entries - 1;
  const int b0 = std::clamp(
      static_cast<int>(std::floor((vmin - cv.value_lo) * cv.value_scale)), 0, last);
  const int b1 = std::clamp(
      static_cast<int>(std::ceil((vmax - cv.value_lo) * cv.value_scale)), 0, last);
  return nonzero_prefix[b1 + 1] - nonzero_prefix[b0] > 0;
}

AxisEncoding::AxisEncoding(const ClassifiedVolume& cv, int axis)
    : axis_(axis), axis_i_((axis + 1) % 3), axis_j_((axis + 2) % 3) {
  // Keep x fastest inside a row where possible: for z slices rows run along x, for y slices
  // along x too (rows are then contiguous in memory); x slices run along y.
  if (axis == 1) std::swap(axis_i_, axis_j_);
  n_i_ = cv.dims[axis_i_];
  n_j_ = cv.dims[axis_j_];
  n_k_ = cv.dims[axis_];
  if (n_i_ < 2 || n_j_ < 2)
    throw Error(fmt::format("shearwarp: a {}×{}×{} volume is too thin to shear (at least 2 "
                            "voxels along each axis)",
                            cv.dims[0], cv.dims[1], cv.dims[2]));
  const std::vector<int> prefix = nonzeroOpacityPrefix(cv);
  slices_.resize(n_k_);
#pragma omp parallel for schedule(dynamic)
  for (int k = 0; k < n_k_; ++k) {
    SliceEncoding& s = slices_[k];
    s.run_offsets.assign(n_j_, 0);
    int p[3];
    p[axis_] = k;
    for (int j = 0; j + 1 < n_j_; ++j) {
      s.run_offsets[j] = static_cast<std::int32_t>(s.runs.size());
      p[axis_j_] = j;
      bool open = false;
      for (int i = 0; i + 1 < n_i_; ++i) {
        p[axis_i_] = i;
        const bool occupied = cellOccupied(cv, prefix, p[0], p[1], p[2], axis_i_, axis_j_);
        if (occupied && !open) s.runs.push_back({i, i + 1});
        if (occupied) s.runs.back().end = i + 1;
        open = occupied;
      }
    }
    s.run_offsets[n_j_ - 1] = static_cast<std::int32_t>(s.runs.size());
    // Voxel row j is touched by the cells of cell rows j − 1 and j.
    s.rows.resize(n_j_);
    for (int j = 0; j < n_j_; ++j) {
      int lo = n_i_, hi = -1;
      for (int cj = std::max(j - 1, 0); cj <= std::min(j, n_j_ - 2); ++cj) {
        const auto first = s.runs.begin() + s.run_offsets[cj];
        const auto last = s.runs.begin() + s.run_offsets[cj + 1];
        if (first == last) continue;
        lo = std::min(lo, first->begin);
        hi = std::max(hi, (last - 1)->end);  // cell end − 1 + its right voxel
      }
      RowSpan& r = s.rows[j];
      r.offset = s.records.size();
      if (hi < lo) continue;
      r.lo = lo;
      r.count = hi - lo + 1;
      p[axis_j_] = j;
      for (int i = lo; i <= hi; ++i) {
        p[axis_i_] = i;
        VoxelRecord rec;
        const std::size_t index = indexOf(cv.dims, p[0], p[1], p[2]);
        rec.value = cv.labels ? static_cast<float>(cv.label[index]) : cv.values[index];
        gradientAt(cv, p, rec.gradient);
        s.records.push_back(rec);
      }
    }
  }
}

std::size_t AxisEncoding::bytes() const {
  std::size_t n = 0;
  for (const SliceEncoding& s : slices_)
    n += s.run_offsets.size() * sizeof(std::int32_t) + s.runs.size() * sizeof(CellRun) +
         s.rows.size() * sizeof(RowSpan) + s.records.size() * sizeof(VoxelRecord);
  return n;
}

std::size_t AxisEncoding::storedVoxels() const {
  std::size_t n = 0;
  for (const SliceEncoding& s : slices_) n += s.records.size();
  return n;
}

RleVolume::RleVolume(const ClassifiedVolume& cv) : cv_(cv) {}

std::shared_ptr<const RleVolume> RleVolume::of(const ClassifiedVolume& cv) {
  return cv.derived->get<RleVolume>("shearwarp.rle",
                                    [&] { return std::make_shared<const RleVolume>(cv); });
}

const AxisEncoding& RleVolume::encoding(int axis) const {
  std::call_once(once_[axis], [&] { axes_[axis] = std::make_unique<AxisEncoding>(cv_, axis); });
  return *axes_[axis];
}

void RleVolume::buildAll() const {
  for (int a = 0; a < 3; ++a) encoding(a);
}

}  // namespace svr::shearwarp
