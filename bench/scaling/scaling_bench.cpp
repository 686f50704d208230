// Time per frame of every registered backend, at rgb and factor:6, against:
//   Volume/ml<n>/<model>/<backend>          Marschner–Lobb at n³ (n = 64 … 512), 512² image
//   Scene/<engine|frog|phantom>/<model>/<backend>   the default scenes' own volumes, 512²
//   Image/engine/<size>/<model>/<backend>  the engine at size² (256 … 1600)
// bench/scaling/run drives it (threads through OMP_NUM_THREADS, timing through
// --benchmark_min_time; it also runs Image/engine/512 at 1 and at all threads for the parallel
// efficiency). Marschner–Lobb spans [−1, 1]³ at every n, so its optical depth stays the same
// while the voxel count grows and the sample step (0.5 voxel) shrinks: the curve is the cost of
// resolution, not of a thicker volume. Classification and what backends cache on it (the
// shear-warp encoding, the splat list) are built once per volume and model, outside the timed
// loop, as they are while only the view changes.
//
// Options, taken out before Google Benchmark reads the rest:
//   --volume-sizes=64,128,256,512   --image-sizes=256,512,800,1200,1600
//   --backends=raycast,shearwarp,…  (default: every registered CPU backend; gl — llvmpipe here,
//                                   15–20 s a frame for Marschner–Lobb 64³ at 512² — on request)
//   --gl-max-image=512              the gl backend only up to this image size
//   --splat-max-volume=256          splat only up to this n: its cost grows with the voxel count
//                                   (about 9 s a frame at 128³ on one core), 512³ would take minutes
#include <benchmark/benchmark.h>
#include <fmt/format.h>

#include <algorithm>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "bench/engine_scene.h"
#include "renderers/registry.h"
#include "base/error.h"

namespace svr {
namespace {

// The built backends that need no GL context (those go in only with --gl, up to gl_max_image).
std::vector<std::string> cpuBackends() {
  std::vector<std::string> names;
  for (const BackendEntry& e : backendEntries())
    if (e.make && !e.info.supports.needs_gl) names.push_back(e.info.name);
  return names;
}

bool needsGl(const std::string& backend) { return backendEntry(backend).info.supports.needs_gl; }

struct Options {
  std::vector<int> volume_sizes{64, 128, 256, 512};
  std::vector<int> image_sizes{256, 512, 800, 1200, 1600};
  std::vector<std::string> backends = cpuBackends();
  int gl_max_image = 512;
  int splat_max_volume = 256;
};

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream in(s);
  for (std::string item; std::getline(in, item, ',');)
    if (!item.empty()) out.push_back(item);
  return out;
}

std::vector<int> splitInts(const std::string& s, const std::string& option) {
  std::vector<int> out;
  for (const std::string& item : split(s)) {
    try {
      out.push_back(std::stoi(item));
    } catch (const std::exception&) {
      throw Error(fmt::format("{}: '{}' is not an integer", option, item));
    }
  }
  return out;
}

// The Marschner–Lobb test scene: two materials over the value range with an opacity ramp,
// per unit world length over a volume 2 world units wide.
nlohmann::json marschnerLobbScene(int n) {
  return nlohmann::json::parse(fmt::format(R"({{
    "volume": {{"procedural": "marschner_lobb", "size": {}}},
    "materials": {{
      "low": {{"reflectance": "ColorChecker/blue", "opacity": 1.0}},
      "high": {{"reflectance": "ColorChecker/orange", "opacity": 4.0, "specular": 0.3}}
    }},
    "transfer_function": {{"type": "scalar", "points": [[0.3, "low"], [0.7, "high"]],
                           "opacity": [[0, 0], [0.25, 0], [0.35, 1], [1, 1]]}},
    "lights": ["D65", "F11"],
    "camera": {{"azimuth": -60, "elevation": 30}},
    "render": {{"step": 0.5, "early_termination": 0.01}}
  }})", n));
}

// One scene, model and classification at a time: a 512³ classification holds gigabytes, and
// the benchmarks run in registration order, grouped by scene and model.
struct Loaded {
  std::string key;
  std::unique_ptr<Scene> scene;
  std::unique_ptr<SceneModel> model;
  std::unique_ptr<ClassifiedVolume> classified;
};

