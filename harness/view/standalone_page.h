#pragma once
// `svr render --html`: the viewer's page as one file that works offline with no server — the
// page's CSS and scripts inlined, the scene's page data and the light-independent frame
// embedded — with the dial, the sliders and relighting, and the camera it was rendered with.

#include <nlohmann/json.hpp>
#include <string>

#include "spectral/light_independent_image.h"

namespace svr {

std::string standalonePage(const nlohmann::json& scene_info, const LightIndependentImage& image);

}  // namespace svr
