#include "harness/comparison.h"

#include <fmt/format.h>

#include <chrono>
#include <new>

#include "renderers/classification/classification.h"
#include "renderers/render/scene_render.h"
#include "renderers/model/scene_model.h"
#include "renderers/registry.h"
#include "spectral/componentwise_model.h"
#include "base/elapsed.h"
#include "base/error.h"
#include "spectral/image_difference.h"
#include "spectral/post_illumination.h"

namespace svr {
namespace {

// Luminance-weighted transmittance per pixel under a light: Y of (L ⊙ T) over Y of L, through
// the model's light matrix (Y of each channel under the light).
std::vector<float> luminanceTransmittance(const LightIndependentImage& image,
                                          const ColourModel& model, const Spectrum& light) {
  const int k = model.channels(), nt = image.transmittanceChannels();
  Eigen::VectorXd weight = model.lightMatrix(light).row(1).transpose();
  weight /= weight.sum();
  std::vector<float> out(image.pixels(), 1.0f);
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x) {
      double t = 0.0;
      if (nt == 1) {
        t = image.transmittance(0, x, y);
      } else {
        for (int c = 0; c < k && c < nt; ++c) t += weight[c] * image.transmittance(c, x, y);
      }
      out[static_cast<std::size_t>(y) * image.width() + x] = static_cast<float>(t);
    }
  return out;
}

}  // namespace

std::string Reference::model() {
  return fmt::format("spectral:{}", WavelengthGrid::standard().count);
}

double Reference::startStepVoxels(const Scene& scene) const {
  return std::min(scene.step_voxels, max_start_voxels);
}

std::string Reference::label() const { return fmt::format("{} {}", renderer, model()); }

nlohmann::json Reference::toJson(const ReferenceStep& step, double render_ms) const {
  return {{"renderer", renderer},
          {"model", model()},
          {"render_ms", render_ms},
          {"step_voxels", step.step_voxels},
          {"step_convergence", step.toJson()},
          {"early_termination", termination}};
}

std::string RunSpec::label() const {
  if (options.contains(renderer) && !options[renderer].empty())
    return fmt::format("{} {} {}", renderer, model, options[renderer].dump());
  return fmt::format("{} {}", renderer, model);
}

ComparisonSession::ComparisonSession(Scene scene, const std::string& data_dir)
    : scene_(std::move(scene)),
      spectra_(std::make_shared<const SessionSpectra>(data_dir)) {
  const std::vector<Spectrum> spectra = sceneIlluminations(scene_, spectra_->observer);
  for (std::size_t i = 0; i < spectra.size(); ++i)
    illuminations_.push_back({i < scene_.lights.size()
                                  ? scene_.lights[i].name
                                  : fmt::format("mix {}", scene_.mixes[i - scene_.lights.size()].name),
                              spectra[i]});
  const Reference reference;
  reference_step_ = convergedReferenceStep(scene_, spectra_->observer,
                                           reference.startStepVoxels(scene_));
  Rendered ref = render(reference.renderer, reference.model(), nlohmann::json::object(),
                        reference_step_.step_voxels, reference.termination);
  reference_model_ = std::move(ref.chosen.model);
  reference_ = std::move(ref.image);
  reference_ms_ = ref.render_ms;
}

ComparisonSession::Rendered ComparisonSession::render(const std::string& renderer_name,
                                                      const std::string& model,
                                                      const nlohmann::json& options,
                                                      double step_voxels, double termination,
                                                      bool steady) {
  Scene scene = scene_;
  scene.step_voxels = step_voxels;
  scene.termination = termination;
  for (const auto& [backend, values] : options.items())
    for (const auto& [key, value] : values.items()) scene.renderer_options[backend][key] = value;
  FrameSettings settings;
  settings.renderer = renderer_name;
  settings.model = model;
  RenderSession session(spectra_, std::move(scene), settings, "comparison");
  const double classify_ms = session.timings().model + session.timings().classify;
  const double first_ms = session.render();
  const double steady_ms = steady ? session.render() : first_ms;
  return {session.takeModel(), session.takeImage(), classify_ms, first_ms, steady_ms};
}

const ComparisonSession::Rendered& ComparisonSession::renderOnce(
    std::map<std::string, Rendered>& cache, const std::string& key, const std::string& renderer,
    const std::string& model, const nlohmann::json& options) {
  auto it = cache.find(key);
  if (it == cache.end())
    it = cache
             .emplace(key, render(renderer, model, options, scene_.step_voxels, scene_.termination))
             .first;
  return it->second;
}

