#pragma once
// shearwarp.classification=pre (issue 17): VolPack's own method (Lacroute & Levoy 1994, §3)
// beside our post-classified default. Each stored voxel of an axis encoding (rle_volume.h) is
// classified and its normal quantised once, at the voxel:
//   [α, α·specular, α·ρ_0 … α·ρ_{k−1}, t_0 … t_{kt−1}]   (classification step Δs)
// plus a 14-bit octahedral normal index. A sample interpolates these classified records
// bilinearly — pre-classification: the colour of the interpolated voxels, not the voxel values'
// interpolated colour — and is shaded from a per-view table over the normal indices
// (ShadingTable), as VolPack's vpShadeTable. The slice spacing correction, α' = 1 − (1 − α)^r
// and t' = t^r with r = slice spacing / Δs, is applied to the interpolated α and t through
// per-view tables (PowerTable). The records share the runs and row segments of the post-classified
// encoding (its occupancy criterion covers every voxel with α > 0), indexed alike.
//
// What it costs in accuracy is charted by svr compare's variant row (svr demo runs it).

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "renderers/memory/block_arena.h"
#include "renderers/classification/classification.h"
#include "renderers/classification/classified_sample.h"
#include "renderers/shearwarp/rle_volume.h"

namespace svr::shearwarp {

// Octahedral normal indices, kNormalSide steps per coordinate (within 1.8° of the gradient's
// direction; VolPack quantises to 13 bits); kFlatNormal, one past them, marks a vanishing
// gradient (full light, no highlight, as phong()). 128² entries keep the per-view table
// (interleaved shade and highlight, 128 KiB) in L2: at 256² (512 KiB in two arrays) its
// lookups missed.
inline constexpr int kNormalSide = 128;
inline constexpr std::uint16_t kFlatNormal = kNormalSide * kNormalSide;
std::uint16_t encodeNormal(const float g[3]);
void decodeNormal(std::uint16_t index, float n[3]);
// encodeNormal of each record's gradient, four at a time.
void encodeNormals(std::span<const VoxelRecord> voxels, std::uint16_t* normals);

class PreclassifiedAxis {
 public:
  // Keeps `encoded` (whose axis encoding it indexes) alive.
  PreclassifiedAxis(const ClassifiedVolume& cv, std::shared_ptr<const RleVolume> encoded,
                    int axis);
  // The classification's instance for this axis, built on first use and cached on it.
  static std::shared_ptr<const PreclassifiedAxis> of(const ClassifiedVolume& cv, int axis);

  int stride() const { return stride_; }  // floats per record (2 + k + kt, padded to 4)
  // Slice k's classified records and normal indices, one per voxel record of the axis
  // encoding and in its order (CellRun::record0 / record1 index them).
  const float* sliceRecords(int k) const { return records_[k]; }
  const std::uint16_t* sliceNormals(int k) const { return normals_[k]; }
  std::size_t bytes() const;

 private:
  std::shared_ptr<const RleVolume> encoded_;
  const AxisEncoding* encoding_;
  int stride_;
  // Per slice, in the order of the axis encoding's records, in arena_.
  std::vector<const float*> records_;
  std::vector<const std::uint16_t*> normals_;
  BlockArena arena_;
};

// Per view: shade and highlight (phong()'s terms) of every normal index, interleaved.
struct ShadingTable {
  std::vector<float> terms;  // 2 × (kFlatNormal + 1): shade, highlight of index i at 2i, 2i + 1
  explicit ShadingTable(const PhongSetup& phong);
};

// Sign-preserving power, the slice-spacing correction of both classification modes: factor-
// model transmission coefficients may dip slightly below zero, where a plain pow of a
// fractional exponent would give NaN.
inline float signedPow(double x, double r) {
  return static_cast<float>(std::copysign(std::pow(std::abs(x), r), x));
}

// x ↦ signedPow(x, r), tabulated over [lo, hi] with linear interpolation (clamped outside).
class PowerTable {
 public:
  PowerTable(float lo, float hi, double r);
  float operator()(float x) const {
    const float p = std::clamp((x - lo_) * inv_step_, 0.f, static_cast<float>(kSteps));
    const int i = std::min(static_cast<int>(p), kSteps - 1);
    return values_[i] + (p - static_cast<float>(i)) * (values_[i + 1] - values_[i]);
  }
  static constexpr int kSteps = 4096;

 private:
  float lo_, inv_step_;
  std::vector<float> values_;
};

}  // namespace svr::shearwarp
