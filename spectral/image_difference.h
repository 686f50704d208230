#pragma once
// ΔE2000 between two light-independent images relit under the same light: the accuracy metric
// of the comparison harness and of the backend tests (design.md §6). Statistics are over covered
// pixels, those where either image's transmittance has fallen below `coverage` (the volume is
// there); the map holds ΔE2000 per pixel (0 where not covered).

#include <optional>
#include <vector>

#include "spectral/colour_model.h"
#include "spectral/light_independent_image.h"
#include "spectral/model_error.h"

namespace svr {

struct ImageDifference {
  ErrorStats stats;
  std::vector<float> map;  // width × height, row 0 at the top
  std::size_t covered = 0;
};

// Each image is relit with its own model (they may differ: e.g. factor:6 against the
// spectral:81 reference) under the light given as a spectrum at unit luminance. Lab is taken
// against that light's white (Y = 1). With a background (a backdrop's reflectance, seen through
// T) every pixel counts, the backdrop's own colour included. Throws svr::Error for different
// sizes or an image without transmittance.
ImageDifference compareRelit(const LightIndependentImage& a, const ColourModel& model_a,
                             const LightIndependentImage& b, const ColourModel& model_b,
                             const Spectrum& unit_light, const Xyz& white,
                             double coverage = 0.98,
                             const std::optional<Spectrum>& background = std::nullopt);

}  // namespace svr