std::optional<std::string> ComparisonSession::unsupported(const std::string& renderer) const {
  // The view is what differs between scenes; channel counts are checked when a run renders.
  return unsupportedBy(backendEntry(renderer).info, scene_.camera, 1, 1);
}

std::variant<RunResult, FailedRun> ComparisonSession::tryRun(const RunSpec& spec) {
  try {
    return run(spec);
  } catch (const Cancelled&) {
    throw;
  } catch (const Error& e) {
    return FailedRun{spec, e.what()};
  } catch (const std::bad_alloc&) {
    return FailedRun{spec, "out of memory (std::bad_alloc)"};
  }
}

RunResult ComparisonSession::run(const RunSpec& spec) {
  Rendered r = render(spec.renderer, spec.model, spec.options, scene_.step_voxels,
                      scene_.termination, /*steady=*/true);
  const std::string baseline = Reference().renderer;  // the algorithm-only error's baseline
  const Rendered* raycast =
      spec.renderer == baseline
          ? nullptr
          : &renderOnce(raycast_by_model_, spec.model, baseline, spec.model,
                        nlohmann::json::object());
  // The exact twin: this very image when the run is spectral:81.
  const Rendered* exact =
      r.chosen.model->name() == Reference::model()
          ? &r
          : &renderOnce(exact_by_backend_, spec.renderer + " " + spec.options.dump(),
                        spec.renderer, Reference::model(), spec.options);
  RunResult result;
  result.spec = spec;
  const ColourModel& model = *r.chosen.model;
  result.model_name = model.name();
  result.model_description = r.chosen.description;
  result.model_choice = r.chosen.record();
  result.k = model.channels();
  result.classify_ms = r.classify_ms;
  result.render_ms = r.render_ms;
  result.first_render_ms = r.first_render_ms;

  PostIlluminator post(model);
  if (scene_.background) post.setBackground(model.project(*scene_.background));
  const auto ref_light_t = [&](const Spectrum& l) {
    return luminanceTransmittance(reference_, *reference_model_, l);
  };
  double relight_total = 0.0;
  for (const auto& ill : illuminations_) {
    LightResult lr;
    lr.light = ill.name;
    const Xyz white = spectra_->observer.xyz(ill.spectrum);
    lr.relit.resize(3 * r.image.pixels());
    // Best of a few: a relight is short enough that one sample mostly measures thread wake-up.
    double best = INFINITY;
    for (int repeat = 0; repeat < 5; ++repeat) {
      const auto t0 = std::chrono::steady_clock::now();
      post.setLight(ill.spectrum);
      post.relightSrgb8(r.image, lr.relit);
      best = std::min(best, msSince(t0));
    }
    relight_total += best;
    const ImageDifference vs_ref =
        compareRelit(r.image, model, reference_, *reference_model_, ill.spectrum, white, 0.98,
                     scene_.background);
    lr.vs_reference = vs_ref.stats;
    lr.error_map = vs_ref.map;
    const ColourModel& exact_model = *exact->chosen.model;
    lr.model_error = compareRelit(r.image, model, exact->image, exact_model, ill.spectrum, white,
                                  0.98, scene_.background)
                         .stats;
    lr.sampling_error = compareRelit(exact->image, exact_model, reference_, *reference_model_,
                                     ill.spectrum, white, 0.98, scene_.background)
                            .stats;
    if (raycast)
      lr.vs_raycast =
          compareRelit(r.image, model, raycast->image, *raycast->chosen.model, ill.spectrum, white,
                       0.98, scene_.background)
              .stats;
    const auto t_run = luminanceTransmittance(r.image, model, ill.spectrum);
    const auto t_ref = ref_light_t(ill.spectrum);
    double sum = 0.0;
    std::size_t n = 0;
    for (std::size_t i = 0; i < t_run.size(); ++i)
      if (std::min(t_run[i], t_ref[i]) <= 0.98f) sum += std::abs(t_run[i] - t_ref[i]), ++n;
    lr.transmittance_error = n ? sum / n : 0.0;
    result.lights.push_back(std::move(lr));
  }
  result.relight_ms = relight_total / std::max<std::size_t>(illuminations_.size(), 1);
  return result;
}

