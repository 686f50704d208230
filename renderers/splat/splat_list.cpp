#include "renderers/splat/splat_list.h"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <utility>

#include "renderers/core/classified_sample.h"
#include "renderers/core/splat_projection.h"

namespace svr::splat {

SplatList::SplatList(const ClassifiedVolume& cv, const RenderRequest& req,
                     const Projector& projector)
    : cv_(cv), voxels_(SplatVoxels::of(cv)), k_(cv.k), kt_(cv.t_channels) {
  ProjectedVoxels projected = projectVoxels(*voxels_, cv, projector, req.width, req.height);
  const auto voxels = voxels_->voxels();
  const bool any_specular = req.shading.specular > 0.0 &&
                            std::any_of(cv.specular.begin(), cv.specular.end(),
                                        [](float s) { return s > 0.f; });
  const Dims& d = cv.dims;
  const std::size_t n = projected.ids.size();
  splats_.resize(n);
#pragma omp parallel for schedule(dynamic, 4096)
  for (std::size_t i = 0; i < n; ++i) {
    const SplatVoxel& voxel = voxels[projected.ids[i]];
    const int x = static_cast<int>(voxel.index % d[0]);
    const int y = static_cast<int>(voxel.index / d[0] % d[1]);
    const int z = static_cast<int>(voxel.index / d[0] / d[1]);
    // The splat carries its kernel's worth of emission, so its shade is the mean of the
    // shade over the voxel's cell — the raycaster's Phong at the cell's 8 corners — not the
    // shade at its centre: near a boundary those differ, and the centre alone is too bright.
    const glm::dvec3 view = projector.towardsEye(voxelWorld(cv, voxel.index));
    const glm::dvec3 light = req.light_direction ? *req.light_direction : view;
    PhongSetup setup(req.shading, light, glm::normalize(light + view));
    if (!any_specular) setup.specular = 0.f;
    float shade = 0.f, highlight = 0.f;
    for (int c = 0; c < 8; ++c) {
      float g[3];
      voxels_->gradientAtNode(x + (c & 1), y + ((c >> 1) & 1), z + ((c >> 2) & 1), g);
      const PhongTerms t = phong(setup, g);
      shade += t.shade;
      highlight += t.highlight;
    }
    splats_[i] = {projected.position[i].x, projected.position[i].y, projected.depth[i],
                  voxel.entry, voxel.frac, shade * 0.125f, highlight * 0.125f};
  }
  footprints_ = std::move(projected.footprints);
  for (const Footprint& fp : footprints_) max_depth_sigma_ = std::max(max_depth_sigma_, fp.depth_sigma);
}

void SplatList::coefficients(const Splat& s, SplatCoefficients& out) const {
  // The same blend as every backend's samples, weighted by the scattering extinction.
  const int entry[2] = {s.entry, std::min(s.entry + 1, cv_.entries - 1)};
  const float w[2] = {1.f - s.frac, s.frac};
  float spec_w;
  blendEntries(cv_, voxels_->sigmaAlpha().data(), voxels_->sigmaT().data(), entry, w, 2, k_, kt_,
               out.sigma_alpha, spec_w, out.colour.data(), out.sigma_t.data());
  const float highlight = s.highlight * spec_w;
  for (int c = 0; c < k_; ++c) out.colour[c] = out.colour[c] * s.shade + cv_.white[c] * highlight;
}

}  // namespace svr::splat

namespace svr::splat {

Bands bandsOf(const SplatList& list, int height, int rows) {
  Bands bands;
  bands.rows = rows;
  bands.count = (height + rows - 1) / rows;
  const auto splats = list.splats();
  // Counting sort by band, in splat order: each band's list stays front to back.
  std::vector<std::size_t> count(bands.count + 1, 0);
  const auto range = [&](std::size_t i, int& b0, int& b1) {
    int lo, hi;
    pixelRange(splats[i].y, list.footprint(i).half_h, height, lo, hi);
    b0 = lo / rows;
    b1 = lo > hi ? b0 - 1 : hi / rows;
  };
  for (std::size_t i = 0; i < splats.size(); ++i) {
    int b0, b1;
    range(i, b0, b1);
    for (int b = b0; b <= b1; ++b) ++count[b + 1];
  }
  for (int b = 0; b < bands.count; ++b) count[b + 1] += count[b];
  bands.offsets = count;
  bands.splats.resize(count.back());
  for (std::size_t i = 0; i < splats.size(); ++i) {
    int b0, b1;
    range(i, b0, b1);
    for (int b = b0; b <= b1; ++b) bands.splats[count[b]++] = static_cast<std::uint32_t>(i);
  }
  return bands;
}

}  // namespace svr::splat
