#pragma once
// One backend against the raycaster on a scene, with the same colour model: the harness's
// algorithm-only figure (harness/comparison.h, vs_raycast), without its spectral reference and
// the runs' exact twins, which issue 49's bench and corpus test do not need. Each frame is a
// steady one (the second of its classification), relit under every light and mix of the scene.

#include <memory>
#include <string>
#include <vector>

#include "harness/render_session.h"

namespace svr {

// A frame of the scene by one backend with one model, with the scene's lights, then its mixes,
// at unit luminance.
struct BackendFrame {
  SceneModel model;
  LightIndependentImage image;
  double ms = 0.0;  // the steady frame's
  std::vector<Spectrum> lights;
};

// Throws svr::Error when the backend cannot render the scene. options: BACKEND.KEY=VALUE over
// the scene's render.options (as svr's --option).
BackendFrame renderBackendFrame(const std::shared_ptr<const SessionSpectra>& spectra,
                                const Scene& scene, const std::string& renderer,
                                const std::string& model,
                                const std::vector<std::string>& options = {});

struct Agreement {
  enum class Status { kRendered, kSkipped, kFailed } status = Status::kRendered;
  // Means over the lights and mixes of the mean and p95 ΔE2000 against the raycaster.
  double vs_raycast = NAN, vs_raycast_p95 = NAN, ms = NAN;
  bool within_tolerance = false;  // the harness's de_vs_raycast tolerances, under every light
  std::string note;               // why it was skipped (the camera) or failed (the error)
};

// `raycast`: the raycaster's frame of the scene with `model`.
Agreement agreementWithRaycast(const std::shared_ptr<const SessionSpectra>& spectra,
                               const Scene& scene, const BackendFrame& raycast,
                               const std::string& renderer, const std::string& model,
                               const std::vector<std::string>& options = {});

}  // namespace svr
