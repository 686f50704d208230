#include "renderers/core/gradient_volume.h"

#include <algorithm>
#include <cmath>

namespace svr {

std::uint64_t GradientVolume::bytesFor(const Dims& dims) {
  return 4ull * sizeof(std::int16_t) * static_cast<std::uint64_t>(dims[0]) * dims[1] * dims[2];
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
  const std::size_t row_voxels = d[0];
  const float half_inv[3] = {static_cast<float>(0.5 / cv.spacing.x),
                             static_cast<float>(0.5 / cv.spacing.y),
                             static_cast<float>(0.5 / cv.spacing.z)};
  const int rows = d[1] * d[2];
  GradientVolume out;
  out.dims = d;
  const bool parallel = static_cast<std::int64_t>(rows) * d[0] >= kParallelVoxels;
  float lo = INFINITY, hi = -INFINITY, largest = 0.f;
#pragma omp parallel reduction(min : lo) reduction(max : hi, largest) if (parallel)
  {
    std::vector<float> g(3 * row_voxels);
#pragma omp for schedule(static)
    for (int r = 0; r < rows; ++r) {
      rowGradients(f, d, r % d[1], r / d[1], half_inv, g.data());
      for (float v : g) largest = std::max(largest, std::abs(v));
      for (std::size_t x = 0; x < row_voxels; ++x) {
        lo = std::min(lo, f[row_voxels * r + x]);
        hi = std::max(hi, f[row_voxels * r + x]);
      }
    }
  }
  const float gscale = largest > 0.f ? largest / 32767.f : 1.f;
  const float vscale = hi > lo ? (hi - lo) / 65534.f : 1.f;
  out.scale[0] = vscale;
  out.offset[0] = lo + 32767.f * vscale;
  for (int a = 1; a < 4; ++a) out.scale[a] = gscale;
  out.q.resize(4 * row_voxels * rows);
#pragma omp parallel if (parallel)
  {
    std::vector<float> g(3 * row_voxels);
#pragma omp for schedule(static)
    for (int r = 0; r < rows; ++r) {
      rowGradients(f, d, r % d[1], r / d[1], half_inv, g.data());
      std::int16_t* o = out.q.data() + 4 * row_voxels * r;
      const float* field = f + row_voxels * r;
      auto quantise = [](float v) {  // to nearest, half away from zero
        return static_cast<std::int16_t>(
            std::clamp(v + (v >= 0.f ? 0.5f : -0.5f), -32767.f, 32767.f));
      };
      for (std::size_t x = 0; x < row_voxels; ++x) {
        o[4 * x] = quantise((field[x] - out.offset[0]) / vscale);
        for (int a = 0; a < 3; ++a) o[4 * x + 1 + a] = quantise(g[3 * x + a] / gscale);
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
