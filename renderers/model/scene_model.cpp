#include "renderers/model/scene_model.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <optional>

#include "renderers/render/scene_render.h"
#include "renderers/registry.h"
#include "spectral/componentwise_model.h"
#include "spectral/image_difference.h"
#include "base/disk_cache.h"
#include "spectral/observer_key.h"
#include "base/error.h"
#include "spectral/factor_training.h"

namespace svr {
namespace {

// The scene's palette as a training set: what the light-independent image holds, under the
// scene's lights at unit luminance. That is each material's reflectance, the flat white of the
// specular term (where a material has one) and the backdrop, each seen directly and through
// every spectral absorber of the scene (deep products R ⊙ t^m, t a material's per-step
// transmission), since a ray meets one material behind another's absorption. X-ray materials
// scatter but do not occlude, so they absorb nothing along a ray. Where no material absorbs
// spectrally, T is a scalar (classification.h) that never enters a componentwise product, and a
// model needs to span only the reflectances. The white enters only for full light matrices:
// projected ones relight it as the light's own coefficients (P·L), and their span is the
// paper's, of light × material signals, which a designed palette's projection term was fitted
// to; taking the lights' own signals too costs those materials more.
TrainingSet scenePalette(const Scene& scene, const Observer& observer,
                         LightMatrixKind light_matrix) {
  const auto& materials = scene.transfer_function.materials;
  const WavelengthGrid& grid = observer.grid();
  const Spectrum flat(grid, Eigen::VectorXd::Ones(grid.count));
  TrainingSet set;
  for (const auto& l : scene.lights) set.lights.push_back(observer.unitLuminance(l.spectrum));
  std::vector<Spectrum> seen, absorbers;
  for (const Material& m : materials) seen.push_back(m.reflectance);
  if (light_matrix == LightMatrixKind::kFull &&
      std::any_of(materials.begin(), materials.end(),
                  [](const Material& m) { return m.specular > 0; }))
    seen.push_back(flat);
  if (scene.background) seen.push_back(*scene.background);
  const double step = scene.stepWorld();
  for (const Material& m : materials) {
    if (!m.absorption || m.extinction <= 0 || m.xray) continue;
    const Eigen::VectorXd shape = m.absorption->values() / m.absorption->values().mean();
    // The opacity transfer function and blends scale a material's extinction down: a ray's
    // steps take t^f for fractions f of the material's own per-step transmission t, and a
    // projection of t^f is not the f-th power of t's.
    for (double f : {1.0, 0.25, 1.0 / 16})
      absorbers.emplace_back(grid, (-f * step * m.extinction * shape).array().exp().matrix());
  }
  if (absorbers.empty()) {
    set.reflectances = seen;
    set.depths.clear();
    return set;
  }
  // Per-step transmissions range from a few percent to nearly 1: depths from one step to a
  // thousand cover what a ray crosses, and the invisible ones count nothing (kVisibleDepthY).
  set.depths = {1, 4, 16, 64, 256, 1024};
  for (const auto& t : absorbers)
    for (const auto& s : seen) {
      set.reflectances.push_back(s);
      set.absorbers.push_back(t);
    }
  return set;
}

// Bump when training, its objective, its defaults or the auto rule change: models cached by an
// older version are then rebuilt rather than reused.
constexpr int kSceneModelVersion = 7;  // 7: exact Jacobian, soft-L1 cost, cancellation ≤ 100

nlohmann::json valuesOf(const std::vector<Spectrum>& spectra) {
  nlohmann::json out = nlohmann::json::array();
  for (const auto& s : spectra) out.push_back(valuesJson(s.values()));
  return out;
}

// Everything a trained scene model depends on: the name asked for, the observer's weighted
// colour-matching functions, the grid and the training set's values.
nlohmann::json modelKey(const std::string& name, const Observer& observer,
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

// factor:k is the best on the scene's palette (trainingSetError) of: the model trained for k,
// k equal bands (stable under any absorption), and the scene's factor:(k−1) with a channel
// split (exactly as good as k − 1). So a model never loses to one with fewer channels, or to the
// bands, on the palette it is made for, and a training that does not converge costs accuracy,
// never a finite image.
SceneModel trainSceneModel(const std::string& name, const Scene& scene, const Observer& observer,
                           const TrainingSet& training) {
  const ModelName parsed = parseModelName(name);
  const int k = parsed.k;
  std::vector<std::pair<std::string, std::unique_ptr<ComponentwiseModel>>> candidates;
  std::optional<SceneModel> previous;
  const ComponentwiseModel* fewer = nullptr;
  if (k > 3) {
    previous = makeSceneModel(ModelName{ModelKind::kFactor, k - 1, parsed.light_matrix}.str(),
                              scene, observer);
    fewer = dynamic_cast<const ComponentwiseModel*>(previous->model.get());
  }
  try {
    candidates.emplace_back(
        "trained", trainFactorModel(observer, training, k, FactorVariant::kRefined,
                                    parsed.light_matrix, nullptr,
                                    fewer ? &fewer->basis() : nullptr));
  } catch (const Error&) {
    // No finite sharpening of this palette at k: the other candidates stand in.
  }
  candidates.emplace_back("bands", bandFactorModel(observer, k, parsed.light_matrix));
  if (fewer) candidates.emplace_back(fmt::format("factor:{} split", k - 1), withChannelSplit(*fewer));
  // The trained model stands unless another candidate is better by a margin: ties (a palette
  // the model fits exactly at any k) keep the model trained for k, whose basis is conditioned
  // for k channels, rather than a chain of splits.
  constexpr double kMargin = 0.01;  // ΔE2000
  std::vector<double> errors;
  for (const auto& candidate : candidates)
    errors.push_back(trainingSetError(*candidate.second, observer, training));
  size_t best = std::min_element(errors.begin(), errors.end()) - errors.begin();
  if (candidates[0].first == "trained" && errors[0] <= errors[best] + kMargin) best = 0;
  const std::string how = fmt::format(
      "factor:{} ({}) of the scene palette ({} lights × {} reflectances, {} light matrices; "
      "mean ΔE2000 {:.3f} over its products, deep ones included)",
      k, candidates[best].first, training.lights.size(), training.reflectances.size(),
      toString(parsed.light_matrix), errors[best]);
  return {std::move(candidates[best].second), how, name, errors[best]};
}

// The smallest factor:k (full light matrices) whose probe error is within the scene's target;
// spectral:81, exact, when none up to factor:16 is.
SceneModel chooseAutoModel(const Scene& scene, const Observer& observer) {
  const ModelProbe probe(scene, observer);
  double best_error = INFINITY;
  std::optional<SceneModel> best;
  std::string trail;  // each candidate's probe error, for the record
  for (int k = 3; k <= 16; ++k) {
    SceneModel candidate = makeSceneModel(fmt::format("factor:{}", k), scene, observer);
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
  return std::move(*best);
}

}  // namespace

Scene ModelProbe::sized(Scene scene) {
  const double scale = std::min(1.0, double(kLongerSide) / std::max(scene.width, scene.height));
  scene.width = std::max(1, static_cast<int>(std::lround(scene.width * scale)));
  scene.height = std::max(1, static_cast<int>(std::lround(scene.height * scale)));
  return scene;
}

ModelProbe::ModelProbe(const Scene& scene, const Observer& observer)
    : scene_(sized(scene)), observer_(observer) {
  lights_ = sceneIlluminations(scene, observer);
  reference_model_ = makeSpectralModel(observer, observer.grid().count);
  reference_ = render(*reference_model_);
}

double ModelProbe::error(const ColourModel& model) const {
  const std::vector<double> each = errors(model);
  return *std::max_element(each.begin(), each.end());
}

std::vector<double> ModelProbe::errors(const ColourModel& model) const {
  const LightIndependentImage image = render(model);
  std::vector<double> each;
  for (const auto& light : lights_) {
    const ImageDifference d = compareRelit(image, model, reference_, *reference_model_, light,
                                           observer_.xyz(light), 0.98, scene_.background);
    each.push_back(d.stats.finite ? d.stats.mean : INFINITY);
  }
  return each;
}

std::string ModelProbe::size() const { return fmt::format("{}×{}", scene_.width, scene_.height); }

LightIndependentImage ModelProbe::render(const ColourModel& model) const {
  const ClassifiedVolume cv = classifyScene(scene_, model);
  // The harness's reference backend, as the registry names it.
  return makeRenderer(referenceRendererName())->render(sceneRequest(scene_, cv), nullptr);
}

nlohmann::json SceneModel::record() const {
  nlohmann::json j = {{"asked", asked},
                      {"model", model->name()},
                      {"k", model->channels()},
                      {"description", description}};
  if (std::isfinite(palette_de2000)) j["palette_de2000"] = palette_de2000;
  if (std::isfinite(target)) j["target"] = target;
  if (std::isfinite(probe_de2000)) j["probe_de2000"] = probe_de2000;
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
  const TrainingSet training = scenePalette(scene, observer, parsed.light_matrix);
  // Trained once per palette: a second run of the scene reads the model from the disk cache.
  const DiskCache& cache = DiskCache::process();
  const nlohmann::json key = modelKey(name, observer, training);
  const DiskCache::Lookup hit = cache.load("model", key);
  if (hit.payload) {
    try {
      return fromCache(*hit.payload, name, cache.entryPath("model", key).string());
    } catch (const std::exception&) {
      // A well-formed entry whose model does not load is rebuilt like a corrupt one.
    }
  }
  SceneModel trained = trainSceneModel(name, scene, observer, training);
  cache.store("model", key, toCache(trained));
  return trained;
}

}  // namespace svr
