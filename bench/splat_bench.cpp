// Splat time per frame beside the raycaster's, in one run, for the engine scene
// (data/scenes/engine.json) at 512²: Splat/engine/512/<model>/<mode> and
// Raycast/engine/512/<model> for rgb and factor:6, so the ratios come from one run
// (bench/ratios.py). Classification and model training happen once, outside the timed loop; the
// splat list (classify at voxels, shade, project, sort) is per frame, since it depends on the view.
#include <benchmark/benchmark.h>
#include <fmt/format.h>

#include <map>

#include "renderers/core/classification.h"
#include "renderers/core/scene.h"
#include "renderers/core/scene_model.h"
#include "renderers/registry.h"
#include "spectral/colorimetry.h"
#include "spectral/data_dir.h"

namespace svr {
namespace {

struct Setup {
  SpectrumLibrary library = SpectrumLibrary::load(defaultDataDir(), WavelengthGrid::standard());
  Observer observer = Observer::cie1931(defaultDataDir(), WavelengthGrid::standard());
  Scene scene = loadScene(defaultDataDir() + "/scenes/engine.json", library);
  std::map<std::string, std::pair<SceneModel, ClassifiedVolume>> classified;
};

Setup& setup() {
  static Setup s;
  return s;
}

const ClassifiedVolume& classifiedFor(const std::string& model_name) {
  Setup& s = setup();
  auto it = s.classified.find(model_name);
  if (it == s.classified.end()) {
    SceneModel model = makeSceneModel(model_name, s.scene, s.observer);
    ClassificationOptions options;
    options.step_world = s.scene.stepWorld();
    options.bins = s.scene.bins;
    ClassifiedVolume cv =
        classify(s.scene.volume, s.scene.transfer_function, *model.model, options);
    it = s.classified.emplace(model_name, std::pair{std::move(model), std::move(cv)}).first;
  }
  return it->second.second;
}

void render(benchmark::State& state, const std::string& backend, const std::string& model,
            const std::string& mode) {
  const Setup& s = setup();
  const ClassifiedVolume& cv = classifiedFor(model);
  const auto renderer = makeRenderer(backend);
  nlohmann::json options = s.scene.renderer_options;
  if (!mode.empty()) options["splat"]["mode"] = mode;
  RenderRequest request{
      cv,   s.scene.camera, 512, 512, s.scene.shading, s.scene.light_direction, s.scene.termination,
      true, options};
  for (auto _ : state) {
    auto image = renderer->render(request, nullptr);
    benchmark::DoNotOptimize(image.planeFloat(0).data());
  }
  state.SetItemsProcessed(state.iterations());
}

const bool registered = [] {
  for (const char* model : {"rgb", "factor:6"}) {
    benchmark::RegisterBenchmark(fmt::format("Raycast/engine/512/{}", model).c_str(), render,
                                 "raycast", std::string(model), std::string())
        ->UseRealTime()
        ->Unit(benchmark::kMillisecond)
        ->Iterations(3);
    for (const char* mode : {"sheet", "direct"})
      benchmark::RegisterBenchmark(fmt::format("Splat/engine/512/{}/{}", model, mode).c_str(),
                                   render, "splat", std::string(model), std::string(mode))
          ->UseRealTime()
          ->Unit(benchmark::kMillisecond)
          ->Iterations(3);
  }
  return true;
}();

}  // namespace
}  // namespace svr

BENCHMARK_MAIN();
