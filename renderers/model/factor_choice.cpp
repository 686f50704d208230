#include "renderers/model/factor_choice.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "base/disk_cache.h"
#include "base/error.h"
#include "renderers/registry.h"
#include "spectral/observer_key.h"

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

// Bump when training, its objective, its defaults or the choice change: models cached by an
// older version are then rebuilt rather than reused.
constexpr int kSceneModelVersion = 8;  // 8: trained from trained k − 1; chosen on a probe render

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
  if (payload.contains("choice_de2000")) m.choice_de2000 = payload.at("choice_de2000");
  m.cached = true;
  return m;
}

nlohmann::json toCache(const SceneModel& m) {
  nlohmann::json payload = {{"model", m.model->toJson()},
                            {"description", m.description},
                            {"palette_de2000", m.palette_de2000}};
  if (std::isfinite(m.choice_de2000)) payload["choice_de2000"] = m.choice_de2000;
  return payload;
}

nlohmann::json vec3(const glm::dvec3& v) { return {v.x, v.y, v.z}; }

nlohmann::json transferFunctionKey(const TransferFunction& tf) {
  nlohmann::json materials = nlohmann::json::array();
  for (const Material& m : tf.materials)
    materials.push_back({{"reflectance", valuesJson(m.reflectance.values())},
                         {"absorption", m.absorption ? valuesJson(m.absorption->values())
                                                     : nlohmann::json()},
                         {"extinction", m.extinction},
                         {"specular", m.specular},
                         {"xray", m.xray}});
  nlohmann::json points = nlohmann::json::array();
  for (const auto& p : tf.points) points.push_back({p.value, p.material});
  return {{"labels", tf.kind == TransferFunction::Kind::kLabels ? nlohmann::json(tf.labels)
                                                                 : nlohmann::json()},
          {"materials", materials},
          {"points", points},
          {"opacity", tf.opacity}};
}

// Everything the probe render of `probe` (the scene at the probe's size) reads, by value: the
// volume's bytes by their SHA-256 (about 1 GB/s, so a warm run pays milliseconds for it).
nlohmann::json probeKey(const Scene& probe) {
  const Volume& v = probe.volume;
  nlohmann::json mixes = nlohmann::json::array();
  for (const LightMix& m : probe.mixes) mixes.push_back(m.weights);
  const Camera& c = probe.camera;
  return {
      {"backend", referenceRendererName()},
      {"size", {probe.width, probe.height}},
      {"volume",
       {{"dims", {v.dims()[0], v.dims()[1], v.dims()[2]}},
        {"spacing", vec3(v.spacing())},
        {"type", toString(v.type())},
        {"sha256", sha256Hex(v.data().data(), v.bytes())}}},
      {"transfer_function", transferFunctionKey(probe.transfer_function)},
      {"camera", {vec3(c.eye), vec3(c.target), vec3(c.up), c.fov_degrees, c.ortho_height}},
      {"step", probe.stepWorld()},
      {"termination", probe.termination},
      {"bins", probe.bins},
      {"options",
       probe.renderer_options.value(referenceRendererName(), nlohmann::json::object())},
      {"shading",
       {probe.shading.ambient, probe.shading.diffuse, probe.shading.specular,
        probe.shading.shininess}},
      {"light_direction", probe.light_direction ? vec3(*probe.light_direction) : nlohmann::json()},
      {"background", probe.background ? valuesJson(probe.background->values()) : nlohmann::json()},
      {"mixes", mixes},
  };
}

}  // namespace

FactorChoice::FactorChoice(const Scene& scene, const Observer& observer)
    : scene_(scene), observer_(observer), probing_(!scene.volume.brick()) {}

std::shared_ptr<ClassifiedVolume> FactorChoice::releaseClassification() {
  if (!probe_) return nullptr;
  auto out = std::make_shared<ClassifiedVolume>(probe_->releaseClassification());
  probe_.reset();
  return out;
}

const ModelProbe* FactorChoice::probe() {
  if (!probing_) return nullptr;
  if (!probe_) probe_.emplace(scene_, observer_, kProbeSide);
  return &*probe_;
}

std::optional<nlohmann::json> FactorChoice::load(const std::string& kind,
                                                 const nlohmann::json& key) const {
  if (const auto hit = memo_.find(kind + key.dump()); hit != memo_.end()) return hit->second;
  return DiskCache::process().load(kind, key).payload;
}

void FactorChoice::store(const std::string& kind, const nlohmann::json& key,
                         const nlohmann::json& payload) {
  memo_[kind + key.dump()] = payload;
  DiskCache::process().store(kind, key, payload);
}

