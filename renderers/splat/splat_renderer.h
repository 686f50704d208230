#pragma once
// The splatting backend (DESIGN §5, issue 5): every voxel that scatters or absorbs is a Gaussian
// kernel projected to an image footprint (footprint.h: one table for orthographic views, EWA
// ellipses with a screen-space low-pass for perspective), composited either through
// image-aligned sheet buffers (sheet_compositor.h, the default) or splat by splat
// (direct_compositor.h). OpenMP over fixed bands of image rows: identical bytes for any number
// of threads.
//
// Options, under options["splat"]:
//   mode     "sheet" | "direct"                  (default sheet)
//   sigma    kernel σ in voxels                  (default 0.7)
//   radius   kernel truncation radius in voxels  (default 2.5)
//   sheet    sheet thickness in voxels           (default: the scene's step)
//   lowpass  screen-space low-pass σ in pixels   (default 0: the raycaster
//            point-samples too; 0.3 raised the engine's ΔE2000 against it from 2.7 to 4.1)

#include <string>

#include "renderers/core/renderer.h"

namespace svr {

struct SplatSettings {
  enum class Mode { kSheet, kDirect } mode = Mode::kSheet;
  double sigma = 0.7;
  double radius = 2.5;
  double sheet_voxels = 0.0;  // 0: the classification step
  double lowpass = 0.0;
};

// Reads options["splat"] (unknown keys and out-of-range values are svr::Error).
SplatSettings readSplatSettings(const nlohmann::json& options);

class SplatRenderer final : public Renderer {
 public:
  std::string name() const override { return "splat"; }
  LightIndependentImage render(const RenderRequest& request,
                               const ProgressFn& progress) const override;
};

}  // namespace svr
