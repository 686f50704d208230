#include "renderers/raycast/raycast_renderer.h"

#include "renderers/core/channel_widths.h"
#include "renderers/raycast/raycast_kernel.h"
#include "renderers/registry.h"

namespace svr {
namespace {

using TileFn = void (*)(const raycast::TileJob&);

template <bool kSpectralT>
TileFn pickKernel(int k, bool dynamic_width) {
  return pickWidth(k, dynamic_width,
                   []<int N>() -> TileFn { return &raycast::traceTile<N, kSpectralT>; });
}

}  // namespace

const BackendInfo& RaycastRenderer::info() const {
  static const BackendInfo info{
      "raycast", "a ray per pixel, trilinear samples, Phong; the reference backend",
      {.perspective = true, .spectral_transmittance = true, .max_channels = raycast::kMaxChannels},
      {}};
  return info;
}

LightIndependentImage RaycastRenderer::renderImpl(const RenderRequest& req, const BackendOptions&,
                                                  ProgressCounter& progress) const {
  const ClassifiedVolume& cv = req.volume;
  LightIndependentImage image(req.width, req.height, cv.k, cv.t_channels);
  const RayGenerator rays(req.camera, req.width, req.height);
  const TileFn fn = cv.t_channels > 1 ? pickKernel<true>(cv.k, dynamic_width_)
                                      : pickKernel<false>(cv.k, dynamic_width_);
  constexpr int kTile = 16;
  const int tiles_x = (req.width + kTile - 1) / kTile, tiles_y = (req.height + kTile - 1) / kTile;
  const int tiles = tiles_x * tiles_y;
  progress.stage(tiles);
#pragma omp parallel for schedule(dynamic)
  for (int t = 0; t < tiles; ++t) {
    const int tx = t % tiles_x, ty = t / tiles_x;
    raycast::TileJob job{&cv, &rays, &req, &image, tx * kTile, ty * kTile,
                         std::min((tx + 1) * kTile, req.width),
                         std::min((ty + 1) * kTile, req.height)};
    fn(job);
    progress.advance();
  }
  return image;
}

namespace backends {
BackendEntry raycast() {
  return {RaycastRenderer().info(), [] { return std::make_unique<RaycastRenderer>(); }, {}, {}};
}
}  // namespace backends

}  // namespace svr
