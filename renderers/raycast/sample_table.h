#pragma once
// The classification's entries laid out for the raycaster's blend: one row per entry,
//   [α, α·specular, α·ρ_0 … α·ρ_{k−1}, t_0 … t_{kt−1}],
// contiguous, so that a sample's two (or eight) entries are two (eight) short rows, and the
// opacity-weighted blend of blendEntries needs no division: a sample adds
// T ⊙ (shade · Σ w α ρ + highlight · Σ w α s · white), which is blendEntries' α · (ρ̄ · shade +
// s̄ · highlight · white) with the normalisation by α cancelled.

#include <memory>
#include <vector>

#include "renderers/classification/classification.h"
#include "renderers/classification/classified_sample.h"

namespace svr::raycast {

struct SampleTable {
  // Rows are padded with zeros to a multiple of 8 floats, so that with a fixed k the blend is
  // whole vectors of a compile-time count (the AVX2 build blends a factor:6 row in two FMAs).
  static constexpr int strideFor(int width) { return (width + 7) / 8 * 8; }

  int stride = 0;  // strideFor(2 + k + kt)
  std::vector<float> rows;

  explicit SampleTable(const ClassifiedVolume& cv)
      : stride(strideFor(2 + cv.k + cv.t_channels)),
        rows(blendRows(cv, cv.alpha.data(), cv.transmission.data(), stride)) {}
  // Entry e's row; kStride: the stride when known at compile time (0: use the run-time one).
  template <int kStride>
  const float* row(int e) const {
    return rows.data() + static_cast<std::size_t>(e) * (kStride > 0 ? kStride : stride);
  }
};

inline std::shared_ptr<const SampleTable> sampleTableOf(const ClassifiedVolume& cv) {
  return cv.derived->get<SampleTable>(
      "raycast sample table", [&] { return std::make_shared<const SampleTable>(cv); });
}

}  // namespace svr::raycast