namespace {

// A backend algorithm's default tolerances against the raycaster with the same model (mean,
// p95 of ΔE2000 under each light), from issue 49's view corpus at each backend's defaults
// (bench/backends/svr_backend_bench, 200 views, seed 40; docs/backends.md, "Tolerances"):
//   shear-warp  the corpus's per-view figures reach mean 2.8 / p95 9.0 but for one view (a
//               500-voxel CT minified 2.5:1, where both alias: 5.2 / 20.9) → 3 / 12;
//   splat       99 % of its per-view figures are within 7.8 / 20.1 (the worst: 8.4 / 27.5,
//               and one factor:6 view at mean 16.3; minified and zoomed views of sharp
//               transfer functions, where a Gaussian and a trilinear reconstruction differ
//               most) → 8 / 22;
//   gl raycast  the raycaster's algorithm: at most 0.07 / 0.21 → 0.1 / 0.3;
//   gl splat    the splat algorithm classified at the voxels: the splats' bound.
// Pre-classified variants stay within these (shear-warp 2.3 on the frog; the splats classified
// at the voxels 2.4 / 8.3 on the engine).
std::pair<double, double> agreementDefaults(const std::string& renderer,
                                            const nlohmann::json& backend_options) {
  if (renderer == "gl") {
    const bool splats = backend_options.is_object() && backend_options.contains("mode") &&
                        backend_options["mode"] == "splat";
    if (!splats) return {0.1, 0.3};
    return agreementDefaults("splat", {});
  }
  if (renderer == "splat") return {8.0, 22.0};
  return {3.0, 12.0};
}

}  // namespace

nlohmann::json runBackendOptions(const RunSpec& spec, const nlohmann::json& scene_options) {
  nlohmann::json out = nlohmann::json::object();
  for (const nlohmann::json* from : {&scene_options, &spec.options})
    if (from->is_object() && from->contains(spec.renderer) && (*from)[spec.renderer].is_object())
      for (const auto& [key, value] : (*from)[spec.renderer].items()) out[key] = value;
  return out;
}

std::vector<Tolerance> tolerancesFor(const std::string& renderer, const nlohmann::json& scene,
                                     const nlohmann::json& backend_options) {
  // Against the spectral reference the colour model's own error counts too (rgb and
  // factor:3–4 under spiky lights reach mean 6–12); against the raycaster with the same model
  // only the algorithm's error counts, and the raycaster is that reference itself.
  std::map<std::string, double> limits{{"de_mean", 15.0}, {"de_p95", 40.0}};
  if (renderer != Reference().renderer) {
    const auto [mean, p95] = agreementDefaults(renderer, backend_options);
    limits["de_vs_raycast_mean"] = mean;
    limits["de_vs_raycast_p95"] = p95;
  }
  auto apply = [&](const nlohmann::json& table) {
    if (!table.is_object()) return;
    for (auto& [metric, limit] : limits)
      if (table.contains(metric) && table[metric].is_number()) limit = table[metric].get<double>();
  };
  apply(scene);
  if (scene.is_object() && scene.contains(renderer)) apply(scene[renderer]);
  std::vector<Tolerance> out;
  for (const auto& [metric, limit] : limits) out.push_back({metric, limit});
  return out;
}

std::string Exceedance::str() const {
  return fmt::format("run '{}' light '{}': {} = {:.3f} exceeds the tolerance {}", run, light,
                     metric, value, tolerance);
}

std::vector<Exceedance> checkTolerances(const RunResult& run, const nlohmann::json& scene,
                                        const nlohmann::json& scene_options) {
  std::vector<Exceedance> out;
  for (const auto& tol :
       tolerancesFor(run.spec.renderer, scene, runBackendOptions(run.spec, scene_options)))
    for (const auto& l : run.lights) {
      double value = 0.0;
      if (tol.metric == "de_mean") value = l.vs_reference.mean;
      else if (tol.metric == "de_p95") value = l.vs_reference.p95;
      else if (tol.metric == "de_vs_raycast_mean" && l.vs_raycast) value = l.vs_raycast->mean;
      else if (tol.metric == "de_vs_raycast_p95" && l.vs_raycast) value = l.vs_raycast->p95;
      const bool finite = l.vs_reference.finite && (!l.vs_raycast || l.vs_raycast->finite);
      if (!finite || value > tol.limit)
        out.push_back({run.spec.label(), l.light,
                       finite ? tol.metric : fmt::format("{} (non-finite)", tol.metric), value,
                       tol.limit});
    }
  return out;
}

}  // namespace svr
