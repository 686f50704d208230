#pragma once
// What the viewer's page knows of a scene, as JSON (docs/viewer.md): the model, the image's
// planes, the initial view, and each light as the 3 × planes matrix that takes a pixel's S and T
// to linear sRGB under it at unit luminance, the scene's backdrop folded in. Mixing lights is
// mixing these matrices (they are linear in the light), so the page relights any mix without
// spectra. `svr view` serves it as /api/scene; `svr render --html` embeds it.

#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "renderers/scene/camera.h"
#include "renderers/scene/scene.h"
#include "renderers/model/scene_model.h"
#include "spectral/colorimetry.h"
#include "spectral/light_independent_image.h"

namespace svr {

struct PageLightContext {
  const ColourModel& model;
  const Observer& observer;
  std::optional<Spectrum> background;
  int t_channels = 1;
};

nlohmann::json pageLight(const PageLightContext& context, const std::string& name,
                         const Spectrum& spectrum);

// The samples the page should be sent: half floats halve the bytes, but where a model's light
// matrices cancel large coefficients (designed lights) their rounding shows. Half is chosen when
// relighting the half image under every scene light stays within one code value of the float
// image; the largest difference found is returned beside the choice.
struct SampleChoice {
  SampleStorage storage = SampleStorage::kHalf;
  int half_code_error = 0;
};
SampleChoice chooseSamples(const PageLightContext& context, const Scene& scene,
                           const LightIndependentImage& image);

nlohmann::json pageSceneInfo(const PageLightContext& context, const Scene& scene,
                             const SceneModel& chosen, const std::string& renderer,
                             const OrbitView& view, const SampleChoice& samples);

}  // namespace svr
