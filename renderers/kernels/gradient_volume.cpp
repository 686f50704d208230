#include "renderers/kernels/gradient_volume.h"

#include <algorithm>
#include <array>
#include <cmath>

#include <fmt/format.h>

namespace svr {

std::uint64_t GradientVolume::bytesFor(const Dims& dims) {
  return 4ull * sizeof(std::int16_t) * static_cast<std::uint64_t>(dims[0]) * dims[1] * dims[2];
}

namespace {

// The central differences of one row of voxels (fixed y, z), clamped at the border, in world
// units, into gx, gy, gz. Rows are independent, so the builder runs them in parallel; within a
// row the interior is a plain loop the compiler vectorises.
void rowGradients(const float* f, const Dims& d, int y, int z, const float half_inv[3],
                  float* gx, float* gy, float* gz) {
  const std::size_t sy = d[0], sz = static_cast<std::size_t>(d[0]) * d[1];
  const int n = d[0];
  const float* row = f + y * sy + z * sz;
  const float* y_lo = f + std::max(y - 1, 0) * sy + z * sz;
  const float* y_hi = f + std::min(y + 1, d[1] - 1) * sy + z * sz;
  const float* z_lo = f + y * sy + std::max(z - 1, 0) * sz;
  const float* z_hi = f + y * sy + std::min(z + 1, d[2] - 1) * sz;
  for (int x = 0; x < n; ++x) {
    gy[x] = (y_hi[x] - y_lo[x]) * half_inv[1];
    gz[x] = (z_hi[x] - z_lo[x]) * half_inv[2];
  }
  for (int x = 1; x + 1 < n; ++x) gx[x] = (row[x + 1] - row[x - 1]) * half_inv[0];
  gx[0] = (row[std::min(1, n - 1)] - row[0]) * half_inv[0];
  if (n > 1) gx[n - 1] = (row[n - 1] - row[n - 2]) * half_inv[0];
}

// To the nearest int16 (half away from zero), within ±32767.
inline std::int16_t quantise(float v) {
  return static_cast<std::int16_t>(std::clamp(v + (v >= 0.f ? 0.5f : -0.5f), -32767.f, 32767.f));
}

// 1 / (2 · spacing) per axis: central differences in world units.
std::array<float, 3> halfInverseSpacing(const ClassifiedVolume& cv) {
  return {static_cast<float>(0.5 / cv.spacing.x), static_cast<float>(0.5 / cv.spacing.y),
          static_cast<float>(0.5 / cv.spacing.z)};
}

}  // namespace

FieldRange fieldRangeOver(const ClassifiedVolume& cv, const VoxelBox& box) {
  const Dims& d = cv.dims;
  const float* f = cv.shadingField().data();
  const std::size_t row_voxels = d[0];
  const std::array<float, 3> half_inv = halfInverseSpacing(cv);
  const Dims size = box.size();
  const int rows = size[1] * size[2];
  const bool parallel = static_cast<std::int64_t>(rows) * d[0] >= kParallelVoxels;
  float lo = INFINITY, hi = -INFINITY, largest = 0.f;
#pragma omp parallel reduction(min : lo) reduction(max : hi, largest) if (parallel)
  {
    std::vector<float> g(3 * row_voxels);
#pragma omp for schedule(static)
    for (int r = 0; r < rows; ++r) {
      const int y = box.lo[1] + r % size[1], z = box.lo[2] + r / size[1];
      rowGradients(f, d, y, z, half_inv.data(), g.data(), g.data() + row_voxels,
                   g.data() + 2 * row_voxels);
      const float* field = f + row_voxels * (static_cast<std::size_t>(z) * d[1] + y);
      for (int x = box.lo[0]; x < box.hi[0]; ++x) {
        for (int a = 0; a < 3; ++a) largest = std::max(largest, std::abs(g[a * row_voxels + x]));
        lo = std::min(lo, field[x]);
        hi = std::max(hi, field[x]);
      }
    }
  }
  return {lo, hi, largest};
}

GradientVolume buildGradientVolume(const ClassifiedVolume& cv) {
  const Dims& d = cv.dims;
  const float* f = cv.shadingField().data();
  const std::size_t row_voxels = d[0];
  const std::array<float, 3> half_inv = halfInverseSpacing(cv);
  const int rows = d[1] * d[2];
  GradientVolume out;
  out.dims = d;
  const bool parallel = static_cast<std::int64_t>(rows) * d[0] >= kParallelVoxels;
  // The field's range and the largest gradient component set the scales (a brick takes the
  // whole volume's, so that every brick quantises alike), then every voxel is quantised to
  // them (recomputing a row is cheaper than keeping 12 bytes a voxel in between).
  const FieldRange range = cv.brick && cv.brick->whole_field
                               ? *cv.brick->whole_field
                               : fieldRangeOver(cv, {{0, 0, 0}, d});
  const float lo = range.lo, hi = range.hi, largest = range.largest;
  const float gscale = largest > 0.f ? largest / 32767.f : 1.f;
  const float vscale = hi > lo ? (hi - lo) / 65534.f : 1.f;
  out.scale[0] = vscale;
  out.offset[0] = lo + 32767.f * vscale;
  for (int a = 1; a < 4; ++a) out.scale[a] = gscale;
  const float inv_g = 1.f / gscale, inv_v = 1.f / vscale, offset = out.offset[0];
  out.count = 4 * row_voxels * rows;
  out.q.reset(new std::int16_t[out.count]);  // uninitialised: every element is written below
#pragma omp parallel if (parallel)
  {
    std::vector<float> g(3 * row_voxels);
#pragma omp for schedule(static)
    for (int r = 0; r < rows; ++r) {
      float* gx = g.data();
      float* gy = gx + row_voxels;
      float* gz = gy + row_voxels;
      rowGradients(f, d, r % d[1], r / d[1], half_inv.data(), gx, gy, gz);
      std::int16_t* o = out.q.get() + 4 * row_voxels * r;
      const float* field = f + row_voxels * r;
      for (std::size_t x = 0; x < row_voxels; ++x) {
        o[4 * x] = quantise((field[x] - offset) * inv_v);
        o[4 * x + 1] = quantise(gx[x] * inv_g);
        o[4 * x + 2] = quantise(gy[x] * inv_g);
        o[4 * x + 3] = quantise(gz[x] * inv_g);
      }
    }
  }
  return out;
}

std::shared_ptr<const GradientVolume> gradientsOf(const ClassifiedVolume& cv) {
  return cv.derived->get<GradientVolume>(
      "gradients", [&] { return std::make_shared<const GradientVolume>(buildGradientVolume(cv)); });
}

namespace {

// Bytes the classification already holds for the renderers (values, shading field, labels).
std::uint64_t classifiedBytes(const ClassifiedVolume& cv) {
  return cv.values.size() * sizeof(float) + cv.shading_field.size() * sizeof(float) +
         cv.label.size() * sizeof(std::uint16_t);
}

}  // namespace

std::shared_ptr<const GradientVolume> gradientsWithinBudget(const RenderRequest& req,
                                                            bool required,
                                                            const std::string& who) {
  const ClassifiedVolume& cv = req.volume;
  const std::uint64_t need = GradientVolume::bytesFor(cv.dims);
  const std::uint64_t held =
      classifiedBytes(cv) +
      LightIndependentImage::bytesFor(req.width, req.height, cv.k, cv.t_channels);
  if (!required && held + need > req.memory_budget) {
    if (req.note)
      req.note(fmt::format("{}: gradients computed per sample (slower): precomputing them "
                           "needs {} beside the {} held, over the memory budget of {}",
                           who, formatBytes(need), formatBytes(held),
                           formatBytes(req.memory_budget)));
    return nullptr;
  }
  checkMemoryBudget(held + need, req.memory_budget,
                    fmt::format("{}: precomputed gradients of {}×{}×{} voxels", who, cv.dims[0],
                                cv.dims[1], cv.dims[2]));
  return gradientsOf(cv);
}

}  // namespace svr
