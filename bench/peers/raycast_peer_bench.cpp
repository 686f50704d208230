// Our raycasters on the views bench/peers/vtk_bench.py gives VTK's mappers, so the two time the
// same volume, transfer function, camera, sample distance (the scene's step, 0.5 voxel) and
// image size:
//   Raycast/<rgb|factor:6>/<size>/az<deg>     the raycast backend against
//                                             vtkFixedPointVolumeRayCastMapper
//   GlRaycast/<rgb|factor:6>/<size>/az<deg>   gl.mode=raycast (its platform's default: OSMesa
//                                             on llvmpipe here) against vtkGPUVolumeRayCastMapper
//                                             on the same llvmpipe; the time includes reading
//                                             the image back
//   GlSplat/<rgb|factor:6>/256/az-60          gl.mode=splat (sheets) on the scene's view, for
//                                             the ratio gl raycast / gl splat at 256²
//   Splat<Sheet|Direct>/<rgb|factor:6>/512/az<deg>   the splat backend against the fixed-point
//                                             mapper (OMP_NUM_THREADS as the raycast rows)
// Classification cached. Threads: OMP_NUM_THREADS for the CPU raycaster (bench/peers/run sets it
// equal to VTK's SetNumberOfThreads); llvmpipe's LP_NUM_THREADS for both GL rows.
// Every view renders one untimed frame first (VTK's script does too), then three repetitions of
// at least 0.5 s each; the table takes their median.
//
// --export=PREFIX writes PREFIX.json (dims, spacing, step, termination, shading, light
// direction, the camera of every azimuth, and the per-value tables of peer_scene.h) and
// PREFIX.raw (the engine's uint8 voxels, x fastest) for the VTK script, then exits: the peer is
// set up from our numbers rather than from a second reading of the scene file.
#include <benchmark/benchmark.h>
#include <fmt/format.h>

#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "bench/peers/peer_scene.h"
#include "renderers/registry.h"
#include "base/error.h"

