#include "harness/view/view_session.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <regex>

#include "renderers/core/scene_render.h"
#include "renderers/registry.h"
#include "spectral/atomic_file.h"
#include "spectral/error.h"
#include "spectral/json_reader.h"
#include "spectral/text_file.h"
#include "harness/view/json_text_edit.h"

namespace svr {

ViewSession::ViewSession(const ViewOptions& options)
    : options_(options),
      // Read once: the scene is parsed from the very text a saved mix is later checked against.
      scene_text_(readTextFile(options.scene, "JSON file")),
      grid_(WavelengthGrid::standard()),
      library_(SpectrumLibrary::load(options.data_dir, grid_)),
      observer_(Observer::cie1931(options.data_dir, grid_)),
      scene_(parseScene(JsonReader::parse(scene_text_, options.scene), options.scene, library_,
                        VolumeLoadOptions{.memory_budget = options.memory_budget})) {
  renderer_ = makeRenderer(options.renderer);
  checkRendererOptions(scene_.renderer_options, options.scene + ": render.options");
  for (const auto& option : options.options)
    applyOptionAssignment(scene_.renderer_options, option, "--option");
  model_ = makeSceneModel(options.model.empty() ? scene_.model : options.model, scene_, observer_);
  classified_ = std::make_unique<ClassifiedVolume>(classifyScene(scene_, *model_.model));
  const ColourModel& model = *model_.model;
  const int planes = model.imageChannels() + classified_->t_channels;
  if (planes > kMaxPlanes)
    throw Error(fmt::format("view: model {} makes {} image planes; the viewer relights at most {}",
                            model.name(), planes, kMaxPlanes));
  initial_view_ = orbitViewOf(scene_.camera);
  RenderRequest first = sceneRequest(scene_, *classified_);
  first.memory_budget = options.memory_budget;
  first.camera = orbitCamera(scene_.camera, initial_view_);
  samples_ = chooseSamples(lightContext(), scene_, renderer_->render(first, nullptr));
  // One tiny frame along each axis: a backend builds what it keeps per principal axis (shear-
  // warp's run-length encodings, ~0.1 s each on the engine) at the first view along it, and
  // that should not land on the first view change that crosses a diagonal.
  for (const OrbitView axis : {OrbitView{0, 0, 1}, OrbitView{90, 0, 1}, OrbitView{0, 90, 1}}) {
    RenderRequest warm = first;
    warm.camera = orbitCamera(scene_.camera, axis);
    warm.width = warm.height = 8;
    renderer_->render(warm, nullptr);
  }

  scene_info_ = pageSceneInfo(lightContext(), scene_, model_, renderer_->name(), initial_view_,
                              samples_);
  scene_info_["max_side"] = kMaxSide;
  scene_info_["read_only"] = options.read_only;
}

PageLightContext ViewSession::lightContext() const {
  return {*model_.model, observer_, scene_.background, classified_->t_channels};
}

nlohmann::json ViewSession::libraryLight(const std::string& name) const {
  return pageLight(lightContext(), name, library_.get(name));
}

std::optional<ViewFrame> ViewSession::render(const ViewRequest& request) {
  const std::uint64_t mine = ++latest_;
  LightIndependentImage image;
  double ms = 0;
  {
    std::lock_guard lock(render_mutex_);
    if (latest_.load() != mine) return std::nullopt;  // a newer view is waiting behind this one
    RenderRequest r = sceneRequest(scene_, *classified_);
    r.camera = orbitCamera(scene_.camera, request.view);
    r.memory_budget = options_.memory_budget;
    r.width = request.width;
    r.height = request.height;
    const auto t0 = std::chrono::steady_clock::now();
    image = renderer_->render(r, nullptr);
    ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  }
  if (latest_.load() != mine) return std::nullopt;
  // The storage conversion is outside the lock: the next view's render need not wait for it.
  return ViewFrame{image.withStorage(request.samples.value_or(samples_.storage)), ms, mine};
}

void ViewSession::saveMix(const std::string& name,
                          const std::vector<std::pair<std::string, double>>& weights) {
  static const std::regex kName("[A-Za-z0-9_.-]{1,64}");
  if (!std::regex_match(name, kName))
    throw Error(fmt::format("mix name '{}' must be 1–64 letters, digits, '_', '-' or '.'", name));
  if (weights.empty()) throw Error("mix has no weights");
  double sum = 0;
  for (const auto& [light, w] : weights) {
    if (!std::isfinite(w) || w < 0)
      throw Error(fmt::format("weight {} of light '{}' must be finite and ≥ 0", w, light));
    sum += w;
  }
  if (!(sum > 0)) throw Error("mix weights are all 0");

  std::lock_guard lock(file_mutex_);
  const std::string& file = options_.scene;
  std::string text;
  try {
    text = readTextFile(file, "scene file");
  } catch (const Error& e) {
    throw SceneFileChanged(fmt::format("{} (it was there when svr view loaded it): the mix is not saved", e.what()));
  }
  if (text != scene_text_)
    throw SceneFileChanged(fmt::format("{} changed on disk since svr view loaded it: the mix is not "
                                       "saved over it (restart svr view to load the new file)", file));
  const nlohmann::ordered_json doc = nlohmann::ordered_json::parse(text, nullptr, false);
  const nlohmann::ordered_json lights =
      doc.is_object() ? doc.value("lights", nlohmann::ordered_json::array()) : nlohmann::ordered_json();
  if (!lights.is_array())
    throw Error(fmt::format("{}: cannot read the scene file back to add the mix", file));
  // A light is named by its "name", or, written as a bare string, by the library name it is.
  const auto listed = [&](const std::string& light) {
    return std::any_of(lights.begin(), lights.end(), [&](const auto& l) {
      return (l.is_string() && l == light) || (l.is_object() && l.value("name", "") == light);
    });
  };
  // New lights are written as the file writes its last one: a bare name or an object.
  const bool bare = !lights.empty() && lights.back().is_string();
  nlohmann::ordered_json mix = nlohmann::ordered_json::object();
  for (const auto& [light, w] : weights) {
    const bool in_scene = std::any_of(scene_.lights.begin(), scene_.lights.end(),
                                      [&](const SceneLight& l) { return l.name == light; });
    if (!in_scene && !listed(light)) {
      library_.get(light);  // an unknown name fails here, naming close ones
      const nlohmann::ordered_json entry =
          bare ? nlohmann::ordered_json(light) : nlohmann::ordered_json{{"name", light}, {"library", light}};
      text = withElementAppended(text, {"lights"}, entry, file);
    }
    mix[light] = w;
  }
  text = withMemberSet(text, {"light_mixes"}, name, mix, file);
  writeTextAtomically(file, text);
  scene_text_ = text;
}

}  // namespace svr
