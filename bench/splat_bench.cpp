// Every CPU backend's time per frame on one scene, in one run: the engine (data/scenes/engine.json)
// at 512², rgb and factor:6 — Frame/engine/512/<model>/<backend>[-<choice>], every backend of the
// registry that needs no GL context, once per value of each of its choice options (splat-sheet,
// splat-direct) — so the ratios splat/raycast and splat/shearwarp come from one run
// (bench/ratios.py --splat).
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
           const nlohmann::json& backend_options) {
  const auto renderer = makeRenderer(backend);
  RenderRequest request = engineRequest(engineClassified(model), 512);
  if (!backend_options.empty()) request.options[backend] = backend_options;
  renderer->render(request);  // builds what is cached on the classification
  for (auto _ : state) {
    auto image = renderer->render(request);
    benchmark::DoNotOptimize(image.planeFloat(0).data());
  }
  state.SetItemsProcessed(state.iterations());
}

void registerFrame(const std::string& model, const std::string& backend, const std::string& name,
                   const nlohmann::json& options) {
  benchmark::RegisterBenchmark(fmt::format("Frame/engine/512/{}/{}", model, name).c_str(), frame,
                               backend, model, options)
      ->UseRealTime()
      ->Unit(benchmark::kMillisecond)
      ->Iterations(3);
}

const bool registered = [] {
  for (const char* model : {"rgb", "factor:6"})
    for (const BackendEntry& entry : backendEntries()) {
      if (!entry.make || entry.info.supports.needs_gl) continue;
      bool has_choice = false;
      for (const OptionSpec& option : entry.info.options) {
        if (option.kind != OptionSpec::Kind::kChoice) continue;
        has_choice = true;
        for (const std::string& choice : option.choices)
          registerFrame(model, entry.info.name, fmt::format("{}-{}", entry.info.name, choice),
                        {{option.key, choice}});
      }
      if (!has_choice) registerFrame(model, entry.info.name, entry.info.name, {});
    }
  return true;
}();

}  // namespace
}  // namespace svr

BENCHMARK_MAIN();
