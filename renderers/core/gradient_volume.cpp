#include "renderers/core/gradient_volume.h"

#include <algorithm>
#include <cmath>

namespace svr {

std::uint64_t GradientVolume::bytesFor(const Dims& dims) {
  return 3ull * sizeof(std::int16_t) * static_cast<std::uint64_t>(dims[0]) * dims[1] * dims[2];
}

namespace {

// The central differences of one row of voxels (fixed y, z), clamped at the border, in world
// units: out[3 x + a] for axis a. Rows are independent, so the builder runs them in parallel.
void rowGradients(const float* f, const Dims& d, int y, int z, const float half_inv[3],
                  float* out) {
  const std::size_t sy = d[0], sz = static_cast<std::size_t>(d[0]) * d[1];
  const float* row = f + y * sy + z * sz;
  const float* y_lo = f + std::max(y - 1, 0) * sy + z * sz;
  const float* y_hi = f + std::min(y + 1, d[1] - 1) * sy + z * sz;
  const float* z_lo = f + y * sy + std::max(z - 1, 0) * sz;
  const float* z_hi = f + y * sy + std::min(z + 1, d[2] - 1) * sz;
  for (int x = 0; x < d[0]; ++x) {
    const int x_lo = std::max(x - 1, 0), x_hi = std::min(x + 1, d[0] - 1);
    out[3 * x + 0] = (row[x_hi] - row[x_lo]) * half_inv[0];
    out[3 * x + 1] = (y_hi[x] - y_lo[x]) * half_inv[1];
    out[3 * x + 2] = (z_hi[x] - z_lo[x]) * half_inv[2];
  }
}

}  // namespace

GradientVolume buildGradientVolume(const ClassifiedVolume& cv) {
  const Dims& d = cv.dims;
  const float* f = cv.shadingField().data();
  const std::size_t row_values = 3 * static_cast<std::size_t>(d[0]);
  const float half_inv[3] = {static_cast<float>(0.5 / cv.spacing.x),
                             static_cast<float>(0.5 / cv.spacing.y),
                             static_cast<float>(0.5 / cv.spacing.z)};
  const int rows = d[1] * d[2];
  // Two passes: the largest component sets the scale, then every voxel is quantised to it
  // (recomputing a row is cheaper than keeping 12 bytes a voxel in between).
  float largest = 0.f;
  const bool parallel = static_cast<std::int64_t>(rows) * d[0] >= kParallelVoxels;
#pragma omp parallel reduction(max : largest) if (parallel)
  {
    std::vector<float> g(row_values);
#pragma omp for schedule(static)
    for (int r = 0; r < rows; ++r) {
      rowGradients(f, d, r % d[1], r / d[1], half_inv, g.data());
      for (float v : g) largest = std::max(largest, std::abs(v));
    }
  }
  GradientVolume out;
  out.dims = d;
  out.scale = largest > 0.f ? largest / 32767.f : 1.f;
  out.q.resize(row_values * rows + GradientVolume::kPadding);
  for (int i = 0; i < GradientVolume::kPadding; ++i) out.q[row_values * rows + i] = 0;
  const float inv_scale = 1.f / out.scale;
#pragma omp parallel if (parallel)
  {
    std::vector<float> g(row_values);
#pragma omp for schedule(static)
    for (int r = 0; r < rows; ++r) {
      rowGradients(f, d, r % d[1], r / d[1], half_inv, g.data());
      std::int16_t* q = out.q.data() + row_values * r;
      for (std::size_t i = 0; i < row_values; ++i) {  // round half away from zero; |v| ≤ 32767
        const float v = g[i] * inv_scale;
        q[i] = static_cast<std::int16_t>(v + (v >= 0.f ? 0.5f : -0.5f));
      }
    }
  }
  return out;
}

std::shared_ptr<const GradientVolume> gradientsOf(const ClassifiedVolume& cv) {
  return cv.derived->get<GradientVolume>(
      "gradients", [&] { return std::make_shared<const GradientVolume>(buildGradientVolume(cv)); });
}

}  // namespace svr
