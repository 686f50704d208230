#include "api/render_session.h"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <optional>

#include "harness/render_outputs.h"
#include "renderers/core/scene_render.h"
#include "renderers/registry.h"
#include "spectral/elapsed.h"
#include "spectral/error.h"
#include "spectral/post_illumination.h"

namespace svr {
SessionSpectra::SessionSpectra(const std::string& dir)
    : data_dir(dir),
      library(SpectrumLibrary::load(dir, grid)),
      observer(Observer::cie1931(dir, grid)) {}

RenderSession::RenderSession(std::shared_ptr<const SessionSpectra> spectra, Scene scene,
                             const RenderSettings& settings, const std::string& source)
    : spectra_(std::move(spectra)), source_(source), scene_(std::move(scene)) {
  const auto t_setup = std::chrono::steady_clock::now();
  if (settings.width < 0 || settings.height < 0)
    throw Error(fmt::format("RenderSettings: image size {}×{} is negative", settings.width,
                            settings.height));
  if (settings.width) scene_.width = settings.width;
  if (settings.height) scene_.height = settings.height;
  renderer_ = makeRenderer(settings.renderer);
  checkRendererOptions(scene_.renderer_options, source + ": render.options");
  for (const auto& option : settings.options)
    applyOptionAssignment(scene_.renderer_options, option, "RenderSettings.options");
  const Observer& observer = spectra_->observer;
  auto t0 = std::chrono::steady_clock::now();
  model_ = makeSceneModel(settings.model.empty() ? scene_.model : settings.model, scene_, observer);
  timings_.model = msSince(t0);
  t0 = std::chrono::steady_clock::now();
  classified_ = classifyScene(scene_, *model_.model);
  timings_.classify = msSince(t0);
  light_spectra_ = sceneIlluminations(scene_, observer);
  light_names_ = sceneIlluminationNames(scene_);
  timings_.setup = msSince(t_setup);
}

void RenderSession::render(const ProgressFn& progress, const std::atomic<bool>* stop) {
  RenderRequest request = sceneRequest(scene_, classified_);
  request.stop = stop;
  const auto t0 = std::chrono::steady_clock::now();
  image_ = renderer_->render(request, progress);
  timings_.render = msSince(t0);
}

const LightIndependentImage& RenderSession::image() const {
  if (!image_) throw Error(fmt::format("{}: nothing rendered yet", source_));
  return *image_;
}

Spectrum RenderSession::light(const std::string& name) const {
  for (size_t i = 0; i < light_names_.size(); ++i)
    if (light_names_[i] == name) return light_spectra_[i];
  return spectra_->observer.unitLuminance(spectra_->library.get(name));
}

Spectrum RenderSession::mix(const std::vector<std::pair<std::string, double>>& weights) const {
  if (weights.empty()) throw Error("relight: the mix has no lights");
  std::optional<Spectrum> sum;
  for (const auto& [name, weight] : weights) {
    if (!std::isfinite(weight) || weight < 0)
      throw Error(fmt::format("relight: weight {} of light '{}' must be finite and ≥ 0", weight,
                              name));
    const Spectrum s = light(name) * weight;
    sum = sum ? *sum + s : s;
  }
  return *sum;
}

Spectrum RenderSession::ownLight(const Spectrum& spectrum, const std::string& what) const {
  if (!(spectrum.grid() == spectra_->grid))
    throw Error(fmt::format("{}: a light on {} is needed, not {}", what,
                            spectra_->grid.describe(), spectrum.grid().describe()));
  if (!spectrum.allFinite() || spectrum.values().minCoeff() < 0)
    throw Error(fmt::format("{}: a light's values must be finite and ≥ 0", what));
  return spectra_->observer.unitLuminance(spectrum);
}

PostIlluminator RenderSession::relighter(const Spectrum& light) const {
  PostIlluminator post(*model_.model);
  if (scene_.background) post.setBackground(model_.model->project(*scene_.background));
  post.setLight(light);
  return post;
}

// PostIlluminator checks the output's size and names it in its error.
void RenderSession::relightSrgb8(const Spectrum& light, std::span<std::uint8_t> out) const {
  relighter(light).relightSrgb8(image(), out);
}

void RenderSession::relightLinear(const Spectrum& light, std::span<float> out) const {
  relighter(light).relightLinear(image(), out);
}

void RenderSession::save(const std::string& dir, bool quiet) const {
  RenderOptions o;
  o.data_dir = spectra_->data_dir;
  o.scene = source_;
  o.renderer = renderer_->name();
  o.model = model_.asked;
  o.out_dir = dir;
  o.quiet = quiet;
  svr::Timings t;
  t.classify = timings_.classify;
  t.render = timings_.render;
  writeRenderOutputs(o, scene_, *renderer_, model_, spectra_->observer, image(), t, {});
}

}  // namespace svr
