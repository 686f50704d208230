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
#include "spectral/json_reader.h"

namespace svr {
namespace {

using ScanlineFn = void (*)(const shearwarp::CompositeJob&, int, std::vector<int>&);

// The single list of channel counts with a compiled kernel; anything else is dynamic.
#define SVR_SHEARWARP_WIDTHS(X) X(3) X(4) X(6) X(8)

template <bool kSpectralT>
ScanlineFn pickKernel(int k) {
  switch (k) {
#define SVR_CASE(N) \
  case N:           \
    return &shearwarp::compositeScanline<N, kSpectralT>;
    SVR_SHEARWARP_WIDTHS(SVR_CASE)
#undef SVR_CASE
    default:
      return &shearwarp::compositeScanline<0, kSpectralT>;
  }
}

struct Options {
  int supersample = 1;
};

Options readOptions(const nlohmann::json& options, const std::string& name) {
  Options o;
  if (!options.is_object() || !options.contains(name)) return o;
  const JsonReader r(options.at(name), "render.options", name);
  if (!r.isObject()) r.fail(fmt::format("expected an object, got {}", r.json().dump()));
  o.supersample = r.integer("supersample", o.supersample, 1, 4);
  r.rejectUnknownKeys();
  return o;
}

// Sign-preserving power: factor-model transmission coefficients may dip slightly below zero,
// where a plain pow of a fractional exponent would give NaN.
float signedPow(float t, double r) {
  return static_cast<float>(std::copysign(std::pow(std::abs(static_cast<double>(t)), r), t));
}

}  // namespace

LightIndependentImage ShearWarpRenderer::render(const RenderRequest& request,
                                                const ProgressFn& progress) const {
  const shearwarp::RleVolume encoded(request.volume);
  return render(encoded, request, progress);
}

LightIndependentImage ShearWarpRenderer::render(const shearwarp::RleVolume& encoded,
                                                const RenderRequest& req,
                                                const ProgressFn& progress) const {
  const ClassifiedVolume& cv = req.volume;
  if (&encoded.classified() != &cv)
    throw Error("shearwarp: the encoding was made for another classified volume");
  if (cv.k > shearwarp::kMaxChannels)
    throw Error(fmt::format("shearwarp: {} channels exceed the supported {}", cv.k,
                            shearwarp::kMaxChannels));
  const Options options = readOptions(req.options, name());
  const shearwarp::ShearWarpFactorization view = shearwarp::factorizeView(
      req.camera, req.width, req.height, cv.dims, cv.spacing, options.supersample);
  const shearwarp::AxisEncoding& encoding = encoded.encoding(view.axis);

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
  std::atomic<int> done{0};
  // Each intermediate scanline only ever receives its own rays, so scanlines composite
  // independently through all slices: no barrier per slice.
#pragma omp parallel
  {
    std::vector<int> links;
#pragma omp for schedule(dynamic, 4)
    for (int v = 0; v < view.height; ++v) {
      fn(job, v, links);
      const int n = ++done;
      if (progress && omp_get_thread_num() == 0 && n % 16 == 0)
        progress(0.95 * n / view.height);
    }
  }

  LightIndependentImage image(req.width, req.height, cv.k, cv.t_channels);
  shearwarp::warpToFinal(intermediate, view, image);
  if (progress) progress(1.0);
  // Numeric failure is reported, never written out.
  for (int p = 0; p < image.planes(); ++p) {
    const auto plane = image.planeFloat(p);
    for (std::size_t i = 0; i < plane.size(); ++i)
      if (!std::isfinite(plane[i]))
        throw Error(fmt::format("shearwarp: non-finite value {} in channel {} at pixel ({}, {})",
                                plane[i], p, i % req.width, i / req.width));
  }
  return image;
}

}  // namespace svr
