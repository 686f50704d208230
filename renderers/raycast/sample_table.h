#pragma once
// The classification's entries laid out for the raycaster's blend: one row per entry,
//   [α, α·specular, α·ρ_0 … α·ρ_{k−1}, t_0 … t_{kt−1}],
// contiguous, so that a sample's two (or eight) entries are two (eight) short rows, and the
// opacity-weighted blend of blendEntries needs no division: a sample adds
// T ⊙ (shade · Σ w α ρ + highlight · Σ w α s · white), which is blendEntries' α · (ρ̄ · shade +
// s̄ · highlight · white) with the normalisation by α cancelled.

#include <memory>
#include <vector>

#include "renderers/core/classification.h"

namespace svr::raycast {

struct SampleTable {
  int k = 0, kt = 0;
  int stride = 0;  // 2 + k + kt
  std::vector<float> rows;

  explicit SampleTable(const ClassifiedVolume& cv)
      : k(cv.k), kt(cv.t_channels), stride(2 + cv.k + cv.t_channels) {
    rows.resize(static_cast<std::size_t>(cv.entries) * stride);
    for (int e = 0; e < cv.entries; ++e) {
      float* row = &rows[static_cast<std::size_t>(e) * stride];
      const float a = cv.alpha[e];
      row[0] = a;
      row[1] = a * cv.specular[e];
      for (int c = 0; c < k; ++c) row[2 + c] = a * cv.reflectance[static_cast<std::size_t>(e) * k + c];
      for (int c = 0; c < kt; ++c)
        row[2 + k + c] = cv.transmission[static_cast<std::size_t>(e) * kt + c];
    }
  }
  const float* row(int e) const { return &rows[static_cast<std::size_t>(e) * stride]; }
};

inline std::shared_ptr<const SampleTable> sampleTableOf(const ClassifiedVolume& cv) {
  return cv.derived->get<SampleTable>(
      "raycast sample table", [&] { return std::make_shared<const SampleTable>(cv); });
}

}  // namespace svr::raycast
