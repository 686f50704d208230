#pragma once
// Image-aligned sheet-buffer compositing (Mueller & Crawfis 1998), the correct mode: the
// kernels are sliced by sheets parallel to the image plane, `thickness` apart in depth; within a
// sheet the slices add up (optical depth and opacity-weighted colour per pixel), and the sheets
// are composited front to back like the raycaster's samples, so overlapping kernels do not bleed
// into each other and the result does not depend on the order within a sheet. `post`: the
// sheets hold the reconstructed value, classified per sheet pixel (the list must hold the
// reconstruction's voxels); otherwise the splats' own classified coefficients.

#include "renderers/render/renderer.h"
#include "renderers/kernels/splat_footprint.h"
#include "renderers/splat/splat_coverage.h"

namespace svr::splat {

void compositeSheets(const SplatCoverage& coverage, const Bands& bands, double thickness,
                     bool post, float termination, LightIndependentImage& image,
                     ProgressCounter& progress);

}  // namespace svr::splat
