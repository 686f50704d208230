#pragma once
// What the viewer's page knows of a scene, as JSON (docs/viewer.md): the model, the image's
// planes, the initial view, and each light as the 3 × planes matrix that takes a pixel's S and T
// to linear sRGB under it at unit luminance, the scene's backdrop folded in. Mixing lights is
// mixing these matrices (they are linear in the light), so the page relights any mix without
// spectra. `svr view` serves it as /api/scene; `svr render --html` embeds it.

#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "renderers/core/camera.h"
#include "renderers/core/scene.h"
#include "renderers/core/scene_model.h"
#include "spectral/colorimetry.h"

namespace svr {

struct PageLightContext {
  const ColourModel& model;
  const Observer& observer;
  std::optional<Spectrum> background;
  int t_channels = 1;
};

nlohmann::json pageLight(const PageLightContext& context, const std::string& name,
                         const Spectrum& spectrum);

nlohmann::json pageSceneInfo(const PageLightContext& context, const Scene& scene,
                             const SceneModel& chosen, const std::string& renderer,
                             const OrbitView& view);

}  // namespace svr
