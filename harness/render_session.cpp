#include "harness/render_session.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <chrono>
#include <cmath>
#include <optional>

#include "base/elapsed.h"
#include "base/error.h"
#include "harness/render_command.h"
#include "harness/render_outputs.h"
#include "renderers/kernels/gradient_volume.h"
#include "renderers/registry.h"
#include "renderers/render/scene_render.h"
#include "renderers/volume/volume_brick.h"
#include "spectral/post_illumination.h"

namespace svr {
namespace {

using Clock = std::chrono::steady_clock;

// The settings that can be checked before the scene is read, so that a bad flag fails first and
// names the flag: the backend (known, and able to render one brick when distributed), the model.
void checkFrameSettings(const FrameSettings& s, const WavelengthGrid& grid) {
  const BackendEntry& entry = backendEntry(s.renderer);
  if (s.distribution && !entry.info.supports.bricks) {
    std::vector<std::string> able;
    for (const std::string& name : rendererNames())
      if (backendEntry(name).info.supports.bricks) able.push_back(name);
    throw Error(fmt::format("--renderer {}: this backend cannot render one brick of a "
                            "distributed render; use {}",
                            s.renderer, fmt::join(able, " or ")));
  }
  if (!s.model.empty()) checkModelName(s.model, s.model_flag, grid);
}

}  // namespace

SessionSpectra::SessionSpectra(const std::string& dir)
    : data_dir(dir),
      library(SpectrumLibrary::load(dir, grid)),
      observer(Observer::cie1931(dir, grid)) {}

FrameSettings FrameSettings::of(const RenderSettings& api) {
  if (api.width < 0 || api.height < 0)
    throw Error(fmt::format("RenderSettings: image size {}×{} is negative", api.width,
                            api.height));
  FrameSettings s;
  s.renderer = api.renderer;
  s.model = api.model;
  if (api.width) s.width = api.width;
  if (api.height) s.height = api.height;
  s.options = api.options;
  s.model_flag = "RenderSettings.model";
  s.options_flag = "RenderSettings.options";
  return s;
}

std::unique_ptr<RenderSession> RenderSession::load(std::shared_ptr<const SessionSpectra> spectra,
                                                   const std::string& scene_file,
                                                   const FrameSettings& settings) {
  const auto t_load = Clock::now();
  RenderDistribution* const dist = settings.distribution;
  VolumeLoadOptions volume_options;
  if (settings.memory_budget) volume_options.memory_budget = *settings.memory_budget;
  std::string estimate_failure;
  if (dist) estimate_failure = splitIntoBricks(*spectra, scene_file, settings, volume_options);
  std::optional<Scene> scene;
  phase(dist, [&] {
    checkFrameSettings(settings, spectra->grid);
    scene.emplace(loadScene(scene_file, spectra->library, volume_options));
  });
  if (dist) {  // the classification's bins span the whole volume's values, on every brick
    VolumeBrick brick = *scene->volume.brick();
    brick.whole_range = dist->wholeRange(scene->volume.localRange());
    scene->volume.setBrick(brick);
  }
  const double load_ms = msSince(t_load);
  auto session = std::make_unique<RenderSession>(std::move(spectra), std::move(*scene), settings,
                                                 scene_file);
  session->timings_.load = load_ms;
  if (!estimate_failure.empty())
    session->notes_.insert(session->notes_.begin(),
                           "the bricks share voxels: estimating the work failed: " +
                               estimate_failure);
  return session;
}

RenderSession::RenderSession(std::shared_ptr<const SessionSpectra> spectra, Scene scene,
                             const RenderSettings& settings, const std::string& source)
    : RenderSession(std::move(spectra), std::move(scene), FrameSettings::of(settings), source) {}

RenderSession::RenderSession(std::shared_ptr<const SessionSpectra> spectra, Scene scene,
                             const FrameSettings& settings, const std::string& source)
    : spectra_(std::move(spectra)),
      source_(source),
      scene_(std::move(scene)),
      distribution_(settings.distribution) {
  const auto t_setup = Clock::now();
  phase(distribution_, [&] { applySettings(settings); });
  const std::string model = settings.model.empty() ? scene_.model : settings.model;
  phase(distribution_, [&] { chooseModel(model); });
  if (distribution_ && model_.asked == "auto") {
    const auto t0 = Clock::now();
    model_ = agreeOnAutoModel(*distribution_, std::move(model_), scene_, spectra_->observer);
    timings_.model += msSince(t0);
  }
  phase(distribution_, [&] { classify(); });
  if (distribution_)  // and its gradients quantise as the whole volume's would
    classified_.brick->whole_field = distribution_->wholeField(
        fieldRangeOver(classified_, ownInStored(*classified_.brick)));
  light_spectra_ = sceneIlluminations(scene_, spectra_->observer);
  light_names_ = sceneIlluminationNames(scene_);
  timings_.setup = msSince(t_setup);
}

void RenderSession::applySettings(const FrameSettings& s) {
  checkFrameSettings(s, spectra_->grid);
  if (s.width) scene_.width = *s.width;
  if (s.height) scene_.height = *s.height;
  renderer_ = makeRenderer(s.renderer);
  checkRendererOptions(scene_.renderer_options, source_ + ": render.options");
  for (const auto& option : s.options)
    applyOptionAssignment(scene_.renderer_options, option, s.options_flag);
  memory_budget_ = s.memory_budget.value_or(VolumeLoadOptions{}.memory_budget);
}

void RenderSession::chooseModel(const std::string& name) {
  const auto t0 = Clock::now();
  model_ = makeSceneModel(name, scene_, spectra_->observer);
  timings_.model = msSince(t0);
}

void RenderSession::classify() {
  const auto t0 = Clock::now();
  // Choosing the model may have classified the volume for its probe: that classification
  // with the chosen model's tables is the one classifyScene would make.
  const ClassificationOptions options = classificationOptions(scene_);
  if (model_.classification && model_.classification->step_world == options.step_world &&
      (model_.classification->labels || model_.classification->entries == options.bins)) {
    classified_ = std::move(*model_.classification);
    svr::setModel(classified_, scene_.transfer_function, *model_.model, options);
  } else {
    classified_ = classifyScene(scene_, *model_.model);
  }
  model_.classification.reset();
  // The light-independent image and every relit image, before any of them is allocated.
  const std::uint64_t relit_count = scene_.lights.size() + scene_.mixes.size();
  checkMemoryBudget(LightIndependentImage::bytesFor(scene_.width, scene_.height, classified_.k,
                                                    classified_.t_channels) +
                        3 * relit_count * std::uint64_t(scene_.width) * scene_.height,
                    memory_budget_,
                    fmt::format("{}: a {}×{} image of {} + {} channels and {} relit images",
                                source_, scene_.width, scene_.height, classified_.k,
                                classified_.t_channels, relit_count));
  timings_.classify = msSince(t0);
}

void RenderSession::setModel(const std::string& name) {
  image_.reset();
  noted_first_frame_ = false;  // the new classification's first frame may note things again
  chooseModel(name);
  classify();
}

double RenderSession::render(const ProgressFn& progress, const std::atomic<bool>* stop) {
  RenderRequest request = sceneRequest(scene_, classified_);
  request.memory_budget = memory_budget_;
  request.stop = stop;
  if (!noted_first_frame_)
    request.note = [this](const std::string& note) { notes_.push_back(note); };
  noted_first_frame_ = true;
  const auto t0 = Clock::now();
  image_ = distribution_ ? renderBrick(request, progress) : renderer_->render(request, progress);
  timings_.render = msSince(t0);
  return timings_.render;
}

LightIndependentImage RenderSession::renderBrick(RenderRequest request,
                                                 const ProgressFn& progress) {
  RenderDistribution& dist = *distribution_;
  LightIndependentImage image;
  phase(&dist, [&] {
    // Bricks behind others stop their rays where the whole render does.
    std::unique_ptr<FrontTransmittance> front;
    if (renderer_->info().supports.front_transmittance)
      front = dist.frontTransmittance(request.camera, request.width, request.height,
                                      classified_.t_channels, scene_.volume.spacing());
    request.front = front.get();
    const auto t0 = Clock::now();
    const double cpu0 = processCpuMs();
    try {
      image = renderer_->render(request, progress);
    } catch (...) {
      if (front) front->abandon();  // the bricks behind are not left waiting on this one
      throw;
    }
    brick_facts_.render_ms = msSince(t0);  // this process's own work, before the others'
    brick_facts_.render_cpu_ms = processCpuMs() - cpu0;
    brick_facts_.front_wait_ms = front ? front->waitedMs() : 0.0;
  });
  const auto t1 = Clock::now();
  image = dist.composite(image, request.camera, scene_.volume.spacing());
  if (dist.writes()) image = renderer_->finishBricks(std::move(image), request);
  brick_facts_.composite_ms = msSince(t1);
  return image;
}

nlohmann::json RenderSession::gatherBricks() const {
  if (!distribution_) throw Error("gatherBricks: not a distributed render");
  return distribution_->gather(brick_facts_.json(scene_.volume));
}

LightIndependentImage RenderSession::renderView(const Camera& camera, int width, int height,
                                                const std::atomic<bool>* stop) const {
  RenderRequest request = sceneRequest(scene_, classified_);
  request.camera = camera;
  request.width = width;
  request.height = height;
  request.memory_budget = memory_budget_;
  request.stop = stop;
  return renderer_->render(request, nullptr);
}

const LightIndependentImage& RenderSession::image() const {
  if (!image_) throw Error(fmt::format("{}: nothing rendered yet", source_));
  return *image_;
}

LightIndependentImage RenderSession::takeImage() {
  image();  // throws when nothing was rendered
  LightIndependentImage taken = std::move(*image_);
  image_.reset();
  return taken;
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
  t.load = timings_.load;
  t.classify = timings_.model + timings_.classify;
  t.render = timings_.render;
  writeRenderOutputs(o, scene_, *renderer_, model_, spectra_->observer, image(), t, notes_);
}

}  // namespace svr
