// The public API's session (include/svr/svr.h): a RenderSession (harness/render_session.h) behind
// the public types, which hold nothing but the standard library's.

#include "svr/svr.h"

#include <fmt/format.h>

#include <filesystem>

#include "harness/render_session.h"
#include "harness/image_files.h"
#include "base/data_dir.h"
#include "base/json_reader.h"

namespace svr {

struct Session::State {
  std::unique_ptr<RenderSession> session;

  RgbImage relit(const Spectrum& light) {
    if (!session->rendered()) session->render();
    const LightIndependentImage& image = session->image();
    RgbImage out{image.width(), image.height(), {}};
    out.pixels.resize(3 * image.pixels());
    session->relightSrgb8(light, out.pixels);
    return out;
  }
};

namespace {

std::shared_ptr<const SessionSpectra> spectraOf(const RenderSettings& settings) {
  return std::make_shared<const SessionSpectra>(settings.data_dir.empty() ? defaultDataDir()
                                                                          : settings.data_dir);
}

}  // namespace

Session::Session(std::unique_ptr<State> state) : state_(std::move(state)) {}
Session::Session(Session&&) noexcept = default;
Session& Session::operator=(Session&&) noexcept = default;
Session::~Session() = default;

Session Session::fromFile(const std::string& scene_file, const RenderSettings& settings) {
  auto spectra = spectraOf(settings);
  Scene scene = loadScene(scene_file, spectra->library);
  auto state = std::make_unique<State>();
  state->session = std::make_unique<RenderSession>(spectra, std::move(scene), settings, scene_file);
  return Session(std::move(state));
}

Session Session::fromJson(const std::string& scene_json, const std::string& base_dir,
                          const RenderSettings& settings) {
  auto spectra = spectraOf(settings);
  // parseScene anchors relative paths at the named file's folder.
  const std::string source = (std::filesystem::path(base_dir) / "scene.json").string();
  Scene scene = parseScene(JsonReader::parse(scene_json, "scene JSON"), source, spectra->library);
  auto state = std::make_unique<State>();
  state->session =
      std::make_unique<RenderSession>(spectra, std::move(scene), settings, "scene JSON");
  return Session(std::move(state));
}

void Session::render() { state_->session->render(); }

int Session::width() const { return state_->session->scene().width; }
int Session::height() const { return state_->session->scene().height; }
std::string Session::modelName() const { return state_->session->model().model->name(); }
std::string Session::rendererName() const { return state_->session->renderer().name(); }
int Session::imagePlanes() const {
  const RenderSession& s = *state_->session;
  return s.model().model->imageChannels() + s.classified().t_channels;
}
std::vector<std::string> Session::lights() const { return state_->session->lightNames(); }

RgbImage Session::relight(const std::string& light) {
  return state_->relit(state_->session->light(light));
}

RgbImage Session::relight(const std::vector<std::pair<std::string, double>>& mix) {
  return state_->relit(state_->session->mix(mix));
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
