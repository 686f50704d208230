#pragma once
// The reference's step, chosen so that the reference is converged (issue 51). The harness used
// to take the scene's step or 0.25 voxel if finer; on random scenes that was up to 1.5 mean
// ΔE2000 from the converged image. Now the step starts there and is halved until halving it
// once more changes the image by at most `target` mean ΔE2000 (the worst light or mix),
// probed small: the registry's reference backend with spectral:81, no early termination, 96
// pixels on the longer side (as auto's model probe). The error falls about linearly with the
// step, so the chosen image is then within about `target` of the limit.

#include <nlohmann/json.hpp>
#include <string>

#include "renderers/scene/scene.h"
#include "spectral/colorimetry.h"

namespace svr {

struct ReferenceStep {
  double step_voxels = 0.25;
  double halving_de2000 = 0.0;  // mean ΔE2000 (worst light) between this step and its half
  bool converged = false;       // halving_de2000 ≤ target (else the finest step was reached)
  double target = 0.1, finest_voxels = 1.0 / 16;
  std::string probe_size;  // "96×96"
  double probe_ms = 0.0;
  nlohmann::json toJson() const;
};

inline constexpr double kReferenceStepTarget = 0.1;

// Starts at `start_voxels` and halves it only while the half is ≥ `finest_voxels` (1/16
// voxel: issue 51's converged step); the probe renders the chosen step's half to measure it. A
// start finer than finest_voxels is kept (the reference is never coarser than the scene).
ReferenceStep convergedReferenceStep(const Scene& scene, const Observer& observer,
                                     double start_voxels, double target = kReferenceStepTarget,
                                     double finest_voxels = 1.0 / 16);

}  // namespace svr
