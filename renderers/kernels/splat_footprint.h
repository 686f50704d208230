#pragma once
// Splat footprints (design.md §5, splat): a voxel's Gaussian reconstruction kernel integrated along
// the viewing rays gives a 2D Gaussian in the image. For orthographic views that footprint is the
// same for every voxel; perspective (and, in general, anisotropic spacing) makes it elliptical:
// the EWA footprint of Zwicker et al. 2001, the kernel's covariance mapped through the local
// Jacobian of the projection, plus a screen-space low-pass that keeps zoomed-out footprints at
// least about a pixel wide. A footprint is evaluated through one precomputed radial table of
// exp(−q/2), indexed by the squared Mahalanobis distance q — or, the one footprint of an
// orthographic view, exactly in factors (splat/footprint_factors.h) — and sheets take their
// share of a kernel from a precomputed table of the normal CDF.

#include <array>
#include <glm/vec3.hpp>
#include <vector>

#include "renderers/scene/camera.h"

namespace svr::splat {

// The kernel, in voxels: a Gaussian of standard deviation `sigma` along each axis (times the
// spacing), truncated at `radius` (Mahalanobis, so the truncation is an ellipsoid).
struct KernelShape {
  double sigma = 0.55;
  double radius = 2.0;
  double lowpass = 0.0;                             // screen-space low-pass filter σ, pixels
  double cutoff() const { return radius / sigma; }  // truncation in units of σ
};

// Sheet-buffer compositing cuts a kernel in depth at ±2σ, not at its truncation radius (±3.6σ
// by default): the 2.3% of its mass in each tail goes to the sheet next to it, less than a
// voxel away, and the shares still sum to exactly 1 over any run of sheets. A splat then
// reaches 3–4 sheets of a voxel instead of 4–5. Measured (256², factor:6, mean ΔE2000 against
// the raycaster): engine 1.694, frog 1.595 → 1.594, cthead_xray_zoom 2.710, unchanged to the
// third decimal; CPU sheet frames at 512² a quarter faster.
inline constexpr double kSheetDepthCut = 2.0;

// A footprint in the image: line integral of the kernel through pixel offset (dx, dy) is
// norm · exp(−q/2), q = a dx² + 2 b dx dy + c dy², for q < cutoff²; zero outside.
struct Footprint {
  float a, b, c;         // inverse of the screen covariance (pixels⁻²)
  float norm;            // world length at the centre: V s² / (2π √det Σ_px · truncated mass)
  float half_w, half_h;  // bounding half extents, pixels
  float depth_sigma;     // σ of the kernel along the view axis, world units
};

// exp(−q/2) on [0, cutoff²] and Φ(t) on [−cutoff, cutoff], both tabulated once per render.
class FootprintTable {
 public:
  explicit FootprintTable(double cutoff, int entries = 4096);
  double cutoff() const { return cutoff_; }
  float cutoffSquared() const { return cutoff2_; }
  // exp(−q/2) for q in [0, cutoff²); the caller has tested q < cutoff².
  float gaussian(float q) const { return exp_[static_cast<int>(q * exp_scale_)]; }
  // The fraction of the truncated 1D kernel below t (σ units), clamped: 0 at −cutoff, 1 at
  // +cutoff, so the fractions of a kernel over consecutive sheets sum to exactly 1.
  float cdf(float t) const;

 private:
  double cutoff_;
  float cutoff2_, exp_scale_, cdf_scale_;
  std::vector<float> exp_, cdf_;
};

// Maps voxels to image positions and footprints for one camera, image size and volume.
class Projector {
 public:
  Projector(const Camera& camera, int width, int height, const glm::dvec3& spacing,
            const KernelShape& kernel);
  bool orthographic() const { return orthographic_; }
  // Image position (pixels, pixel centres at +0.5) and depth along the view axis (world).
  glm::dvec3 project(const glm::dvec3& world) const;
  Footprint footprint(const glm::dvec3& world) const;
  // Unit vector from the point towards the eye.
  glm::dvec3 towardsEye(const glm::dvec3& world) const;

 private:
  Footprint build(const std::array<glm::dvec3, 2>& jacobian, double pixels_per_world) const;
  Camera camera_;
  bool orthographic_;
  int width_, height_;
  glm::dvec3 forward_, right_, up_;
  double scale_;         // pixels per world unit (orthographic) or per unit of u/z (perspective)
  glm::dvec3 variance_;  // kernel variance per world axis
  double volume_;        // kernel integral: the voxel's volume
  KernelShape kernel_;
  Footprint ortho_{};
};

}  // namespace svr::splat
