#pragma once
// The scene every backend bench renders (data/scenes/engine.json), loaded once per binary, so
// the raycast, shear-warp and splat benches time the same volume, transfer function and view.

#include <map>
#include <string>
#include <utility>

#include "renderers/classification/classification.h"
#include "renderers/scene/scene.h"
#include "renderers/model/scene_model.h"
#include "renderers/render/scene_render.h"
#include "spectral/colorimetry.h"
#include "base/data_dir.h"
#include "spectral/spectrum_library.h"

namespace svr {

struct EngineBenchScene {
  SpectrumLibrary library = SpectrumLibrary::load(defaultDataDir(), WavelengthGrid::standard());
  Observer observer = Observer::cie1931(defaultDataDir(), WavelengthGrid::standard());
  Scene scene = loadScene(defaultDataDir() + "/scenes/engine.json", library);
};

inline const EngineBenchScene& engineBenchScene() {
  static const EngineBenchScene s;
  return s;
}

// The engine classified for one model with the scene's step and bins: what a viewer holds
// while only the view changes.
inline ClassifiedVolume classifyEngine(const ColourModel& model) {
  return classifyScene(engineBenchScene().scene, model);
}

// The engine's request at size × size pixels.
inline RenderRequest engineRequest(const ClassifiedVolume& cv, int size) {
  RenderRequest request = sceneRequest(engineBenchScene().scene, cv);
  request.width = request.height = size;
  // The benches time steady frames (after a warm-up): the raycaster's gradients are built
  // once and kept, whatever "auto" would pick for a single frame of this size.
  request.options["raycast"]["gradients"] = "precomputed";
  return request;
}

// The model and classification for a model name, built once per binary and kept.
inline const ClassifiedVolume& engineClassified(const std::string& model_name) {
  static std::map<std::string, std::pair<SceneModel, ClassifiedVolume>> cache;
  auto it = cache.find(model_name);
  if (it == cache.end()) {
    const EngineBenchScene& s = engineBenchScene();
    SceneModel model = makeSceneModel(model_name, s.scene, s.observer);
    ClassifiedVolume cv = classifyEngine(*model.model);
    it = cache.emplace(model_name, std::pair{std::move(model), std::move(cv)}).first;
  }
  return it->second.second;
}

}  // namespace svr
