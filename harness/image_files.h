#pragma once
// Image files through OpenImageIO: the light-independent image as a k-channel OpenEXR
// ("S.00", "S.01", … then "T.00", …: names that sort in channel order), and relit 8-bit sRGB
// PNGs. Writes go to a temporary file renamed into place, so a failure never leaves a partial
// output file behind.

#include <cstdint>
#include <map>
#include <span>
#include <string>
#include <vector>

#include "spectral/light_independent_image.h"

namespace svr {

void writeLightIndependentExr(const LightIndependentImage& image, const std::string& path,
                              const std::map<std::string, std::string>& attributes);
// Throws svr::Error naming the file for a missing file, a non-EXR, or channels not named
// S.nn / T.nn in order.
LightIndependentImage readLightIndependentExr(const std::string& path,
                                              std::map<std::string, std::string>* attributes);

void writeSrgbPng(const std::vector<std::uint8_t>& rgb, int width, int height,
                  const std::string& path);
// The same PNG as bytes in memory (the Python module's Image._repr_png_ for Jupyter).
std::vector<std::uint8_t> encodeSrgbPng(std::span<const std::uint8_t> rgb, int width, int height);

}  // namespace svr
