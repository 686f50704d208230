// Every CPU backend's time per frame on one scene, in one run: the engine (data/scenes/engine.json)
// at 512², rgb and factor:6 — Frame/engine/512/<model>/<backend>, with splat in both modes — so
// the ratios splat/raycast and splat/shearwarp come from one run (bench/ratios.py --splat).
// Classification (and the splat list of non-empty voxels, cached on it) happens once, outside
// the timed loop, as it does when only the view changes; the per-frame splat work (shade,
// project, sort, composite) is timed.
#include <benchmark/benchmark.h>
#include <fmt/format.h>

#include "bench/engine_scene.h"
#include "renderers/registry.h"

namespace svr {
namespace {

void frame(benchmark::State& state, const std::string& backend, const std::string& model,
           const std::string& mode) {
  const Scene& scene = engineBenchScene().scene;
  const ClassifiedVolume& cv = engineClassified(model);
  const auto renderer = makeRenderer(backend);
  nlohmann::json options = scene.renderer_options;
  if (!mode.empty()) options["splat"]["mode"] = mode;
  const RenderRequest request{cv,   scene.camera, 512,    512, scene.shading, scene.light_direction,
                              scene.termination, true, options};
  renderer->render(request, nullptr);  // builds what is cached on the classification
  for (auto _ : state) {
    auto image = renderer->render(request, nullptr);
    benchmark::DoNotOptimize(image.planeFloat(0).data());
  }
  state.SetItemsProcessed(state.iterations());
}

const bool registered = [] {
  const std::pair<const char*, const char*> runs[] = {
      {"raycast", ""}, {"shearwarp", ""}, {"splat", "sheet"}, {"splat", "direct"}};
  for (const char* model : {"rgb", "factor:6"})
    for (const auto& [backend, mode] : runs) {
      const std::string name = *mode ? fmt::format("{}-{}", backend, mode) : backend;
      benchmark::RegisterBenchmark(fmt::format("Frame/engine/512/{}/{}", model, name).c_str(),
                                   frame, std::string(backend), std::string(model),
                                   std::string(mode))
          ->UseRealTime()
          ->Unit(benchmark::kMillisecond)
          ->Iterations(3);
    }
  return true;
}();

}  // namespace
}  // namespace svr

BENCHMARK_MAIN();
