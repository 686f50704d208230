#include "renderers/shearwarp/preclassified_axis.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "renderers/core/classified_sample.h"
#include "renderers/core/volume.h"

namespace svr::shearwarp {

// Octahedral mapping (Meyer et al. 2010): the unit sphere folded onto [−1, 1]², kNormalSide
// steps a side.
std::uint16_t encodeNormal(const float g[3]) {
  const float len1 = std::abs(g[0]) + std::abs(g[1]) + std::abs(g[2]);
  const float len2 = std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
  if (!(len2 > 1e-6f)) return kFlatNormal;
  float x = g[0] / len1, y = g[1] / len1;
  if (g[2] < 0.f) {
    const float fx = (1.f - std::abs(y)) * (x >= 0.f ? 1.f : -1.f);
    const float fy = (1.f - std::abs(x)) * (y >= 0.f ? 1.f : -1.f);
    x = fx, y = fy;
  }
  constexpr float kTop = kNormalSide - 1;
  const auto q = [&](float c) {
    return static_cast<int>(std::clamp(std::lround((c * 0.5f + 0.5f) * kTop), 0l,
                                       static_cast<long>(kTop)));
  };
  return static_cast<std::uint16_t>(q(y) * kNormalSide + q(x));
}

void decodeNormal(std::uint16_t index, float n[3]) {
  constexpr float kTop = kNormalSide - 1;
  float x = static_cast<float>(index % kNormalSide) / kTop * 2.f - 1.f;
  float y = static_cast<float>(index / kNormalSide) / kTop * 2.f - 1.f;
  const float z = 1.f - std::abs(x) - std::abs(y);
  if (z < 0.f) {
    const float fx = (1.f - std::abs(y)) * (x >= 0.f ? 1.f : -1.f);
    const float fy = (1.f - std::abs(x)) * (y >= 0.f ? 1.f : -1.f);
    x = fx, y = fy;
  }
  const float len = std::sqrt(x * x + y * y + z * z);
  n[0] = x / len, n[1] = y / len, n[2] = z / len;
}

PreclassifiedAxis::PreclassifiedAxis(const ClassifiedVolume& cv,
                                     std::shared_ptr<const RleVolume> encoded, int axis)
    : encoded_(std::move(encoded)),
      encoding_(&encoded_->encoding(axis)),
      stride_((2 + cv.k + cv.t_channels + 3) / 4 * 4) {
  const AxisEncoding& encoding = *encoding_;
  const int k = cv.k, kt = cv.t_channels, n_k = encoding.slices(), n_j = encoding.rowCount();
  records_.resize(n_k);
  normals_.resize(n_k);
  // Classifying and encoding a voxel costs some 30 times what the loops kParallelVoxels was
  // chosen for do per voxel: in parallel from an eighth of it (the engine stores about 3 M).
  const bool parallel =
      encoding.storedVoxels() >= static_cast<std::size_t>(kParallelVoxels) / 8;
#pragma omp parallel for schedule(dynamic) if (parallel)
  for (int s = 0; s < n_k; ++s) {
    std::size_t count = 0;
    for (int j = 0; j < n_j; ++j) count += encoding.row(s, j).count;
    records_[s].assign(count * stride_, 0.f);
    normals_[s].resize(count);
    for (int j = 0; j < n_j; ++j) {
      const RowSpan& row = encoding.row(s, j);
      const VoxelRecord* voxels = encoding.rowRecords(s, j);
      for (int i = row.lo; i < row.lo + row.count; ++i) {
        const std::size_t at = row.offset + (i - row.lo);
        float* r = &records_[s][at * stride_];
        normals_[s][at] = encodeNormal(voxels[i].gradient);
        // The voxel's own classification: its label's entry, or its value's two bins.
        int e[2] = {0, 0};
        float w[2] = {1.f, 0.f};
        if (cv.labels) {
          e[0] = e[1] = static_cast<int>(voxels[i].bin);
        } else {
          entriesOfBin(cv, voxels[i].bin, e[0], e[1], w[1]);
          w[0] = 1.f - w[1];
        }
        for (int n = 0; n < 2; ++n) {
          const float a = w[n] * cv.alpha[e[n]];
          r[0] += a;
          r[1] += a * cv.specular[e[n]];
          for (int c = 0; c < k; ++c)
            r[2 + c] += a * cv.reflectance[static_cast<std::size_t>(e[n]) * k + c];
          for (int c = 0; c < kt; ++c)
            r[2 + k + c] += w[n] * cv.transmission[static_cast<std::size_t>(e[n]) * kt + c];
        }
      }
    }
  }
}

std::shared_ptr<const PreclassifiedAxis> PreclassifiedAxis::of(const ClassifiedVolume& cv,
                                                               int axis) {
  static const char* const kKeys[3] = {"shearwarp.pre.x", "shearwarp.pre.y", "shearwarp.pre.z"};
  // The encoding first: the cache is not re-entrant (a get inside a get's builder deadlocks).
  auto encoded = RleVolume::of(cv);
  encoded->encoding(axis);
  return cv.derived->get<PreclassifiedAxis>(kKeys[axis], [&] {
    return std::make_shared<const PreclassifiedAxis>(cv, encoded, axis);
  });
}

std::size_t PreclassifiedAxis::bytes() const {
  std::size_t n = 0;
  for (std::size_t s = 0; s < records_.size(); ++s)
    n += records_[s].size() * sizeof(float) + normals_[s].size() * sizeof(std::uint16_t);
  return n;
}

ShadingTable::ShadingTable(const PhongSetup& phong) : terms(2 * (kFlatNormal + 1)) {
  for (int i = 0; i <= kFlatNormal; ++i) {
    float n[3] = {0.f, 0.f, 0.f};
    if (i != kFlatNormal) decodeNormal(static_cast<std::uint16_t>(i), n);
    const PhongTerms t = svr::phong(phong, n);
    terms[2 * i] = t.shade;
    terms[2 * i + 1] = t.highlight;
  }
}

PowerTable::PowerTable(float lo, float hi, double r)
    : lo_(lo), inv_step_(hi > lo ? kSteps / (hi - lo) : 0.f), values_(kSteps + 1) {
  for (int i = 0; i <= kSteps; ++i) {
    const double x = lo + (hi - lo) * static_cast<double>(i) / kSteps;
    values_[i] = signedPow(x, r);
  }
}

}  // namespace svr::shearwarp
