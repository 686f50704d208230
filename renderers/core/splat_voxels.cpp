#include "renderers/core/splat_voxels.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "renderers/core/classified_sample.h"
#include "spectral/error.h"

namespace svr::splat {
namespace {

// −ln(a)/Δs: the extinction that gives transmission a over the classification step.
float perUnitLength(float transmission, double step) {
  return static_cast<float>(-std::log(std::max(transmission, 1e-30f)) / step);
}

}  // namespace

SplatVoxels::SplatVoxels(const ClassifiedVolume& cv) : dims_(cv.dims) {
  const int kt = cv.t_channels;
  sigma_alpha_.resize(cv.entries);
  sigma_t_.resize(static_cast<std::size_t>(cv.entries) * kt);
  for (int e = 0; e < cv.entries; ++e) {
    sigma_alpha_[e] = perUnitLength(1.f - cv.alpha[e], cv.step_world);
    for (int c = 0; c < kt; ++c)
      sigma_t_[e * kt + c] = perUnitLength(cv.transmission[e * kt + c], cv.step_world);
  }
  for (int a = 0; a < 3; ++a) inv_spacing_[a] = static_cast<float>(1.0 / cv.spacing[a]);

  const Dims& d = cv.dims;
  const std::size_t count = static_cast<std::size_t>(d[0]) * d[1] * d[2];
  if (count > std::numeric_limits<std::uint32_t>::max())
    throw Error("splat: volumes of more than 2³² voxels are not supported");

  // Visible voxels, one list per z-slice filled in parallel and joined in slice order.
  std::vector<std::vector<SplatVoxel>> slices(d[2]);
#pragma omp parallel for schedule(dynamic)
  for (int z = 0; z < d[2]; ++z)
    for (int y = 0; y < d[1]; ++y)
      for (int x = 0; x < d[0]; ++x) {
        const std::size_t i = x + static_cast<std::size_t>(d[0]) * (y + static_cast<std::size_t>(d[1]) * z);
        int e0, e1;
        float f = 0.f;
        if (cv.labels)
          e0 = e1 = cv.label[i];
        else
          binOf(cv, cv.values[i], e0, e1, f);
        const float g = 1.f - f;
        bool visible = g * sigma_alpha_[e0] + f * sigma_alpha_[e1] > 0.f;
        for (int c = 0; c < kt && !visible; ++c)
          visible = g * sigma_t_[e0 * kt + c] + f * sigma_t_[e1 * kt + c] > 0.f;
        if (visible)
          slices[z].push_back(
              {static_cast<std::uint32_t>(i), static_cast<std::uint16_t>(e0), f});
      }
  std::size_t total = 0;
  for (const auto& s : slices) total += s.size();
  voxels_.reserve(total);
  for (auto& s : slices) {
    voxels_.insert(voxels_.end(), s.begin(), s.end());
    std::vector<SplatVoxel>().swap(s);
  }

  // Cell means of the shading field on the dual grid, voxel indices clamped at the borders.
  const int nx = d[0] + 1, ny = d[1] + 1, nz = d[2] + 1;
  cell_mean_.resize(static_cast<std::size_t>(nx) * ny * nz);
  const auto field = [&](int x, int y, int z) {
    x = std::clamp(x, 0, d[0] - 1);
    y = std::clamp(y, 0, d[1] - 1);
    z = std::clamp(z, 0, d[2] - 1);
    return cv.shadingField()[x + static_cast<std::size_t>(d[0]) * (y + static_cast<std::size_t>(d[1]) * z)];
  };
#pragma omp parallel for schedule(static)
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        float sum = 0.f;
        for (int c = 0; c < 8; ++c)
          sum += field(i - 1 + (c & 1), j - 1 + ((c >> 1) & 1), k - 1 + ((c >> 2) & 1));
        cell_mean_[(static_cast<std::size_t>(k) * ny + j) * nx + i] = sum * 0.125f;
      }
}

std::shared_ptr<const SplatVoxels> SplatVoxels::of(const ClassifiedVolume& cv) {
  return cv.derived->get<SplatVoxels>(
      "splat.voxels", [&] { return std::make_shared<const SplatVoxels>(cv); });
}

void SplatVoxels::gradientAtNode(int i, int j, int k, float g[3]) const {
  const int at[3] = {i, j, k};
  for (int a = 0; a < 3; ++a) {
    int lo[3] = {i, j, k}, hi[3] = {i, j, k};
    lo[a] = std::max(at[a] - 1, 0);
    hi[a] = std::min(at[a] + 1, dims_[a]);
    g[a] = (node(hi[0], hi[1], hi[2]) - node(lo[0], lo[1], lo[2])) * 0.5f * inv_spacing_[a];
  }
}

}  // namespace svr::splat
