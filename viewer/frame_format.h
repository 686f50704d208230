#pragma once
#include <nlohmann/json.hpp>
#include <string>

#include "spectral/light_independent_image.h"

namespace svr {

// The light-independent frame as the page reads it (docs/viewer.md): "SVRI", a little-endian
// uint32 byte count n, n bytes of JSON (width, height, channels, t_channels, render_ms, …)
// padded with spaces to a multiple of 4, then each plane's width×height IEEE half floats,
// little-endian, row 0 at the top: S planes first, then T.
std::string encodeFrame(const LightIndependentImage& image, const nlohmann::json& header);


}  // namespace svr
