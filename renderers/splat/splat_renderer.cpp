#include "renderers/splat/splat_renderer.h"

#include <algorithm>

#include "renderers/core/splat_footprint.h"
#include "renderers/core/splat_settings.h"
#include "renderers/registry.h"
#include "renderers/splat/direct_compositor.h"
#include "renderers/splat/sheet_compositor.h"
#include "renderers/splat/splat_list.h"

namespace svr {

const BackendInfo& SplatRenderer::info() const {
  static const BackendInfo info{
      "splat", "Gaussian splats of the pre-classified voxels, sheet-buffer or direct compositing",
      {.perspective = true, .spectral_transmittance = true, .max_channels = 128},
      splat::splatOptionSpecs()};
  return info;
}

LightIndependentImage SplatRenderer::renderImpl(const RenderRequest& req,
                                                const BackendOptions& options,
                                                ProgressCounter& progress) const {
  const splat::SplatSettings settings = splat::splatSettings(options);
  const ClassifiedVolume& cv = req.volume;
  LightIndependentImage image(req.width, req.height, cv.k, cv.t_channels);
  const splat::Projector projector(req.camera, req.width, req.height, cv.spacing,
                                   settings.kernel);
  const splat::FootprintTable table(settings.kernel.cutoff());
  const splat::SplatList list(cv, req, projector);
  constexpr int kBandRows = 8;
  const splat::Bands bands = splat::bandsOf(list, req.height, kBandRows);
  const float termination = static_cast<float>(req.termination);
  if (settings.mode == splat::SplatSettings::Mode::kSheet) {
    const double min_spacing = std::min({cv.spacing.x, cv.spacing.y, cv.spacing.z});
    const double thickness = settings.sheet_voxels * min_spacing;
    splat::compositeSheets(list, table, bands, thickness, termination, image, progress);
  } else {
    splat::compositeDirect(list, table, bands, termination, image, progress);
  }
  return image;
}

namespace backends {
BackendEntry splat() { return {SplatRenderer().info(), [] { return std::make_unique<SplatRenderer>(); }, {}, {}}; }
}  // namespace backends

}  // namespace svr