namespace svr::peers {
namespace {

// The scene's azimuth, an axis view and one near the 45° diagonal.
constexpr double kAzimuths[] = {-60.0, 0.0, 44.0};

void raycastFrame(benchmark::State& state, const std::string& backend,
                  const nlohmann::json& options, const std::string& model, int size,
                  double azimuth) {
  const ClassifiedVolume& cv = engineClassified(model);
  const auto renderer = makeRenderer(backend);
  RenderRequest request = engineRequest(cv, azimuth, size);
  if (!options.empty()) request.options[backend] = options;
  // One untimed frame first: it builds what the renderer keeps with the classification (the
  // gradient volume), which VTK's warm-up frame builds too.
  benchmark::DoNotOptimize(renderer->render(request).planeFloat(0).data());
  for (auto _ : state) {
    auto image = renderer->render(request);
    benchmark::DoNotOptimize(image.planeFloat(0).data());
  }
}

void exportScene(const std::string& prefix) {
  const Scene& scene = engineBenchScene().scene;
  const Volume& volume = scene.volume;
  if (volume.type() != ScalarType::kUint8)
    throw Error("raycast peer bench: the engine volume must be uint8");
  const ValueTables t = engineValueTables();
  nlohmann::json j;
  j["dims"] = volume.dims();
  j["spacing"] = {volume.spacing().x, volume.spacing().y, volume.spacing().z};
  j["step_world"] = scene.stepWorld();
  j["termination"] = scene.termination;
  j["shading"] = {{"ambient", scene.shading.ambient},
                  {"diffuse", scene.shading.diffuse},
                  {"specular", scene.shading.specular},
                  {"shininess", scene.shading.shininess}};
  const glm::dvec3 l = scene.light_direction.value_or(glm::dvec3(0.0));
  j["light_direction"] = {l.x, l.y, l.z};
  j["headlight"] = !scene.light_direction.has_value();
  for (double az : kAzimuths) {
    const Camera c = engineCamera(az);
    j["cameras"].push_back({{"azimuth", az},
                            {"eye", {c.eye.x, c.eye.y, c.eye.z}},
                            {"target", {c.target.x, c.target.y, c.target.z}},
                            {"up", {c.up.x, c.up.y, c.up.z}},
                            {"ortho_height", c.ortho_height}});
  }
  j["opacity_per_unit_length"] = t.opacity;
  j["rgb"] = t.rgb;
  j["specular_weight"] = t.specular;
  std::ofstream json_out(prefix + ".json");
  json_out << j.dump(1) << '\n';
  if (!json_out) throw Error(fmt::format("{}.json: cannot write", prefix));
  std::ofstream raw(prefix + ".raw", std::ios::binary);
  raw.write(reinterpret_cast<const char*>(volume.data().data()),
            static_cast<std::streamsize>(volume.bytes()));
  if (!raw) throw Error(fmt::format("{}.raw: cannot write", prefix));
}

void registerAll() {
  const bool gl_built = std::ranges::any_of(
      backendEntries(), [](const BackendEntry& e) { return e.info.name == "gl" && e.make; });
  struct Row {
    const char* name;
    const char* backend;
    nlohmann::json options;
  };
  const nlohmann::json gl_raycast = {{"mode", "raycast"}, {"gradients", "precomputed"}};
  for (const Row& row : {Row{"Raycast", "raycast", {}}, Row{"GlRaycast", "gl", gl_raycast}}) {
    if (std::string(row.backend) == "gl" && !gl_built) continue;
    for (int size : {512, 800})
      for (double az : kAzimuths)
        for (const char* model : {"rgb", "factor:6"})
          benchmark::RegisterBenchmark(
              fmt::format("{}/{}/{}/az{}", row.name, model, size, az).c_str(), raycastFrame,
              std::string(row.backend), row.options, std::string(model), size, az)
              ->UseRealTime()
              ->Unit(benchmark::kMillisecond)
              ->MinTime(0.5)
              ->Repetitions(3)  // the table takes the median, as VTK's rows do
              ->ReportAggregatesOnly(true);
  }
  // The splat backend against the same VTK rows (issue 17: sheet ≤ 4×, direct ≤ 2× VTK at 512²),
  // two timed frames after the untimed one: a sheet frame takes seconds.
  for (const char* mode : {"sheet", "direct"})
    for (double az : kAzimuths)
      for (const char* model : {"rgb", "factor:6"})
        benchmark::RegisterBenchmark(
            fmt::format("Splat{}/{}/512/az{}", mode[0] == 's' ? "Sheet" : "Direct", model, az)
                .c_str(),
            raycastFrame, std::string("splat"), nlohmann::json{{"mode", mode}},
            std::string(model), 512, az)
            ->UseRealTime()
            ->Unit(benchmark::kMillisecond)
            ->Iterations(2);
  if (!gl_built) return;
  for (const char* model : {"rgb", "factor:6"})
    for (const Row& row : {Row{"GlRaycast", "gl", gl_raycast}, Row{"GlSplat", "gl", {{"mode", "splat"}}}})
      benchmark::RegisterBenchmark(fmt::format("{}/{}/256/az-60", row.name, model).c_str(),
                                   raycastFrame, std::string(row.backend), row.options,
                                   std::string(model), 256, -60.0)
          ->UseRealTime()
          ->Unit(benchmark::kMillisecond)
          ->Iterations(3);
}

}  // namespace
}  // namespace svr::peers

int main(int argc, char** argv) {
  try {
    for (int i = 1; i < argc; ++i) {
      const std::string arg = argv[i];
      if (arg.rfind("--export=", 0) == 0) {
        svr::peers::exportScene(arg.substr(9));
        return 0;
      }
    }
    svr::peers::registerAll();
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 2;
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
  } catch (const std::exception& e) {
    fmt::print(stderr, "svr_raycast_peer_bench: {}\n", e.what());
    return 1;
  }
  return 0;
}
