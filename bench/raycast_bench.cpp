// Raycast time per frame for the engine scene (data/scenes/engine.json) at 512² and 800²:
// Raycast/engine/<size>/<model> for rgb, factor:6 and spectral:81 in one run, so the ratio
// factor:6 / rgb is read from one run (bench/ratios.py --raycast). Classification happens once,
// outside the timed loop, as it does when only the view changes.
#include <benchmark/benchmark.h>
#include <fmt/format.h>

#include "renderers/classification/classification.h"
#include "renderers/scene/scene.h"
#include "renderers/model/scene_model.h"
#include "renderers/registry.h"
#include "spectral/colorimetry.h"
#include "base/data_dir.h"
#include "bench/engine_scene.h"

namespace svr {
namespace {

void raycast(benchmark::State& state, int size, const std::string& model_name) {
  const EngineBenchScene& s = engineBenchScene();
  const SceneModel model = makeSceneModel(model_name, s.scene, s.observer);
  const ClassifiedVolume cv = classifyEngine(*model.model);
  const auto renderer = makeRenderer("raycast");
  const RenderRequest request = engineRequest(cv, size);
  for (auto _ : state) {
    auto image = renderer->render(request);
    benchmark::DoNotOptimize(image.planeFloat(0).data());
  }
  state.SetItemsProcessed(state.iterations());
}

const bool registered = [] {
  for (int size : {512, 800})
    for (const char* model : {"rgb", "factor:6", "spectral:81"})
      benchmark::RegisterBenchmark(fmt::format("Raycast/engine/{}/{}", size, model).c_str(),
                                   raycast, size, std::string(model))
          ->UseRealTime()
          ->Unit(benchmark::kMillisecond)
          ->MinTime(2.0);
  return true;
}();

}  // namespace
}  // namespace svr

BENCHMARK_MAIN();
