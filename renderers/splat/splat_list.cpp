#include "renderers/splat/splat_list.h"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <utility>

namespace svr::splat {
namespace {

// −ln(a)/Δs: the extinction that gives transmission a over the classification step.
float perUnitLength(float transmission, double step) {
  return static_cast<float>(-std::log(std::max(transmission, 1e-30f)) / step);
}

}  // namespace

SplatList::SplatList(const ClassifiedVolume& cv, const RenderRequest& req,
                     const Projector& projector)
    : cv_(cv), k_(cv.k), kt_(cv.t_channels) {
  sigma_alpha_.resize(cv.entries);
  sigma_t_.resize(static_cast<std::size_t>(cv.entries) * kt_);
  for (int e = 0; e < cv.entries; ++e) {
    sigma_alpha_[e] = perUnitLength(1.f - cv.alpha[e], cv.step_world);
    for (int c = 0; c < kt_; ++c)
      sigma_t_[e * kt_ + c] = perUnitLength(cv.transmission[e * kt_ + c], cv.step_world);
  }

  const Dims& d = cv.dims;
  const glm::dvec3 centre = 0.5 * glm::dvec3(d[0] - 1, d[1] - 1, d[2] - 1);
  const glm::dvec3 inv_spacing = 1.0 / cv.spacing;
  const float ambient = static_cast<float>(req.shading.ambient);
  const float diffuse = static_cast<float>(req.shading.diffuse);
  const float specular = static_cast<float>(req.shading.specular);
  const float shininess = static_cast<float>(req.shading.shininess);
  const Footprint any = projector.footprint(glm::dvec3(0.0));
  const std::size_t sx = 1, sy = d[0], sz = static_cast<std::size_t>(d[0]) * d[1];

  // One list per z-slice, filled in parallel and joined in slice order: deterministic.
  std::vector<std::vector<Splat>> slices(d[2]);
  std::vector<std::vector<Footprint>> slice_footprints(d[2]);
#pragma omp parallel for schedule(dynamic)
  for (int z = 0; z < d[2]; ++z) {
    auto& out = slices[z];
    for (int y = 0; y < d[1]; ++y)
      for (int x = 0; x < d[0]; ++x) {
        const std::size_t i = x * sx + y * sy + z * sz;
        int e0 = 0;
        float f = 0.f;
        if (cv.labels) {
          e0 = cv.label[i];
        } else {
          const float bin =
              std::clamp(static_cast<float>((cv.values[i] - cv.value_lo) * cv.value_scale), 0.f,
                         static_cast<float>(cv.entries - 1));
          e0 = std::min(static_cast<int>(bin), std::max(cv.entries - 2, 0));
          f = bin - e0;
        }
        const int e1 = std::min(e0 + 1, cv.entries - 1);
        const float g = 1.f - f;
        bool visible = g * sigma_alpha_[e0] + f * sigma_alpha_[e1] > 0.f;
        for (int c = 0; c < kt_ && !visible; ++c)
          visible = g * sigma_t_[e0 * kt_ + c] + f * sigma_t_[e1 * kt_ + c] > 0.f;
        if (!visible) continue;

        const glm::dvec3 world = (glm::dvec3(x, y, z) - centre) * cv.spacing;
        const glm::dvec3 pos = projector.project(world);
        const Footprint fp = projector.orthographic() ? any : projector.footprint(world);
        if (pos.z <= 0.0 && !projector.orthographic()) continue;  // behind the eye
        if (pos.x + fp.half_w < 0 || pos.x - fp.half_w > req.width || pos.y + fp.half_h < 0 ||
            pos.y - fp.half_h > req.height)
          continue;

        // Phong from the central-difference gradient of the shading field at the voxel.
        const int at[3] = {x, y, z};
        glm::dvec3 grad;
        for (int a = 0; a < 3; ++a) {
          int lo[3] = {x, y, z}, hi[3] = {x, y, z};
          lo[a] = std::max(at[a] - 1, 0);
          hi[a] = std::min(at[a] + 1, d[a] - 1);
          const float fhi = cv.shading_field[hi[0] * sx + hi[1] * sy + hi[2] * sz];
          const float flo = cv.shading_field[lo[0] * sx + lo[1] * sy + lo[2] * sz];
          grad[a] = (fhi - flo) * 0.5 * inv_spacing[a];
        }
        const glm::dvec3 view = projector.towardsEye(world);
        const glm::dvec3 light = req.light_direction ? *req.light_direction : view;
        const glm::dvec3 half = glm::normalize(light + view);
        float shade = ambient + diffuse, highlight = 0.f;
        const double gl = glm::length(grad);
        if (gl > 1e-6) {
          const glm::dvec3 n = -grad / gl;
          shade = ambient + diffuse * static_cast<float>(std::abs(glm::dot(n, light)));
          highlight =
              specular * std::pow(static_cast<float>(std::abs(glm::dot(n, half))), shininess);
        }
        const float spec_w = g * cv.specular[e0] + f * cv.specular[e1];
        out.push_back({static_cast<float>(pos.x), static_cast<float>(pos.y),
                       static_cast<float>(pos.z), static_cast<std::uint16_t>(e0), f, shade,
                       highlight * spec_w});
        if (!projector.orthographic()) slice_footprints[z].push_back(fp);
      }
  }
  std::size_t total = 0;
  for (const auto& s : slices) total += s.size();
  std::vector<Splat> joined;
  std::vector<Footprint> joined_fp;
  joined.reserve(total);
  for (int z = 0; z < d[2]; ++z) {
    joined.insert(joined.end(), slices[z].begin(), slices[z].end());
    std::vector<Splat>().swap(slices[z]);
    joined_fp.insert(joined_fp.end(), slice_footprints[z].begin(), slice_footprints[z].end());
  }
  // Front to back; ties broken by voxel order, so the order never depends on threads.
  std::vector<std::pair<float, std::uint32_t>> order(total);
  for (std::size_t i = 0; i < total; ++i)
    order[i] = {joined[i].depth, static_cast<std::uint32_t>(i)};
  std::sort(order.begin(), order.end());
  splats_.resize(total);
  for (std::size_t i = 0; i < total; ++i) splats_[i] = joined[order[i].second];
  if (projector.orthographic()) {
    footprints_ = {any};
    max_depth_sigma_ = any.depth_sigma;
  } else {
    footprints_.resize(total);
    for (std::size_t i = 0; i < total; ++i) {
      footprints_[i] = joined_fp[order[i].second];
      max_depth_sigma_ = std::max(max_depth_sigma_, footprints_[i].depth_sigma);
    }
  }
}

void SplatList::coefficients(const Splat& s, SplatCoefficients& out) const {
  const int e0 = s.entry, e1 = std::min(e0 + 1, cv_.entries - 1);
  const float f = s.frac, g = 1.f - f;
  out.sigma_alpha = g * sigma_alpha_[e0] + f * sigma_alpha_[e1];
  for (int c = 0; c < kt_; ++c)
    out.sigma_t[c] = g * sigma_t_[e0 * kt_ + c] + f * sigma_t_[e1 * kt_ + c];
  for (int c = 0; c < k_; ++c)
    out.colour[c] =
        (g * cv_.reflectance[e0 * k_ + c] + f * cv_.reflectance[e1 * k_ + c]) * s.shade +
        cv_.white[c] * s.highlight;
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
