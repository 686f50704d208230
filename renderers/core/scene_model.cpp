#include "renderers/core/scene_model.h"

#include <fmt/format.h>

#include <cmath>

#include "spectral/componentwise_model.h"
#include "spectral/disk_cache.h"
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

// Bump when training, its objective, its defaults or the auto rule change: models cached by an
// older version are then rebuilt rather than reused.
constexpr int kSceneModelVersion = 2;  // 2: full-spectrum light matrices

nlohmann::json valuesOf(const std::vector<Spectrum>& spectra) {
  nlohmann::json out = nlohmann::json::array();
  for (const auto& s : spectra) out.push_back(valuesJson(s.values()));
  return out;
}

// Everything a trained scene model depends on: the name asked for (and auto's target), the
// observer's weighted colour-matching functions, the grid and the training set's values.
nlohmann::json modelKey(const std::string& name, double auto_target, const Observer& observer,
                        const TrainingSet& training) {
  nlohmann::json key = {
      {"version", kSceneModelVersion},
      {"asked", name},
      {"observer", observerKey(observer)},
      {"lights", valuesOf(training.lights)},
      {"reflectances", valuesOf(training.reflectances)},
      {"absorbers", valuesOf(training.absorbers)},
      {"depths", training.depths},
  };
  if (name == "auto") key["auto_target"] = auto_target;
  return key;
}

SceneModel fromCache(const nlohmann::json& payload, const std::string& name,
                     const std::string& source) {
  SceneModel m{modelFromJson(payload.at("model"), source), payload.at("description"), name};
  m.palette_de2000 = payload.at("palette_de2000");
  if (payload.contains("target")) m.target = payload.at("target");
  m.cached = true;
  return m;
}

nlohmann::json toCache(const SceneModel& m) {
  nlohmann::json payload = {{"model", m.model->toJson()},
                            {"description", m.description},
                            {"palette_de2000", m.palette_de2000}};
  if (std::isfinite(m.target)) payload["target"] = m.target;
  return payload;
}

SceneModel trainSceneModel(const std::string& name, const Scene& scene, const Observer& observer,
                           const EvaluationSet& palette, const TrainingSet& training) {
  const LightMatrixKind light_matrix =
      name == "auto" ? LightMatrixKind::kFull : parseModelName(name).light_matrix;
  auto describe = [&](int k, double error) {
    return fmt::format("factor:{} trained on the scene palette ({} lights × {} materials, {} "
                       "light matrices; mean ΔE2000 {:.3f} single/deep)",
                       k, training.lights.size(), training.reflectances.size(),
                       toString(light_matrix), error);
  };
  if (name != "auto") {
    const int k = parseModelName(name).k;
    auto model = trainFactorModel(observer, training, k, FactorVariant::kRefined, light_matrix);
    const double error = worstMean(*model, observer, palette);
    return {std::move(model), describe(k, error), name, error};
  }
  std::unique_ptr<ColourModel> best;
  double best_error = INFINITY;
  for (int k = 3; k <= 10; ++k) {
    auto model = trainFactorModel(observer, training, k, FactorVariant::kRefined, light_matrix);
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

}  // namespace

nlohmann::json SceneModel::record() const {
  nlohmann::json j = {{"asked", asked},
                      {"model", model->name()},
                      {"k", model->channels()},
                      {"description", description}};
  if (std::isfinite(palette_de2000)) j["palette_de2000"] = palette_de2000;
  if (std::isfinite(target)) j["target"] = target;
  if (model->name().rfind("factor:", 0) == 0) j["cached"] = cached;
  return j;
}

SceneModel makeSceneModel(const std::string& name, const Scene& scene, const Observer& observer) {
  if (name != "auto") {
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
  }
  const EvaluationSet palette = scenePalette(scene, observer);
  const TrainingSet training{palette.lights, palette.reflectances, palette.absorbers, {16, 64, 256}};
  // Trained once per palette: a second run of the scene reads the model from the disk cache.
  const DiskCache& cache = DiskCache::process();
  const nlohmann::json key = modelKey(name, scene.auto_target, observer, training);
  const DiskCache::Lookup hit = cache.load("model", key);
  if (hit.payload) {
    try {
      return fromCache(*hit.payload, name, cache.entryPath("model", key).string());
    } catch (const std::exception&) {
      // A well-formed entry whose model does not load is rebuilt like a corrupt one.
    }
  }
  SceneModel trained = trainSceneModel(name, scene, observer, palette, training);
  cache.store("model", key, toCache(trained));
  return trained;
}

}  // namespace svr
