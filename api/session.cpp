// The public API's session (include/svr/svr.h): the steps of `svr render` — spectra, scene,
// model, classification, backend, light-independent image, relighting — behind one object.

#include "svr/svr.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <optional>

#include "harness/image_files.h"
#include "renderers/core/classification.h"
#include "renderers/core/renderer.h"
#include "renderers/core/scene.h"
#include "renderers/core/scene_render.h"
#include "renderers/registry.h"
#include "renderers/scene_model.h"
#include "spectral/colorimetry.h"
#include "spectral/data_dir.h"
#include "spectral/json_reader.h"
#include "spectral/post_illumination.h"
#include "spectral/spectrum_library.h"

namespace svr {

struct Session::State {
  RenderSettings settings;
  WavelengthGrid grid = WavelengthGrid::standard();
  SpectrumLibrary library;
  Observer observer;
  Scene scene;
  SceneModel model;
  std::unique_ptr<Renderer> renderer;
  std::optional<ClassifiedVolume> classified;
  std::optional<LightIndependentImage> image;
  std::map<std::string, Spectrum> lights;  // scene lights and mixes at unit luminance
  std::vector<std::string> light_names;

  State(const RenderSettings& s, const std::string& data_dir)
      : settings(s),
        library(SpectrumLibrary::load(data_dir, grid)),
        observer(Observer::cie1931(data_dir, grid)) {}

  // The scene as loaded, with the settings' overrides; then model, classification, backend.
  void prepare(Scene loaded, const std::string& source) {
    scene = std::move(loaded);
    if (settings.width < 0 || settings.height < 0)
      throw Error(fmt::format("RenderSettings: image size {}×{} is negative", settings.width, settings.height));
    if (settings.width) scene.width = settings.width;
    if (settings.height) scene.height = settings.height;
    renderer = makeRenderer(settings.renderer);
    checkRendererOptions(scene.renderer_options, source + ": render.options");
    for (const auto& option : settings.options)
      applyOptionAssignment(scene.renderer_options, option, "RenderSettings.options");
    model = makeSceneModel(settings.model.empty() ? scene.model : settings.model, scene, observer);
    classified.emplace(classifyScene(scene, *model.model));
    const std::vector<Spectrum> spectra = sceneIlluminations(scene, observer);
    for (const auto& l : scene.lights) light_names.push_back(l.name);
    for (const auto& m : scene.mixes) light_names.push_back(m.name);
    for (size_t i = 0; i < light_names.size(); ++i) lights.emplace(light_names[i], spectra[i]);
  }

  // A scene light or mix by name, else a library spectrum at unit luminance.
  Spectrum light(const std::string& name) const {
    if (const auto it = lights.find(name); it != lights.end()) return it->second;
    return observer.unitLuminance(library.get(name));
  }

  RgbImage relit(const Spectrum& light) {
    if (!image) render();
    PostIlluminator post(*model.model);
    if (scene.background) post.setBackground(model.model->project(*scene.background));
    post.setLight(light);
    RgbImage out{image->width(), image->height(), {}};
    out.pixels.resize(3 * image->pixels());
    post.relightSrgb8(*image, out.pixels);
    return out;
  }

  void render() {
    RenderRequest request = sceneRequest(scene, *classified);
    image = renderer->render(request, nullptr);
  }
};

namespace {

std::string dataDirOf(const RenderSettings& settings) {
  return settings.data_dir.empty() ? defaultDataDir() : settings.data_dir;
}

}  // namespace

Session::Session(std::unique_ptr<State> state) : state_(std::move(state)) {}
Session::Session(Session&&) noexcept = default;
Session& Session::operator=(Session&&) noexcept = default;
Session::~Session() = default;

Session Session::fromFile(const std::string& scene_file, const RenderSettings& settings) {
  auto state = std::make_unique<State>(settings, dataDirOf(settings));
  state->prepare(loadScene(scene_file, state->library), scene_file);
  return Session(std::move(state));
}

Session Session::fromJson(const std::string& scene_json, const std::string& base_dir,
                          const RenderSettings& settings) {
  auto state = std::make_unique<State>(settings, dataDirOf(settings));
  // parseScene anchors relative paths at the named file's folder.
  const std::string source = (std::filesystem::path(base_dir) / "scene.json").string();
  state->prepare(parseScene(JsonReader::parse(scene_json, "scene JSON"), source, state->library),
                 "scene JSON");
  return Session(std::move(state));
}

void Session::render() { state_->render(); }

int Session::width() const { return state_->scene.width; }
int Session::height() const { return state_->scene.height; }
std::string Session::modelName() const { return state_->model.model->name(); }
std::string Session::rendererName() const { return state_->renderer->name(); }
int Session::imagePlanes() const {
  return state_->model.model->imageChannels() + state_->classified->t_channels;
}
std::vector<std::string> Session::lights() const { return state_->light_names; }

RgbImage Session::relight(const std::string& light) { return state_->relit(state_->light(light)); }

RgbImage Session::relight(const std::vector<std::pair<std::string, double>>& mix) {
  if (mix.empty()) throw Error("relight: the mix has no lights");
  std::optional<Spectrum> sum;
  for (const auto& [name, weight] : mix) {
    if (!std::isfinite(weight) || weight < 0)
      throw Error(fmt::format("relight: weight {} of light '{}' must be finite and ≥ 0", weight, name));
    const Spectrum s = state_->light(name) * weight;
    sum = sum ? *sum + s : s;
  }
  return state_->relit(*sum);
}

void RgbImage::savePng(const std::string& path) const {
  if (width <= 0 || height <= 0 || pixels.size() != 3 * size_t(width) * size_t(height))
    throw Error(fmt::format("{}: an RgbImage of {}×{} must hold {} bytes, not {}", path, width,
                            height, 3 * size_t(std::max(width, 0)) * size_t(std::max(height, 0)),
                            pixels.size()));
  writeSrgbPng(pixels, width, height, path);
}

std::string version() { return SVR_VERSION; }

}  // namespace svr
