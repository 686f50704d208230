#include "renderers/kernels/splat_footprint.h"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <numbers>

namespace svr::splat {

FootprintTable::FootprintTable(double cutoff, int entries)
    : cutoff_(cutoff),
      cutoff2_(static_cast<float>(cutoff * cutoff)),
      exp_scale_(static_cast<float>(entries / (cutoff * cutoff))),
      cdf_scale_(static_cast<float>(entries / (2.0 * cutoff))) {
  // Bin midpoints: the nearest-bin lookup then errs by at most half a bin either way. Two spare
  // bins absorb float rounding of q just below cutoff².
  exp_.resize(entries + 2);
  for (int i = 0; i < entries + 2; ++i)
    exp_[i] = static_cast<float>(std::exp(-0.5 * (i + 0.5) / exp_scale_));
  const auto phi = [](double t) { return 0.5 * std::erfc(-t / std::numbers::sqrt2); };
  const double lo = phi(-cutoff), span = phi(cutoff) - lo;
  cdf_.resize(entries + 1);
  for (int i = 0; i <= entries; ++i)
    cdf_[i] = static_cast<float>((phi(-cutoff + i / cdf_scale_) - lo) / span);
  cdf_.front() = 0.f;
  cdf_.back() = 1.f;
}

float FootprintTable::cdf(float t) const {
  const float x = (t + static_cast<float>(cutoff_)) * cdf_scale_;
  if (!(x > 0.f)) return 0.f;
  const int last = static_cast<int>(cdf_.size()) - 1;
  if (x >= last) return 1.f;
  const int i = static_cast<int>(x);
  const float f = x - i;
  return cdf_[i] + f * (cdf_[i + 1] - cdf_[i]);
}

Projector::Projector(const Camera& camera, int width, int height, const glm::dvec3& spacing,
                     const KernelShape& kernel)
    : camera_(camera),
      orthographic_(camera.orthographic()),
      width_(width),
      height_(height),
      kernel_(kernel) {
  // The same frame as RayGenerator, so both backends see the same image.
  const RayGenerator rays(camera, width, height);
  forward_ = rays.forward();
  right_ = glm::normalize(glm::cross(forward_, camera.up));
  up_ = glm::cross(right_, forward_);
  const double half_h = orthographic_
                            ? 0.5 * camera.ortho_height
                            : std::tan(0.5 * camera.fov_degrees * std::numbers::pi / 180.0);
  scale_ = 0.5 * height / half_h;
  variance_ = kernel.sigma * kernel.sigma * spacing * spacing;
  volume_ = spacing.x * spacing.y * spacing.z;
  if (orthographic_) ortho_ = build({scale_ * right_, -scale_ * up_}, scale_);
}

glm::dvec3 Projector::project(const glm::dvec3& world) const {
  const glm::dvec3 p = world - camera_.eye;
  const double z = glm::dot(p, forward_);
  const double u = glm::dot(p, right_), v = glm::dot(p, up_);
  if (orthographic_) return {0.5 * width_ + scale_ * u, 0.5 * height_ - scale_ * v, z};
  return {0.5 * width_ + scale_ * u / z, 0.5 * height_ - scale_ * v / z, z};
}

glm::dvec3 Projector::towardsEye(const glm::dvec3& world) const {
  if (orthographic_) return -forward_;
  return glm::normalize(camera_.eye - world);
}

Footprint Projector::footprint(const glm::dvec3& world) const {
  if (orthographic_) return ortho_;
  // EWA: the local affine approximation of the perspective projection at the voxel.
  const glm::dvec3 p = world - camera_.eye;
  const double z = std::max(glm::dot(p, forward_), 1e-9);
  const double u = glm::dot(p, right_), v = glm::dot(p, up_);
  const glm::dvec3 jx = scale_ * (right_ / z - (u / (z * z)) * forward_);
  const glm::dvec3 jy = -scale_ * (up_ / z - (v / (z * z)) * forward_);
  return build({jx, jy}, scale_ / z);
}

Footprint Projector::build(const std::array<glm::dvec3, 2>& j, double pixels_per_world) const {
  // Screen covariance J Σ Jᵀ (Σ diagonal) plus the low-pass filter's.
  const double lp2 = kernel_.lowpass * kernel_.lowpass;
  const double sxx = glm::dot(j[0] * variance_, j[0]) + lp2;
  const double sxy = glm::dot(j[0] * variance_, j[1]);
  const double syy = glm::dot(j[1] * variance_, j[1]) + lp2;
  const double det = std::max(sxx * syy - sxy * sxy, 1e-300);
  const double cut = kernel_.cutoff();
  Footprint f;
  f.a = static_cast<float>(syy / det);
  f.b = static_cast<float>(-sxy / det);
  f.c = static_cast<float>(sxx / det);
  // The line integral through the centre: the kernel's integral V spread over the 2D Gaussian,
  // converted from per pixel² to per world² (the low-pass keeps the integral).
  // Divided by the truncated kernel's mass, so that the truncated kernel integrates to V too
  // and a lattice of them still reconstructs a constant (at radius 2σ the mass is only 0.86).
  const double mass = 1.0 - std::exp(-0.5 * cut * cut);
  f.norm = static_cast<float>(volume_ * pixels_per_world * pixels_per_world /
                              (2.0 * std::numbers::pi * std::sqrt(det) * mass));
  f.half_w = static_cast<float>(cut * std::sqrt(sxx));
  f.half_h = static_cast<float>(cut * std::sqrt(syy));
  f.depth_sigma = static_cast<float>(std::sqrt(glm::dot(forward_ * variance_, forward_)));
  return f;
}

}  // namespace svr::splat
