#include "renderers/kernels/splat_voxels.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "renderers/classification/classified_sample.h"
#include "base/error.h"

namespace svr::splat {
namespace {

// −ln(a)/Δs: the extinction that gives transmission a over the classification step.
float perUnitLength(float transmission, double step) {
  return static_cast<float>(-std::log(std::max(transmission, 1e-30f)) / step);
}

// Widens each voxel's [lo, hi] of one slice by its neighbours' along x (axis 0) or y (axis 1),
// clamped at the slice's sides.
void widenAlong(int axis, int nx, int ny, const float* lo_in, const float* hi_in, float* lo,
                float* hi) {
  const std::size_t step = axis == 0 ? 1 : static_cast<std::size_t>(nx);
  for (int y = 0; y < ny; ++y)
    for (int x = 0; x < nx; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * nx + x;
      const int at = axis == 0 ? x : y, size = axis == 0 ? nx : ny;
      float a = lo_in[i], b = hi_in[i];
      if (at > 0) a = std::min(a, lo_in[i - step]), b = std::max(b, hi_in[i - step]);
      if (at + 1 < size) a = std::min(a, lo_in[i + step]), b = std::max(b, hi_in[i + step]);
      lo[i] = a;
      hi[i] = b;
    }
}

// The smallest and largest value of the 3 × 3 neighbourhood of each voxel of slice z, x fastest.
void sliceNeighbourhoodRange(const ClassifiedVolume& cv, int z, std::vector<float>& lo,
                             std::vector<float>& hi, std::vector<float>& row_lo,
                             std::vector<float>& row_hi) {
  const int nx = cv.dims[0], ny = cv.dims[1];
  const std::size_t plane = static_cast<std::size_t>(nx) * ny;
  const float* v = cv.values.data() + plane * z;
  row_lo.resize(plane);
  row_hi.resize(plane);
  lo.resize(plane);
  hi.resize(plane);
  widenAlong(0, nx, ny, v, v, row_lo.data(), row_hi.data());
  widenAlong(1, nx, ny, row_lo.data(), row_hi.data(), lo.data(), hi.data());
}

}  // namespace

SplatVoxels::SplatVoxels(const ClassifiedVolume& cv, Set set) : dims_(cv.dims) {
  if (set == Set::kReconstruction && cv.labels)
    throw Error("splat: a label map has no values between its voxels to classify");
  const int kt = cv.t_channels;
  sigma_alpha_.resize(cv.entries);
  sigma_t_.resize(static_cast<std::size_t>(cv.entries) * kt);
  // visible_before[e]: how many of the entries below e scatter or absorb.
  std::vector<int> visible_before(cv.entries + 1, 0);
  for (int e = 0; e < cv.entries; ++e) {
    sigma_alpha_[e] = perUnitLength(1.f - cv.alpha[e], cv.step_world);
    bool visible = sigma_alpha_[e] > 0.f;
    for (int c = 0; c < kt; ++c) {
      sigma_t_[e * kt + c] = perUnitLength(cv.transmission[e * kt + c], cv.step_world);
      visible = visible || sigma_t_[e * kt + c] > 0.f;
    }
    visible_before[e + 1] = visible_before[e] + (visible ? 1 : 0);
  }
  for (int a = 0; a < 3; ++a) inv_spacing_[a] = static_cast<float>(1.0 / cv.spacing[a]);

  const Dims& d = cv.dims;
  const std::size_t count = static_cast<std::size_t>(d[0]) * d[1] * d[2];
  if (count > std::numeric_limits<std::uint32_t>::max())
    throw Error("splat: volumes of more than 2³² voxels are not supported");
  const std::size_t plane = static_cast<std::size_t>(d[0]) * d[1];
  // Whether any value in [lo, hi] falls in or next to a visible entry.
  const auto spansVisible = [&](float lo, float hi) {
    int e_lo, e_hi, unused;
    float f;
    binOf(cv, lo, e_lo, unused, f);
    binOf(cv, hi, unused, e_hi, f);
    return visible_before[e_hi + 1] - visible_before[e_lo] > 0;
  };

  // One list per z-slice filled in parallel and joined in slice order.
  std::vector<std::vector<SplatVoxel>> slices(d[2]);
#pragma omp parallel
  {
    std::vector<float> lo[3], hi[3], row_lo, row_hi;  // the neighbourhood ranges of z − 1 … z + 1
#pragma omp for schedule(dynamic)
    for (int z = 0; z < d[2]; ++z) {
      if (set == Set::kReconstruction)
        for (int s = 0; s < 3; ++s)
          sliceNeighbourhoodRange(cv, std::clamp(z - 1 + s, 0, d[2] - 1), lo[s], hi[s], row_lo,
                                  row_hi);
      for (std::size_t xy = 0; xy < plane; ++xy) {
        const std::size_t i = plane * z + xy;
        int e0, e1;
        float f = 0.f;
        if (cv.labels)
          e0 = e1 = cv.label[i];
        else
          binOf(cv, cv.values[i], e0, e1, f);
        bool keep;
        if (set == Set::kReconstruction) {
          keep = spansVisible(std::min({lo[0][xy], lo[1][xy], lo[2][xy]}),
                              std::max({hi[0][xy], hi[1][xy], hi[2][xy]}));
        } else {
          const float g = 1.f - f;
          keep = g * sigma_alpha_[e0] + f * sigma_alpha_[e1] > 0.f;
          for (int c = 0; c < kt && !keep; ++c)
            keep = g * sigma_t_[e0 * kt + c] + f * sigma_t_[e1 * kt + c] > 0.f;
        }
        if (keep)
          slices[z].push_back({static_cast<std::uint32_t>(i), static_cast<std::uint16_t>(e0), f});
      }
    }
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

std::shared_ptr<const SplatVoxels> SplatVoxels::of(const ClassifiedVolume& cv, Set set) {
  return cv.derived->get<SplatVoxels>(
      set == Set::kVisible ? "splat.voxels" : "splat.voxels.reconstruction",
      [&] { return std::make_shared<const SplatVoxels>(cv, set); });
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
