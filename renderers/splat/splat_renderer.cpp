#include "renderers/splat/splat_renderer.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "renderers/splat/direct_compositor.h"
#include "renderers/splat/footprint.h"
#include "renderers/splat/sheet_compositor.h"
#include "renderers/splat/splat_list.h"
#include "spectral/error.h"
#include "spectral/json_reader.h"

namespace svr {

SplatSettings readSplatSettings(const nlohmann::json& options, const std::string& backend) {
  SplatSettings s;
  if (!options.is_object() || !options.contains(backend)) return s;
  const JsonReader r(options.at(backend), "render options", backend);
  if (!r.isObject()) r.fail(fmt::format("expected an object, got {}", r.json().dump()));
  const std::string mode = r.string("mode", "sheet");
  if (mode == "direct")
    s.mode = SplatSettings::Mode::kDirect;
  else if (mode != "sheet")
    r.at("mode").fail(fmt::format("'{}' is not sheet or direct", mode));
  s.sigma = r.number("sigma", s.sigma, 0.25, 4.0);
  s.radius = r.number("radius", s.radius, 0.5, 8.0);
  s.sheet_voxels = r.number("sheet", s.sheet_voxels, 0.1, 8.0);
  s.lowpass = r.number("lowpass", s.lowpass, 0.0, 4.0);
  r.rejectUnknownKeys();
  return s;
}

LightIndependentImage SplatRenderer::render(const RenderRequest& req,
                                            const ProgressFn& progress) const {
  const SplatSettings settings = readSplatSettings(req.options);
  const ClassifiedVolume& cv = req.volume;
  LightIndependentImage image(req.width, req.height, cv.k, cv.t_channels);
  const splat::KernelShape kernel{settings.sigma, settings.radius, settings.lowpass};
  const splat::Projector projector(req.camera, req.width, req.height, cv.spacing, kernel);
  const splat::FootprintTable table(kernel.cutoff());
  const splat::SplatList list(cv, req, projector);
  constexpr int kBandRows = 8;
  const splat::Bands bands = splat::bandsOf(list, req.height, kBandRows);
  const float termination = static_cast<float>(req.termination);
  if (settings.mode == SplatSettings::Mode::kSheet) {
    const double min_spacing = std::min({cv.spacing.x, cv.spacing.y, cv.spacing.z});
    const double thickness = settings.sheet_voxels * min_spacing;
    splat::compositeSheets(list, table, bands, thickness, termination, image, progress);
  } else {
    splat::compositeDirect(list, table, bands, termination, image, progress);
  }
  // Numeric failure is reported, never written out.
  for (int p = 0; p < image.planes(); ++p) {
    const auto plane = image.planeFloat(p);
    for (std::size_t i = 0; i < plane.size(); ++i)
      if (!std::isfinite(plane[i]))
        throw Error(fmt::format("splat: non-finite value {} in channel {} at pixel ({}, {})",
                                plane[i], p, i % req.width, i / req.width));
  }
  return image;
}

}  // namespace svr
