#include "harness/view/view_session.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <regex>

#include "renderers/render/scene_render.h"
#include "renderers/registry.h"
#include "base/atomic_file.h"
#include "base/error.h"
#include "base/json_reader.h"
#include "base/text_file.h"
#include "harness/view/json_text_edit.h"

namespace svr {

ViewSession::ViewSession(const ViewOptions& options)
    : options_(options),
      // Read once: the scene is parsed from the very text a saved mix is later checked against.
      scene_text_(readTextFile(options.scene, "JSON file")) {
  auto spectra = std::make_shared<const SessionSpectra>(options.data_dir);
  Scene loaded = parseScene(JsonReader::parse(scene_text_, options.scene), options.scene,
                            spectra->library,
                            VolumeLoadOptions{.memory_budget = options.memory_budget});
  FrameSettings settings;
  settings.renderer = options.renderer;
  settings.model = options.model;
  settings.options = options.options;
  settings.memory_budget = options.memory_budget;
  session_ = std::make_unique<RenderSession>(std::move(spectra), std::move(loaded), settings,
                                             options.scene);
  const ColourModel& model = *session_->model().model;
  const int planes = model.imageChannels() + classified().t_channels;
  if (planes > kMaxPlanes)
    throw Error(fmt::format("view: model {} makes {} image planes; the page relights at most {} "
                            "(WebGL2's 224 fragment uniform vectors)",
                            model.name(), planes, kMaxPlanes));
  const Scene& s = scene();
  initial_view_ = orbitViewOf(s.camera);
  samples_ = chooseSamples(lightContext(), s,
                           session_->renderView(orbitCamera(s.camera, initial_view_), s.width,
                                                s.height));
  // One tiny frame along each axis: a backend builds what it keeps per principal axis (shear-
  // warp's run-length encodings, ~0.1 s each on the engine) at the first view along it, and
  // that should not land on the first view change that crosses a diagonal.
  for (const OrbitView axis : {OrbitView{0, 0, 1}, OrbitView{90, 0, 1}, OrbitView{0, 90, 1}})
    session_->renderView(orbitCamera(s.camera, axis), 8, 8);

  scene_info_ = pageSceneInfo(lightContext(), s, session_->model(), session_->renderer().name(),
                              initial_view_, samples_);
  scene_info_["max_side"] = kMaxSide;
  scene_info_["max_frame_values"] = kMaxFrameValues;
  scene_info_["read_only"] = options.read_only;
}

PageLightContext ViewSession::lightContext() const {
  return {*session_->model().model, session_->spectra().observer, scene().background,
          classified().t_channels};
}

nlohmann::json ViewSession::libraryLight(const std::string& name) const {
  return pageLight(lightContext(), name, session_->spectra().library.get(name));
}

std::optional<ViewFrame> ViewSession::render(const ViewRequest& request) {
  const std::uint64_t mine = ++latest_;
  LightIndependentImage image;
  double ms = 0;
  {
    std::lock_guard lock(render_mutex_);
    if (latest_.load() != mine) return std::nullopt;  // a newer view is waiting behind this one
    const auto t0 = std::chrono::steady_clock::now();
    image = session_->renderView(orbitCamera(scene().camera, request.view), request.width,
                                 request.height);
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
    const bool in_scene = std::any_of(scene().lights.begin(), scene().lights.end(),
                                      [&](const SceneLight& l) { return l.name == light; });
    if (!in_scene && !listed(light)) {
      session_->spectra().library.get(light);  // an unknown name fails here, naming close ones
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
