#pragma once
// Composite-every-splat, the fast mode: each splat's whole line integral is composited front to
// back in the order of the voxel centres' depths. Overlapping kernels are composited as if one
// lay wholly in front of the other, so colours bleed, and the order flips (pops) as the view
// turns; kept because the harness charts that difference against the sheet mode.

#include "renderers/render/renderer.h"
#include "renderers/kernels/splat_footprint.h"
#include "renderers/splat/splat_coverage.h"

namespace svr::splat {

// dynamic_width: the any-k loop even where k has a compiled width (tests: the same bytes).
void compositeDirect(const SplatCoverage& coverage, const Bands& bands, float termination,
                     bool dynamic_width, LightIndependentImage& image, ProgressCounter& progress);

}  // namespace svr::splat
