#include "renderers/core/scene_model.h"

#include <fmt/format.h>

#include <cmath>

#include "spectral/componentwise_model.h"
#include "spectral/error.h"
#include "spectral/factor_training.h"
#include "spectral/model_error.h"

namespace svr {
namespace {

// The scene's palette as an evaluation set: unit-luminance lights × material reflectances;
// each material's absorber is its own per-step transmission when it absorbs spectrally, else a
// weak absorber made from another material (so deep products are trained even then).
EvaluationSet scenePalette(const Scene& scene, const Observer& observer) {
  std::vector<Spectrum> lights, reflectances;
  for (const auto& l : scene.lights) lights.push_back(observer.unitLuminance(l.spectrum));
  for (const auto& m : scene.transfer_function.materials) reflectances.push_back(m.reflectance);
  EvaluationSet set = makeEvaluationSet("palette", lights, reflectances, 1);
  const double step = scene.stepWorld();
  for (size_t j = 0; j < scene.transfer_function.materials.size(); ++j) {
    const Material& m = scene.transfer_function.materials[j];
    if (m.absorption && m.extinction > 0) {
      const Eigen::VectorXd shape = m.absorption->values() / m.absorption->values().mean();
      set.absorbers[j] = Spectrum(m.reflectance.grid(),
                                  (-step * m.extinction * shape).array().exp().matrix());
    }
  }
  return set;
}

double worstMean(const ColourModel& model, const Observer& observer, const EvaluationSet& set) {
  double worst = 0.0;
  for (const auto& row : evaluateModel(model, observer, set))
    if (row.evaluation_case == "product" || row.evaluation_case == "absorb256")
      worst = std::max(worst, row.stats.finite ? row.stats.mean : INFINITY);
  return worst;
}

}  // namespace

nlohmann::json SceneModel::record() const {
  nlohmann::json j = {{"asked", asked},
                      {"model", model->name()},
                      {"k", model->channels()},
                      {"description", description}};
  if (std::isfinite(palette_de2000)) j["palette_de2000"] = palette_de2000;
  if (std::isfinite(target)) j["target"] = target;
  return j;
}

SceneModel makeSceneModel(const std::string& name, const Scene& scene, const Observer& observer) {
  if (name != "auto") {
    const ModelName parsed = parseModelName(name);
    switch (parsed.kind) {
      case ModelKind::kRgb: return {makeRgbModel(observer), "rgb", name};
      case ModelKind::kSpectral:
        return {makeSpectralModel(observer, parsed.k),
                fmt::format("spectral:{} ({} bands of the {}-sample grid)", parsed.k, parsed.k,
                            observer.grid().count),
                name};
      case ModelKind::kLinear:
        throw Error(fmt::format("{}: linear:k has no componentwise product; the renderers take "
                                "rgb, factor:k, spectral:n or auto", scene.file));
      case ModelKind::kFactor: break;
    }
  }
  const EvaluationSet palette = scenePalette(scene, observer);
  const TrainingSet training{palette.lights, palette.reflectances, palette.absorbers, {16, 64, 256}};
  auto describe = [&](int k, double error) {
    return fmt::format("factor:{} trained on the scene palette ({} lights × {} materials; mean "
                       "ΔE2000 {:.3f} single/deep)",
                       k, training.lights.size(), training.reflectances.size(), error);
  };
  if (name != "auto") {
    const int k = parseModelName(name).k;
    auto model = trainFactorModel(observer, training, k, FactorVariant::kRefined);
    const double error = worstMean(*model, observer, palette);
    return {std::move(model), describe(k, error), name, error};
  }
  std::unique_ptr<ColourModel> best;
  double best_error = INFINITY;
  for (int k = 3; k <= 10; ++k) {
    auto model = trainFactorModel(observer, training, k, FactorVariant::kRefined);
    const double error = worstMean(*model, observer, palette);
    if (error < best_error) best_error = error, best = std::move(model);
    if (best_error <= scene.auto_target)
      return {std::move(best),
              "auto: " + describe(k, best_error) +
                  fmt::format(" — the smallest k within {}", scene.auto_target),
              name, best_error, scene.auto_target};
  }
  const int k = best->channels();
  return {std::move(best),
          "auto: " + describe(k, best_error) +
              fmt::format(" — no k ≤ 10 reached {}; the most accurate one", scene.auto_target),
          name, best_error, scene.auto_target};
}

}  // namespace svr
