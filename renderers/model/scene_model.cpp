#include "renderers/model/scene_model.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <optional>

#include "base/error.h"
#include "renderers/model/factor_choice.h"
#include "spectral/componentwise_model.h"

namespace svr {
namespace {

// The smallest factor:k (full light matrices) whose probe error is within the scene's target;
// spectral:81, exact, when none up to factor:16 is.
SceneModel chooseAutoModel(const Scene& scene, const Observer& observer) {
  const ModelProbe probe(scene, observer);
  FactorChoice factor(scene, observer);  // one choice probe for every k
  double best_error = INFINITY;
  std::optional<SceneModel> best;
  std::string trail;  // each candidate's probe error, for the record
  for (int k = 3; k <= 16; ++k) {
    SceneModel candidate = factor.make(ModelName{ModelKind::kFactor, k});
    const double error = probe.error(*candidate.model);
    trail += fmt::format("{}{}: {:.2f}", trail.empty() ? "" : ", ", k, error);
    const bool reached = error <= scene.auto_target;
    if (reached || error < best_error) {
      best_error = error;
      best = std::move(candidate);
    }
    if (reached) break;
  }
  if (!best) throw Error("auto: no factor:k up to 16 renders the probe finite");
  // Where no factor:k reaches the target, the closest stands: spectral:81 would be exact, but at
  // 162 image planes it costs ten times the closest model and the viewer relights at most 32.
  best->description =
      best_error <= scene.auto_target
          ? fmt::format("auto: {} — probe render {} mean ΔE2000 {:.3f} (worst light) against "
                        "spectral:81, the smallest k within {} (k: error {})",
                        best->description, probe.size(), best_error, scene.auto_target, trail)
          : fmt::format("auto: {} — no factor:k up to 16 reached mean ΔE2000 {} on the probe "
                        "render {}; this one came closest, {:.3f} (k: error {})",
                        best->description, scene.auto_target, probe.size(), best_error, trail);
  best->asked = "auto";
  best->target = scene.auto_target;
  best->probe_de2000 = best_error;
  best->classification = factor.releaseClassification();
  return std::move(*best);
}

}  // namespace

nlohmann::json SceneModel::record() const {
  nlohmann::json j = {{"asked", asked},
                      {"model", model->name()},
                      {"k", model->channels()},
                      {"description", description}};
  if (std::isfinite(palette_de2000)) j["palette_de2000"] = palette_de2000;
  if (std::isfinite(target)) j["target"] = target;
  if (std::isfinite(probe_de2000)) j["probe_de2000"] = probe_de2000;
  if (std::isfinite(choice_de2000)) j["choice_de2000"] = choice_de2000;
  if (model->name().rfind("factor:", 0) == 0) j["cached"] = cached;
  return j;
}

void checkModelName(const std::string& name, const std::string& flag, const WavelengthGrid& grid) {
  if (name == "auto") return;
  try {
    const ModelName parsed = parseModelName(name);
    if (parsed.kind == ModelKind::kSpectral && parsed.k > grid.count)
      throw Error(fmt::format("spectral:{} asks for more bands than the {} samples of the grid",
                              parsed.k, grid.count));
  } catch (const Error& e) {
    throw Error(fmt::format("{} '{}': {}", flag, name, e.what()));
  }
}

SceneModel makeSceneModel(const std::string& name, const Scene& scene, const Observer& observer) {
  if (name == "auto") return chooseAutoModel(scene, observer);
  const ModelName parsed = parseModelName(name);
  switch (parsed.kind) {
    case ModelKind::kRgb: return {makeRgbModel(observer), "rgb", name};
    case ModelKind::kSpectral:
      return {makeSpectralModel(observer, parsed.k, parsed.light_matrix),
              fmt::format("spectral:{} ({} bands of the {}-sample grid, {} light matrices)",
                          parsed.k, parsed.k, observer.grid().count,
                          toString(parsed.light_matrix)),
              name};
    case ModelKind::kLinear:
      throw Error(fmt::format("{}: linear:k has no componentwise product; the renderers take "
                              "rgb, factor:k, spectral:n or auto", scene.file));
    case ModelKind::kFactor: break;
  }
  FactorChoice choice(scene, observer);
  SceneModel chosen = choice.make(parsed);
  chosen.classification = choice.releaseClassification();
  return chosen;
}

}  // namespace svr
