// Shear-warp against raycast in one run, engine scene (data/scenes/engine.json, its camera), at
// 512² and 800², rgb and factor:6:
//   Shearwarp/engine/<size>/<model>   time per frame with the encoding already built
//   Raycast/engine/<size>/<model>     the reference backend, same request
//   ShearwarpEncode/<volume>/<model>/<axis>  run-length encoding of one principal axis (x, y,
//                                     z: every view uses one of them; x's rows are strided), of
//                                     the engine (256×256×128) and of engine256, the engine
//                                     resampled to 256³ (the size issue 17's bound is set for),
//                                     and of the frog (a label map, 500×470×136)
//   Classify/engine/<model>           classification (shared by both backends)
// so per-frame time is split from classification and encoding, and the speed ratio is read from
// one run (python3 bench/ratios.py out.json).
#include <benchmark/benchmark.h>
#include <fmt/format.h>

#include "renderers/classification/classification.h"
#include "renderers/scene/scene.h"
#include "renderers/model/scene_model.h"
#include "renderers/raycast/raycast_renderer.h"
#include "renderers/shearwarp/rle_volume.h"
#include "renderers/shearwarp/shearwarp_renderer.h"
#include "spectral/colorimetry.h"
#include "base/data_dir.h"
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

// The engine with z resampled linearly to 256 slices (spacing halved: the same shape), a
// real CT at 256³.
Scene engine256() {
  Scene scene = engineBenchScene().scene;
  const Volume& v = scene.volume;
  const std::vector<float> values = v.toFloat();
  const Dims d = v.dims(), out{d[0], d[1], 256};
  std::vector<float> resampled(static_cast<std::size_t>(out[0]) * out[1] * out[2]);
  const std::size_t plane = static_cast<std::size_t>(d[0]) * d[1];
  for (int z = 0; z < out[2]; ++z) {
    const double at = z * (d[2] - 1.0) / (out[2] - 1.0);
    const int z0 = std::min(static_cast<int>(at), d[2] - 2);
    const float f = static_cast<float>(at - z0);
    for (std::size_t i = 0; i < plane; ++i)
      resampled[z * plane + i] =
          std::round(values[z0 * plane + i] * (1.f - f) + values[(z0 + 1) * plane + i] * f);
  }
  glm::dvec3 spacing = v.spacing();
  spacing.z *= (d[2] - 1.0) / (out[2] - 1.0);
  scene.volume = Volume::fromValues(out, spacing, resampled, "engine resampled to 256³");
  return scene;
}

// The frog (data/scenes/frog.json): a label map of 32 M voxels, the largest default scene.
Scene frog() {
  return loadScene(defaultDataDir() + "/scenes/frog.json", engineBenchScene().library);
}

void encode(benchmark::State& state, const std::string& volume, const std::string& model_name,
            int axis) {
  const SceneModel model = makeSceneModel(model_name, engineBenchScene().scene, engineBenchScene().observer);
  const ClassifiedVolume cv = volume == "engine"      ? classifyEngine(*model.model)
                             : volume == "engine256" ? classifyScene(engine256(), *model.model)
                                                     : classifyScene(frog(), *model.model);
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
    for (const char* volume : {"engine", "engine256", "frog"})
      for (int axis = 0; axis < 3; ++axis)
        benchmark::RegisterBenchmark(
            fmt::format("ShearwarpEncode/{}/{}/{}", volume, model, "xyz"[axis]).c_str(), encode,
            std::string(volume), std::string(model), axis)
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
