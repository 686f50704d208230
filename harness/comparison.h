#pragma once
// The comparison at the heart of the harness (design.md §6): one scene rendered by the reference
// (raycast, spectral:81, step ≤ 0.25 voxel, no early termination) and by any backend × colour
// model; every run relit under every scene light and mix and measured against the reference
// (colour-model plus algorithm error, and the two apart: LightResult) and against the raycaster
// with the same model (algorithm error alone), with timings. compare, sweep and demo are built
// on it.

#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "harness/reference_step.h"
#include "harness/render_session.h"
#include "renderers/scene/scene.h"
#include "renderers/registry.h"
#include "renderers/model/scene_model.h"
#include "spectral/colorimetry.h"
#include "spectral/colour_model.h"
#include "spectral/light_independent_image.h"
#include "spectral/model_error.h"

namespace svr {

// The reference every run is measured against (design.md §6): the reference backend (the
// raycaster, as the registry names it) with the full spectral model, a fine step and every
// sample composited.
// Its step is converged (reference_step.h): it starts at the scene's step, or
// max_start_voxels if finer, and is halved until halving it again changes little.
struct Reference {
  std::string renderer = referenceRendererName();
  double max_start_voxels = 0.25;
  double termination = 0.0;    // no early termination
  static std::string model();  // "spectral:81": every sample of the standard grid
  double startStepVoxels(const Scene& scene) const;
  std::string label() const;   // "raycast spectral:81"
  nlohmann::json toJson(const ReferenceStep& step, double render_ms) const;
};

struct RunSpec {
  std::string renderer = "raycast";
  std::string model = "factor:6";
  nlohmann::json options = nlohmann::json::object();  // backend options, keyed by backend
  std::string label() const;                           // "splat factor:6 {mode: direct}"
};

// The total error (vs_reference) splits in two (issue 51), each measured against the same
// backend and options rendered with spectral:81 at the run's own step and termination (the
// run's "exact twin"):
//   model_error     the run against its exact twin: what the colour model alone costs;
//   sampling_error  the exact twin against the reference: what the step, early termination and
//                   the backend's resampling cost, whatever the model.
struct LightResult {
  std::string light;
  ErrorStats vs_reference;
  ErrorStats model_error, sampling_error;
  std::optional<ErrorStats> vs_raycast;  // empty for the raycaster itself
  double transmittance_error = 0.0;      // mean |ΔT| (luminance-weighted) over covered pixels
  std::vector<float> error_map;          // ΔE2000 against the reference, per pixel
  std::vector<std::uint8_t> relit;       // sRGB8
};

struct RunResult {
  RunSpec spec;
  std::string model_name, model_description;
  nlohmann::json model_choice;  // SceneModel::record(): auto's choice and the error behind it
  int k = 0;
  // render: a steady frame (the same view rendered again, with what the backend keeps per
  // classification already built: encodings, gradients, uploads); first_render: the first frame
  // of the classification, which builds them. relight: per light.
  double classify_ms = 0.0, render_ms = 0.0, first_render_ms = 0.0, relight_ms = 0.0;
  std::vector<LightResult> lights;
};

// A run that ended in an error (training, non-finite output, memory, a backend option this
// scene cannot take): the harness records it with its error and reports the runs that worked
// (issue 49).
struct FailedRun {
  RunSpec spec;
  std::string error;
};

// A named light or mix of the scene, as a unit-luminance spectrum.
struct SceneIllumination {
  std::string name;
  Spectrum spectrum;
};

class ComparisonSession {
 public:
  ComparisonSession(Scene scene, const std::string& data_dir);

  const Scene& scene() const { return scene_; }
  const std::vector<SceneIllumination>& illuminations() const { return illuminations_; }
  double referenceMs() const { return reference_ms_; }
  const ReferenceStep& referenceStep() const { return reference_step_; }
  const LightIndependentImage& reference() const { return reference_; }
  const ColourModel& referenceModel() const { return *reference_model_; }

  // Renders and measures one run. Throws svr::Error for unknown renderers or bad options.
  RunResult run(const RunSpec& spec);
  // run(spec), or the failure it ended in: an svr::Error or std::bad_alloc. A cancelled render
  // or an interrupt is no failure of the run; it propagates.
  std::variant<RunResult, FailedRun> tryRun(const RunSpec& spec);
  // Why this backend cannot render the scene's view (a perspective camera for shear-warp), or
  // nothing; the harness skips such runs with this note instead of failing.
  std::optional<std::string> unsupported(const std::string& renderer) const;

 private:
  struct Rendered {
    SceneModel chosen;
    LightIndependentImage image;
    double classify_ms, first_render_ms, render_ms;  // render_ms: steady (first when !steady)
  };
  // steady: render the view a second time and time that too.
  Rendered render(const std::string& renderer, const std::string& model,
                  const nlohmann::json& options, double step_voxels, double termination,
                  bool steady = false);

  // Rendered at the scene's own sampling once per key (the raycaster per model for the
  // algorithm-only error; a run's exact twin per backend and options).
  const Rendered& renderOnce(std::map<std::string, Rendered>& cache, const std::string& key,
                             const std::string& renderer, const std::string& model,
                             const nlohmann::json& options);

  Scene scene_;
  std::shared_ptr<const SessionSpectra> spectra_;
  std::vector<SceneIllumination> illuminations_;
  std::unique_ptr<ColourModel> reference_model_;
  ReferenceStep reference_step_;
  LightIndependentImage reference_;
  double reference_ms_ = 0.0;
  std::map<std::string, Rendered> raycast_by_model_;  // for the algorithm-only error
  std::map<std::string, Rendered> exact_by_backend_;  // runs' exact twins, by backend and options
};

// Tolerances: one table of defaults per backend algorithm (gl's two modes are two algorithms),
// overridden by the scene's "tolerances" ({"de_mean": 8, "shearwarp": {"de_vs_raycast_mean":
// 3}}; a backend's key covers all its modes). backend_options: the run's options for this
// backend, the scene's render.options with the run's over them ({"mode": "splat"}).
struct Tolerance {
  std::string metric;  // "de_mean", "de_p95", "de_vs_raycast_mean", "de_vs_raycast_p95"
  double limit;
};
std::vector<Tolerance> tolerancesFor(const std::string& renderer, const nlohmann::json& scene,
                                     const nlohmann::json& backend_options = {});
// The run's options for its backend: scene_options[renderer] (render.options) with the run's
// own over them.
nlohmann::json runBackendOptions(const RunSpec& spec, const nlohmann::json& scene_options);

struct Exceedance {
  std::string run, light, metric;
  double value, tolerance;
  std::string str() const;
};
std::vector<Exceedance> checkTolerances(const RunResult& run, const nlohmann::json& scene,
                                        const nlohmann::json& scene_options = {});

}  // namespace svr
