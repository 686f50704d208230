#include "renderers/raycast/raycast_renderer.h"

#include <fmt/format.h>

#include <atomic>
#include <cmath>
#include <omp.h>

#include "renderers/raycast/raycast_kernel.h"
#include "spectral/error.h"
#include "spectral/json_reader.h"

namespace svr {
namespace {

using TileFn = void (*)(const raycast::TileJob&);

// The single list of channel counts with a compiled kernel; anything else is dynamic.
#define SVR_RAYCAST_WIDTHS(X) X(3) X(4) X(6) X(8)

template <bool kSpectralT>
TileFn pickKernel(int k, bool dynamic_width) {
  if (!dynamic_width) switch (k) {
#define SVR_CASE(N) \
  case N:           \
    return &raycast::traceTile<N, kSpectralT>;
      SVR_RAYCAST_WIDTHS(SVR_CASE)
#undef SVR_CASE
      default:
        break;
    }
  return &raycast::traceTile<0, kSpectralT>;
}

}  // namespace

LightIndependentImage RaycastRenderer::render(const RenderRequest& req,
                                              const ProgressFn& progress) const {
  // raycast reads no options: any key given for it is a typo or meant for another backend.
  if (req.options.is_object() && req.options.contains(name())) {
    const JsonReader options(req.options.at(name()), "render.options", name());
    if (!options.isObject()) options.fail("expected an object of options for this backend");
    options.rejectUnknownKeys();
  }
  const ClassifiedVolume& cv = req.volume;
  if (cv.k > raycast::kMaxChannels)
    throw Error(fmt::format("raycast: {} channels exceed the supported {}", cv.k,
                            raycast::kMaxChannels));
  LightIndependentImage image(req.width, req.height, cv.k, cv.t_channels);
  const RayGenerator rays(req.camera, req.width, req.height);
  const TileFn fn = cv.t_channels > 1 ? pickKernel<true>(cv.k, dynamic_width_)
                                      : pickKernel<false>(cv.k, dynamic_width_);
  constexpr int kTile = 16;
  const int tiles_x = (req.width + kTile - 1) / kTile, tiles_y = (req.height + kTile - 1) / kTile;
  const int tiles = tiles_x * tiles_y;
  std::atomic<int> done{0};
#pragma omp parallel for schedule(dynamic)
  for (int t = 0; t < tiles; ++t) {
    const int tx = t % tiles_x, ty = t / tiles_x;
    raycast::TileJob job{&cv, &rays, &req, &image, tx * kTile, ty * kTile,
                         std::min((tx + 1) * kTile, req.width),
                         std::min((ty + 1) * kTile, req.height)};
    fn(job);
    const int n = ++done;
    if (progress && omp_get_thread_num() == 0) progress(static_cast<double>(n) / tiles);
  }
  // Numeric failure is reported, never written out.
  for (int p = 0; p < image.planes(); ++p) {
    const auto plane = image.planeFloat(p);
    for (std::size_t i = 0; i < plane.size(); ++i)
      if (!std::isfinite(plane[i]))
        throw Error(fmt::format("raycast: non-finite value {} in channel {} at pixel ({}, {})",
                                plane[i], p, i % req.width, i / req.width));
  }
  return image;
}

}  // namespace svr
