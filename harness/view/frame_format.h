#pragma once
// The binary frame of svr view's /api/render and of svr render --html.

#include <nlohmann/json.hpp>
#include <string>

#include "spectral/light_independent_image.h"

namespace svr {

// The light-independent frame as the page reads it (docs/viewer.md): "SVRI", a little-endian
// uint32 byte count n, n bytes of JSON (the header given — width, height, channels, t_channels,
// render_ms, … — plus "samples": "half" or "float") padded with spaces to a multiple of 4, then
// each plane's width×height samples in the image's storage (IEEE half or single floats),
// little-endian, row 0 at the top: S planes first, then T.
std::string encodeFrame(const LightIndependentImage& image, nlohmann::json header);

}  // namespace svr
