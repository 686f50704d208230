// Shear-warp against raycast in one run, engine scene (data/scenes/engine.json, its camera), at
// 512² and 800², rgb and factor:6:
//   Shearwarp/engine/<size>/<model>   time per frame with the encoding already built
//   Raycast/engine/<size>/<model>     the reference backend, same request
//   ShearwarpEncode/engine/<model>/<axis>  run-length encoding of one principal axis (x, y, z:
//                                     every view uses one of them; x's rows are strided)
//   Classify/engine/<model>           classification (shared by both backends)
// so per-frame time is split from classification and encoding, and the speed ratio is read from
// one run (python3 bench/ratios.py out.json).
#include <benchmark/benchmark.h>
#include <fmt/format.h>

#include "renderers/core/classification.h"
#include "renderers/core/scene.h"
#include "renderers/scene_model.h"
#include "renderers/raycast/raycast_renderer.h"
#include "renderers/shearwarp/rle_volume.h"
#include "renderers/shearwarp/shearwarp_renderer.h"
#include "spectral/colorimetry.h"
#include "spectral/data_dir.h"
#include "bench/engine_scene.h"

namespace svr {
namespace {

void frame(benchmark::State& state, int size, const std::string& model_name, bool shearwarp) {
  const SceneModel model = makeSceneModel(model_name, engineBenchScene().scene, engineBenchScene().observer);
  const ClassifiedVolume cv = classifyEngine(*model.model);
  const RenderRequest request = engineRequest(cv, size);
  shearwarp::RleVolume::of(cv)->buildAll();  // cached on cv: every frame reuses it
  const ShearWarpRenderer sw;
  const RaycastRenderer rc;
  for (auto _ : state) {
    auto image = shearwarp ? sw.render(request) : rc.render(request);
    benchmark::DoNotOptimize(image.planeFloat(0).data());
  }
  state.SetItemsProcessed(state.iterations());
}

void encode(benchmark::State& state, const std::string& model_name, int axis) {
  const SceneModel model = makeSceneModel(model_name, engineBenchScene().scene, engineBenchScene().observer);
  const ClassifiedVolume cv = classifyEngine(*model.model);
  std::size_t stored = 0, bytes = 0;
  for (auto _ : state) {
    const shearwarp::RleVolume encoded(cv);
    benchmark::DoNotOptimize(&encoded.encoding(axis));
    stored = encoded.encoding(axis).storedVoxels(), bytes = encoded.encoding(axis).bytes();
  }
  state.counters["stored_voxels"] = static_cast<double>(stored);
  state.counters["MiB"] = static_cast<double>(bytes) / (1 << 20);
}

void classifyOnly(benchmark::State& state, const std::string& model_name) {
  const SceneModel model = makeSceneModel(model_name, engineBenchScene().scene, engineBenchScene().observer);
  for (auto _ : state) {
    const ClassifiedVolume cv = classifyEngine(*model.model);
    benchmark::DoNotOptimize(cv.alpha.data());
  }
}

const bool registered = [] {
  for (const char* model : {"rgb", "factor:6"}) {
    for (int size : {512, 800})
      for (bool sw : {true, false})
        benchmark::RegisterBenchmark(
            fmt::format("{}/engine/{}/{}", sw ? "Shearwarp" : "Raycast", size, model).c_str(),
            frame, size, std::string(model), sw)
            ->UseRealTime()
            ->Unit(benchmark::kMillisecond)
            ->MinTime(1.0);
    for (int axis = 0; axis < 3; ++axis)
      benchmark::RegisterBenchmark(
          fmt::format("ShearwarpEncode/engine/{}/{}", model, "xyz"[axis]).c_str(), encode,
          std::string(model), axis)
          ->UseRealTime()
          ->Unit(benchmark::kMillisecond)
          ->MinTime(1.0);
    benchmark::RegisterBenchmark(fmt::format("Classify/engine/{}", model).c_str(), classifyOnly,
                                 std::string(model))
        ->UseRealTime()
        ->Unit(benchmark::kMillisecond)
        ->MinTime(1.0);
  }
  return true;
}();

}  // namespace
}  // namespace svr

BENCHMARK_MAIN();
