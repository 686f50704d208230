#include "renderers/shearwarp/rle_volume.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "renderers/core/classified_sample.h"
#include "renderers/core/volume.h"
#include "spectral/error.h"

namespace svr::shearwarp {
namespace {

std::size_t indexOf(const Dims& d, int x, int y, int z) {
  return (static_cast<std::size_t>(z) * d[1] + y) * d[0] + x;
}

// A voxel row of one slice as strides into the volume: voxel i of the row is at
// base + i · step_i; the neighbours along the three axes are ± stride[a].
struct RowAddress {
  std::size_t base;
  std::ptrdiff_t step_i;
};

// The bins a voxel's value can blend (cellOccupied's floor and ceil, per voxel: the floor of a
// cell's minimum is the minimum of its corners' floors, the ceiling of its maximum the maximum
// of their ceilings), or for label maps whether the label is visible (lo = hi = 0 or 1 against
// a prefix of [0, 0, 1]).
struct BinRange {
  std::int32_t lo, hi;
};

void rowBins(const ClassifiedVolume& cv, const RowAddress& row, int n, BinRange* out) {
  if (cv.labels) {
    for (int i = 0; i < n; ++i) {
      const int visible = cv.alpha[cv.label[row.base + i * row.step_i]] > 0.f;
      out[i] = {visible, visible};
    }
    return;
  }
  const int last = cv.entries - 1;
  const double lo = cv.value_lo, scale = cv.value_scale, top = last;
  for (int i = 0; i < n; ++i) {
    // floor and ceil clamped to [0, last], by truncation (std::floor is a libm call on the
    // baseline x86-64 target): the same integers for every bin.
    const double bin = std::clamp((cv.values[row.base + i * row.step_i] - lo) * scale, 0.0, top);
    const int down = static_cast<int>(bin);
    out[i] = {down, down + (static_cast<double>(down) < bin ? 1 : 0)};
  }
}

// The voxel records of voxels lo .. hi of a row: bin coordinate (or label) and the central differences
// of the shading field, clamped at the border as the raycaster's, in world units.
void appendRowRecords(const ClassifiedVolume& cv, const int p0[3], int axis_i, int lo, int hi,
                      std::vector<VoxelRecord>& out) {
  const Dims& d = cv.dims;
  const std::size_t stride[3] = {1, static_cast<std::size_t>(d[0]),
                                 static_cast<std::size_t>(d[0]) * d[1]};
  const float* f = cv.shadingField().data();
  const float half_inv[3] = {static_cast<float>(0.5 / cv.spacing.x),
                             static_cast<float>(0.5 / cv.spacing.y),
                             static_cast<float>(0.5 / cv.spacing.z)};
  int p[3] = {p0[0], p0[1], p0[2]};
  for (int i = lo; i <= hi; ++i) {
    p[axis_i] = i;
    const std::size_t index = p[0] * stride[0] + p[1] * stride[1] + p[2] * stride[2];
    VoxelRecord rec;
    rec.bin = cv.labels ? static_cast<float>(cv.label[index]) : binCoordinate(cv, cv.values[index]);
    for (int a = 0; a < 3; ++a) {
      const std::size_t down = p[a] > 0 ? stride[a] : 0;
      const std::size_t up = p[a] + 1 < d[a] ? stride[a] : 0;
      rec.gradient[a] = (f[index + up] - f[index - down]) * half_inv[a];
    }
    out.push_back(rec);
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
  // Label maps classify each corner alone: a cell is occupied when any corner's label is
  // visible, a prefix over the two "bins" 0 (hidden) and 1 (visible).
  const std::vector<int> prefix = cv.labels ? std::vector<int>{0, 0, 1} : nonzeroOpacityPrefix(cv);
  const std::size_t stride[3] = {1, static_cast<std::size_t>(cv.dims[0]),
                                 static_cast<std::size_t>(cv.dims[0]) * cv.dims[1]};
  slices_.resize(n_k_);
  const bool parallel =
      static_cast<std::int64_t>(n_i_) * n_j_ * n_k_ >= kParallelVoxels;
#pragma omp parallel if (parallel)
  {
    std::vector<BinRange> below(n_i_), above(n_i_);
    std::vector<std::uint8_t> occupied(n_i_);
#pragma omp for schedule(dynamic)
    for (int k = 0; k < n_k_; ++k) {
      SliceEncoding& s = slices_[k];
      s.run_offsets.assign(n_j_, 0);
      const auto rowOf = [&](int j) {
        return RowAddress{k * stride[axis_] + j * stride[axis_j_],
                          static_cast<std::ptrdiff_t>(stride[axis_i_])};
      };
      rowBins(cv, rowOf(0), n_i_, below.data());
      for (int j = 0; j + 1 < n_j_; ++j) {
        s.run_offsets[j] = static_cast<std::int32_t>(s.runs.size());
        rowBins(cv, rowOf(j + 1), n_i_, above.data());
        // Cell i spans voxels i, i + 1 of rows j, j + 1: the range of their bins.
        for (int i = 0; i + 1 < n_i_; ++i) {
          const int b0 = std::min({below[i].lo, below[i + 1].lo, above[i].lo, above[i + 1].lo});
          const int b1 = std::max({below[i].hi, below[i + 1].hi, above[i].hi, above[i + 1].hi});
          occupied[i] = prefix[b1 + 1] - prefix[b0] > 0;
        }
        for (int i = 0; i + 1 < n_i_; ++i) {
          if (!occupied[i]) continue;
          const int begin = i;
          while (i + 1 < n_i_ && occupied[i]) ++i;
          s.runs.push_back({begin, i});
        }
        std::swap(below, above);
      }
      s.run_offsets[n_j_ - 1] = static_cast<std::int32_t>(s.runs.size());
      // Voxel row j is touched by the cells of cell rows j − 1 and j.
      s.rows.resize(n_j_);
      int p[3];
      p[axis_] = k;
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
        appendRowRecords(cv, p, axis_i_, lo, hi, s.records);
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