// Trained for k on the palette, from the basis trained for k − 1; null where no sharpening of
// the palette at k is finite (the other candidates then stand in).
std::unique_ptr<ComponentwiseModel> FactorChoice::trained(const ModelName& name,
                                                          const TrainingSet& palette) {
  const nlohmann::json key = modelKey(name.str(), observer_, palette);
  if (const auto hit = load("trained", key)) try {
      if (hit->at("model").is_null()) return nullptr;
      auto model = modelFromJson(hit->at("model"), "cached trained model");
      if (auto* c = dynamic_cast<ComponentwiseModel*>(model.get())) {
        model.release();
        return std::unique_ptr<ComponentwiseModel>(c);
      }
    } catch (const std::exception&) {
      // A well-formed entry whose model does not load is rebuilt like a corrupt one.
    }
  std::unique_ptr<ComponentwiseModel> fewer;
  if (name.k > 3) fewer = trained(ModelName{ModelKind::kFactor, name.k - 1, name.light_matrix},
                                  palette);
  std::unique_ptr<ComponentwiseModel> model;
  try {
    model = trainFactorModel(observer_, palette, name.k, FactorVariant::kRefined,
                             name.light_matrix, nullptr, fewer ? &fewer->basis() : nullptr);
  } catch (const Error&) {
    // No finite sharpening of this palette at k.
  }
  store("trained", key, {{"model", model ? model->toJson() : nlohmann::json()}});
  return model;
}

std::vector<FactorChoice::Candidate> FactorChoice::candidates(const ModelName& name,
                                                              const TrainingSet& palette) {
  std::vector<Candidate> out;
  if (auto t = trained(name, palette)) out.push_back({"trained", std::move(t)});
  out.push_back({"bands", bandFactorModel(observer_, name.k, name.light_matrix)});
  if (name.k > 3) {
    const SceneModel fewer = make(ModelName{ModelKind::kFactor, name.k - 1, name.light_matrix});
    out.push_back({fmt::format("factor:{} split", name.k - 1),
                   withChannelSplit(dynamic_cast<const ComponentwiseModel&>(*fewer.model))});
  }
  out.push_back({"rgb", rgbFactorModel(observer_, name.k)});
  return out;
}

// The candidate with the least error on the probe (on the palette in a brick). The trained
// model stands unless another is better by a margin: ties keep the model trained for k, whose
// basis is conditioned for k channels, rather than a chain of splits.
SceneModel FactorChoice::choose(const ModelName& name, const TrainingSet& palette) {
  std::vector<Candidate> all = candidates(name, palette);
  const ModelProbe* p = probe();
  std::vector<double> errors;
  std::string trail;
  for (const Candidate& c : all) {
    errors.push_back(p ? p->meanError(*c.model) : trainingSetError(*c.model, observer_, palette));
    trail += fmt::format("{}{} {:.3f}", trail.empty() ? "" : ", ", c.how, errors.back());
  }
  constexpr double kMargin = 0.01;  // ΔE2000
  size_t best = std::min_element(errors.begin(), errors.end()) - errors.begin();
  if (all[0].how == "trained" && errors[0] <= errors[best] + kMargin) best = 0;
  if (!std::isfinite(errors[best]))
    throw Error(
        fmt::format("factor:{}: no candidate renders the scene finite ({})", name.k, trail));
  SceneModel chosen{std::move(all[best].model), "", name.str()};
  chosen.palette_de2000 = trainingSetError(*chosen.model, observer_, palette);
  chosen.description =
      p ? fmt::format("factor:{} ({}), the best on a {} probe render against spectral:81, mean "
                      "ΔE2000 over {} lights and mixes: {}; trained on the scene palette ({} "
                      "lights × {} reflectances, {} light matrices)",
                      name.k, all[best].how, p->size(),
                      scene_.lights.size() + scene_.mixes.size(), trail,
                      palette.lights.size(), palette.reflectances.size(),
                      toString(name.light_matrix))
        : fmt::format("factor:{} ({}), the best on the scene palette ({} lights × {} "
                      "reflectances, {} light matrices; a brick has no probe render), mean "
                      "ΔE2000 over its products: {}",
                      name.k, all[best].how, palette.lights.size(), palette.reflectances.size(),
                      toString(name.light_matrix), trail);
  if (p) chosen.choice_de2000 = errors[best];
  return chosen;
}

SceneModel FactorChoice::make(const ModelName& name) {
  const TrainingSet palette = scenePalette(scene_, observer_, name.light_matrix);
  nlohmann::json key = modelKey(name.str(), observer_, palette);
  if (probing_) {
    if (probe_key_.is_null()) probe_key_ = probeKey(ModelProbe::sized(scene_, kProbeSide));
    key["probe"] = probe_key_;
  }
  if (const auto hit = load("model", key)) try {
      return fromCache(*hit, name.str(), DiskCache::process().entryPath("model", key).string());
    } catch (const std::exception&) {
      // A well-formed entry whose model does not load is rebuilt like a corrupt one.
    }
  SceneModel chosen = choose(name, palette);
  store("model", key, toCache(chosen));
  return chosen;
}

}  // namespace svr
