#include "renderers/splat/splat_renderer.h"

#include <omp.h>

#include <algorithm>
#include <glm/vec2.hpp>

#include "renderers/kernels/splat_footprint.h"
#include "renderers/kernels/splat_settings.h"
#include "renderers/render/backend_entry.h"
#include "renderers/splat/direct_compositor.h"
#include "renderers/splat/sheet_compositor.h"
#include "renderers/splat/splat_coverage.h"
#include "renderers/splat/splat_list.h"
#include "base/error.h"

namespace svr {

const BackendInfo& SplatRenderer::info() const {
  static const BackendInfo info = [] {
    std::vector<OptionSpec> options = splat::splatOptionSpecs();
    options.push_back(OptionSpec::choice(
        "classification", {"auto", "post", "pre"},
        "post: splat the value, shade and highlight into each sheet and classify per sheet pixel "
        "(Mueller, Möller & Crawfis 1999: sharp at material edges and under zoom; sheet mode, "
        "scalar volumes); pre: classify at the voxels; auto: post where it applies"));
    return BackendInfo{"splat",
                       "Gaussian splats of the voxels, post- or pre-classified, sheet-buffer or "
                       "direct compositing",
                       {.perspective = true,
                        .spectral_transmittance = true,
                        .max_channels = splat::kMaxSplatChannels},
                       std::move(options)};
  }();
  return info;
}

namespace {

// Image rows a band takes (each composited by one thread, in order; the splats' bands).
constexpr int kBandRows = 16;

// Whether this render classifies per sheet pixel: `auto` does wherever it applies; asking for
// post where it cannot (direct compositing has no sheet to classify; a label map has no values
// between its voxels) is an error naming the key.
bool postClassified(const BackendOptions& options, const splat::SplatSettings& settings,
                    const ClassifiedVolume& cv) {
  const std::string& asked = options.choice("classification");
  if (asked == "pre") return false;
  const bool sheet = settings.mode == splat::SplatSettings::Mode::kSheet;
  if (asked == "post" && !sheet)
    throw Error("splat.classification=post needs splat.mode=sheet: direct compositing "
                "classifies at the voxels");
  if (asked == "post" && cv.labels)
    throw Error("splat.classification=post needs a scalar volume: a label map is classified at "
                "its voxels");
  return sheet && !cv.labels;
}

}  // namespace

std::uint64_t SplatRenderer::workingBytes(const RenderRequest& req,
                                          const BackendOptions& options) const {
  const splat::SplatSettings settings = splat::splatSettings(options);
  const ClassifiedVolume& cv = req.volume;
  const bool post = postClassified(options, settings, cv);
  const std::uint64_t voxels =
      splat::SplatVoxels::of(cv, post ? splat::SplatVoxels::Set::kReconstruction
                                      : splat::SplatVoxels::Set::kVisible)
          ->voxels()
          .size();
  // Per listed voxel: its position, depth, keep flag and order; three sort arrays; its splat
  // in list order and in depth order; its band range and about two band entries; a perspective
  // camera's footprint, in list order and in depth order.
  std::uint64_t per_voxel = sizeof(glm::vec2) + sizeof(float) + 1 + 4 + 3 * 4 +
                            2 * sizeof(splat::Splat) + 2 * 4 + 2 * 4;
  if (!req.camera.orthographic()) per_voxel += 2 * sizeof(splat::Footprint);
  // Each thread's sheet buffer: a band's rows of the image, up to 1 + k + kt floats a pixel.
  const std::uint64_t sheet = settings.mode == splat::SplatSettings::Mode::kSheet
                                  ? std::uint64_t(req.width) * kBandRows *
                                        std::uint64_t(1 + cv.k + cv.t_channels) * sizeof(float) *
                                        std::uint64_t(omp_get_max_threads())
                                  : 0;
  return voxels * per_voxel + sheet;
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
  const bool post = postClassified(options, settings, cv);
  const auto memory = pool_.take();
  const splat::SplatList list(
      cv, req, projector,
      post ? splat::SplatVoxels::Set::kReconstruction : splat::SplatVoxels::Set::kVisible,
      memory->list);
  const splat::SplatCoverage coverage(list, table, req.width, req.height);
  splat::Bands& bands = memory->bands;
  splat::bandsOf(coverage, kBandRows, bands);
  const float termination = static_cast<float>(req.termination);
  if (settings.mode == splat::SplatSettings::Mode::kSheet) {
    const double min_spacing = std::min({cv.spacing.x, cv.spacing.y, cv.spacing.z});
    const double thickness = settings.sheet_voxels * min_spacing;
    splat::compositeSheets(coverage, bands, thickness, post, termination, image, progress);
  } else {
    splat::compositeDirect(coverage, bands, termination, force_.dynamic_width, image, progress);
  }
  return image;
}

SplatRenderer::SplatRenderer(KernelForce force) : force_(force) {}
SplatRenderer::~SplatRenderer() = default;

namespace backends {
BackendEntry splat() { return {SplatRenderer().info(), [] { return std::make_unique<SplatRenderer>(); }, {}, {}}; }
}  // namespace backends

}  // namespace svr
