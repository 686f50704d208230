#pragma once
// The settings of splatting, shared by the two backends that splat (splat on the CPU, gl on
// OpenGL): one description of their options, read the same way under either backend's name.

#include <vector>

#include "renderers/render/backend_options.h"
#include "renderers/kernels/splat_footprint.h"

namespace svr::splat {

struct SplatSettings {
  enum class Mode { kSheet, kDirect } mode = Mode::kSheet;
  KernelShape kernel;         // σ, truncation radius and screen low-pass
  double sheet_voxels = 1.0;  // sheet thickness in voxels
};

// mode, sigma, radius, sheet, lowpass — with the defaults chosen by measurement (splat/README).
std::vector<OptionSpec> splatOptionSpecs();
// `mode_key`: the option holding sheet or direct ("splat_mode" in the gl backend, whose own
// `mode` chooses between ray casting and splatting).
SplatSettings splatSettings(const BackendOptions& options, const std::string& mode_key = "mode");

}  // namespace svr::splat
