#include "renderers/shearwarp/shearwarp_renderer.h"

#include <fmt/format.h>
#include <omp.h>

#include <atomic>
#include <cmath>
#include <glm/geometric.hpp>

#include "renderers/shearwarp/intermediate_warp.h"
#include "renderers/shearwarp/shear_warp_factorization.h"
#include "renderers/shearwarp/shearwarp_kernel.h"
#include "spectral/error.h"
#include "renderers/core/channel_widths.h"
#include "renderers/registry.h"
#include "renderers/shearwarp/rle_volume.h"

namespace svr {
namespace {

using ScanlineFn = void (*)(const shearwarp::CompositeJob&, int, std::vector<int>&);

template <bool kSpectralT>
ScanlineFn pickKernel(int k) {
  return pickWidth(k, false, []<int N>() -> ScanlineFn {
    return &shearwarp::compositeScanline<N, kSpectralT>;
  });
}

// Sign-preserving power: factor-model transmission coefficients may dip slightly below zero,
// where a plain pow of a fractional exponent would give NaN.
float signedPow(float t, double r) {
  return static_cast<float>(std::copysign(std::pow(std::abs(static_cast<double>(t)), r), t));
}

}  // namespace

const BackendInfo& ShearWarpRenderer::info() const {
  static const BackendInfo info{
      "shearwarp", "Lacroute & Levoy shear-warp over run-length-encoded classified slices",
      {.perspective = false, .spectral_transmittance = true,
       .max_channels = shearwarp::kMaxChannels},
      {OptionSpec::integer("supersample", 1, 1, 4,
                           "intermediate pixels per voxel along each slice axis: less blur "
                           "under zoom, for time")}};
  return info;
}

std::uint64_t ShearWarpRenderer::workingBytes(const RenderRequest& req,
                                              const BackendOptions& options) const {
  const ClassifiedVolume& cv = req.volume;
  const shearwarp::ShearWarpFactorization view = shearwarp::factorizeView(
      req.camera, req.width, req.height, cv.dims, cv.spacing, options.integer("supersample"));
  return std::uint64_t(view.width) * std::uint64_t(view.height) *
         std::uint64_t(cv.k + cv.t_channels) * sizeof(float);
}

LightIndependentImage ShearWarpRenderer::renderImpl(const RenderRequest& req,
                                                    const BackendOptions& options,
                                                    ProgressCounter& progress) const {
  const ClassifiedVolume& cv = req.volume;
  const std::shared_ptr<const shearwarp::RleVolume> encoded = shearwarp::RleVolume::of(cv);
  const shearwarp::ShearWarpFactorization view = shearwarp::factorizeView(
      req.camera, req.width, req.height, cv.dims, cv.spacing, options.integer("supersample"));
  const shearwarp::AxisEncoding& encoding = encoded->encoding(view.axis);

  // Opacity and transmission for the slice spacing instead of the classification step.
  const double ratio = view.slice_spacing_world / cv.step_world;
  std::vector<float> alpha(cv.entries), transmission(cv.transmission.size());
  for (int e = 0; e < cv.entries; ++e)
    alpha[e] = 1.f - signedPow(1.f - cv.alpha[e], ratio);
  for (std::size_t i = 0; i < transmission.size(); ++i)
    transmission[i] = signedPow(cv.transmission[i], ratio);

  const RayGenerator rays(req.camera, req.width, req.height);
  const glm::dvec3 view_dir = -rays.forward();
  const glm::dvec3 light = req.light_direction ? glm::normalize(*req.light_direction) : view_dir;
  const glm::dvec3 half = glm::normalize(light + view_dir);

  shearwarp::IntermediateImage intermediate(view.width, view.height, cv.k, cv.t_channels);
  shearwarp::CompositeJob job{&cv,
                              &encoding,
                              &view,
                              alpha.data(),
                              transmission.data(),
                              static_cast<float>(req.termination),
                              PhongSetup(req.shading, light, half),
                              &intermediate};
  const ScanlineFn fn = cv.t_channels > 1 ? pickKernel<true>(cv.k) : pickKernel<false>(cv.k);
  progress.stage(view.height, 0.0, 0.95);
  // Each intermediate scanline only ever receives its own rays, so scanlines composite
  // independently through all slices: no barrier per slice.
#pragma omp parallel
  {
    std::vector<int> links;
#pragma omp for schedule(dynamic, 4)
    for (int v = 0; v < view.height; ++v) {
      fn(job, v, links);
      progress.advance();
    }
  }

  LightIndependentImage image(req.width, req.height, cv.k, cv.t_channels);
  shearwarp::warpToFinal(intermediate, view, image);
  return image;
}

namespace backends {
BackendEntry shearwarp() {
  return {ShearWarpRenderer().info(), [] { return std::make_unique<ShearWarpRenderer>(); }, {}, {}};
}
}  // namespace backends

}  // namespace svr