const Loaded& load(const std::string& scene_name, const std::string& model_name) {
  static Loaded current;
  const std::string key = scene_name + "|" + model_name;
  if (current.key == key) return current;
  current = Loaded{};  // release the previous classification before building the next
  const EngineBenchScene& base = engineBenchScene();
  if (scene_name.rfind("ml", 0) == 0) {
    current.scene = std::make_unique<Scene>(
        parseScene(marschnerLobbScene(std::stoi(scene_name.substr(2))),
                   defaultDataDir() + "/scenes/" + scene_name, base.library));
  } else {
    current.scene = std::make_unique<Scene>(
        loadScene(defaultDataDir() + "/scenes/" + scene_name + ".json", base.library));
  }
  current.model =
      std::make_unique<SceneModel>(makeSceneModel(model_name, *current.scene, base.observer));
  ClassificationOptions options;
  options.step_world = current.scene->stepWorld();
  options.bins = current.scene->bins;
  current.classified = std::make_unique<ClassifiedVolume>(
      classify(current.scene->volume, current.scene->transfer_function, *current.model->model,
               options));
  current.key = key;
  return current;
}

void frame(benchmark::State& state, const std::string& scene_name, const std::string& model,
           const std::string& backend, int size) {
  const Loaded& l = load(scene_name, model);
  const Scene& s = *l.scene;
  const auto renderer = makeRenderer(backend);
  RenderRequest request = sceneRequest(s, *l.classified);
  request.width = request.height = size;
  request.options["raycast"]["gradients"] = "precomputed";  // steady frames, as engineRequest
  renderer->render(request);  // builds what backends cache on the classification
  for (auto _ : state) {
    auto image = renderer->render(request);
    benchmark::DoNotOptimize(image.planeFloat(0).data());
  }
  state.counters["voxels"] = static_cast<double>(s.volume.voxelCount());
  state.counters["pixels"] = static_cast<double>(size) * size;
}

void add(const std::string& name, const std::string& scene, const std::string& model,
         const std::string& backend, int size) {
  benchmark::RegisterBenchmark(name.c_str(), frame, scene, model, backend, size)
      ->UseRealTime()
      ->Unit(benchmark::kMillisecond);
}

void registerAll(const Options& o) {
  const char* models[] = {"rgb", "factor:6"};
  // Grouped by scene, then model, so that load() classifies each pair once.
  for (int n : o.volume_sizes)
    for (const char* model : models)
      for (const std::string& b : o.backends)
        if (b != "splat" || n <= o.splat_max_volume)
          add(fmt::format("Volume/ml{}/{}/{}", n, model, b), fmt::format("ml{}", n), model, b, 512);
  for (const char* scene : {"engine", "frog", "phantom"})
    for (const char* model : models)
      for (const std::string& b : o.backends)
        add(fmt::format("Scene/{}/{}/{}", scene, model, b), scene, model, b, 512);
  for (const char* model : models)
    for (int size : o.image_sizes)
      for (const std::string& b : o.backends)
        if (!needsGl(b) || size <= o.gl_max_image)
          add(fmt::format("Image/engine/{}/{}/{}", size, model, b), "engine", model, b, size);
}

}  // namespace
}  // namespace svr

int main(int argc, char** argv) {
  try {
    svr::Options o;
    int kept = 1;
    for (int i = 1; i < argc; ++i) {
      const std::string arg = argv[i];
      const auto value = [&](const char* option) {
        const std::string prefix = std::string(option) + "=";
        return arg.rfind(prefix, 0) == 0 ? arg.substr(prefix.size()) : std::string();
      };
      if (auto v = value("--volume-sizes"); !v.empty()) o.volume_sizes = svr::splitInts(v, "--volume-sizes");
      else if (auto v = value("--image-sizes"); !v.empty()) o.image_sizes = svr::splitInts(v, "--image-sizes");
      else if (auto v = value("--gl-max-image"); !v.empty()) o.gl_max_image = svr::splitInts(v, "--gl-max-image").at(0);
      else if (auto v = value("--splat-max-volume"); !v.empty()) o.splat_max_volume = svr::splitInts(v, "--splat-max-volume").at(0);
      else if (auto v = value("--backends"); !v.empty()) {
        o.backends = svr::split(v);
        for (const std::string& b : o.backends) svr::makeRenderer(b);  // unknown names fail here
      } else argv[kept++] = argv[i];
    }
    argc = kept;
    svr::registerAll(o);
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 2;
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
  } catch (const std::exception& e) {
    fmt::print(stderr, "svr_scaling_bench: {}\n", e.what());
    return 1;
  }
  return 0;
}
