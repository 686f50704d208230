#include "harness/render_command.h"

#include <fmt/format.h>

#include <cctype>
#include <chrono>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "harness/image_files.h"
#include "harness/interrupt.h"
#include "harness/progress.h"
#include "renderers/core/classification.h"
#include "renderers/core/scene.h"
#include "renderers/core/scene_model.h"
#include "renderers/registry.h"
#include "spectral/atomic_file.h"
#include "spectral/colorimetry.h"
#include "spectral/error.h"
#include "spectral/light_mixer.h"
#include "spectral/post_illumination.h"

namespace svr {
namespace fs = std::filesystem;

namespace {

double msSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

// A light or mix name as a file name: letters, digits, '-', '_' and '.' survive.
std::string fileStem(const std::string& name) {
  std::string out;
  for (char c : name) out += (std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == '.') ? c : '_';
  return out.empty() ? "light" : out;
}

// "splat.mode=sheet" → options["splat"]["mode"] = "sheet"; values that parse as JSON (numbers,
// true/false) keep their type.
void applyOption(nlohmann::json& options, const std::string& text) {
  const auto dot = text.find('.'), eq = text.find('=');
  if (dot == std::string::npos || eq == std::string::npos || dot == 0 || eq < dot + 2)
    throw Error(fmt::format("--option '{}': expected BACKEND.KEY=VALUE, e.g. splat.mode=sheet", text));
  const std::string backend = text.substr(0, dot), key = text.substr(dot + 1, eq - dot - 1);
  const std::string value = text.substr(eq + 1);
  nlohmann::json parsed = nlohmann::json::parse(value, nullptr, false);
  options[backend][key] = parsed.is_discarded() ? nlohmann::json(value) : parsed;
}

}  // namespace

int runRender(const RenderOptions& o) {
  using clock = std::chrono::steady_clock;
  const auto t_load = clock::now();
  const WavelengthGrid grid = WavelengthGrid::standard();
  const auto library = SpectrumLibrary::load(o.data_dir, grid);
  const auto observer = Observer::cie1931(o.data_dir, grid);
  VolumeLoadOptions volume_options;
  if (o.memory_budget) volume_options.memory_budget = *o.memory_budget;
  Scene scene = loadScene(o.scene, library, volume_options);
  if (o.width) scene.width = *o.width;
  if (o.height) scene.height = *o.height;
  const auto renderer = makeRenderer(o.renderer);  // unknown names fail before any work
  checkRendererOptions(scene.renderer_options, o.scene + ": render.options");
  for (const auto& option : o.options) applyOption(scene.renderer_options, option);
  checkRendererOptions(scene.renderer_options, "--option");
  const double load_ms = msSince(t_load);

  const auto t_classify = clock::now();
  const std::string model_name = o.model.empty() ? scene.model : o.model;
  const SceneModel chosen = makeSceneModel(model_name, scene, observer);
  const ColourModel& model = *chosen.model;
  ClassificationOptions copts;
  copts.step_world = scene.stepWorld();
  copts.bins = scene.bins;
  const ClassifiedVolume classified = classify(scene.volume, scene.transfer_function, model, copts);
  const double classify_ms = msSince(t_classify);

  const auto t_render = clock::now();
  LightIndependentImage image;
  {
    Progress progress("render", 100, o.quiet);
    int shown = 0;
    RenderRequest request{classified, scene.camera, scene.width, scene.height, scene.shading,
                          scene.light_direction, scene.termination, true,
                          scene.renderer_options};
    image = renderer->render(request, [&](double f) {
      while (shown < static_cast<int>(f * 100)) ++shown, progress.advance();
    });
  }
  const double render_ms = msSince(t_render);

  // From here on files are written: Ctrl-C waits for them to be complete (issue 9).
  const WritingOutputs writing;
  std::error_code mkdir_error;
  fs::create_directories(o.out_dir, mkdir_error);
  if (mkdir_error)
    throw Error(fmt::format("--out {}: cannot create the folder: {}", o.out_dir,
                            mkdir_error.message()));
  // Relight under every light and mix.
  const auto t_relight = clock::now();
  PostIlluminator post(model);
  if (scene.background) post.setBackground(model.project(*scene.background));
  std::vector<Eigen::VectorXd> light_coeffs;
  for (const auto& l : scene.lights) light_coeffs.push_back(model.project(observer.unitLuminance(l.spectrum)));
  struct Output {
    std::string name, file;
    Eigen::VectorXd light;
  };
  std::vector<Output> outputs;
  for (size_t i = 0; i < scene.lights.size(); ++i)
    outputs.push_back({scene.lights[i].name, fileStem(scene.lights[i].name) + ".png", light_coeffs[i]});
  for (const auto& mix : scene.mixes) {
    std::vector<Eigen::VectorXd> ls;
    std::vector<double> ws;
    for (const auto& [index, w] : mix.weights) ls.push_back(light_coeffs[index]), ws.push_back(w);
    outputs.push_back({mix.name, "mix_" + fileStem(mix.name) + ".png", mixLights(ls, ws)});
  }
  std::vector<std::vector<std::uint8_t>> relit(outputs.size());
  for (size_t i = 0; i < outputs.size(); ++i) {
    relit[i].resize(3 * image.pixels());
    post.setLight(outputs[i].light);
    post.relightSrgb8(image, relit[i]);
  }
  const double relight_ms = msSince(t_relight) / std::max<size_t>(outputs.size(), 1);

  const LightIndependentImage stored =
      o.half ? image.withStorage(SampleStorage::kHalf) : image;
  const std::string exr = (fs::path(o.out_dir) / "light_independent.exr").string();
  const std::string model_file = (fs::path(o.out_dir) / "light_independent.model.json").string();
  saveModel(model, model_file);
  writeLightIndependentExr(stored, exr,
                           {{"model", model.name()}, {"model_file", "light_independent.model.json"},
                            {"scene", o.scene}, {"renderer", renderer->name()}});
  for (size_t i = 0; i < outputs.size(); ++i)
    writeSrgbPng(relit[i], image.width(), image.height(),
                 (fs::path(o.out_dir) / outputs[i].file).string());

  nlohmann::json report = {
      {"renderer", renderer->name()},
      {"model", model.name()},
      {"model_description", chosen.description},
      {"model_choice", chosen.record()},
      {"k", model.channels()},
      {"t_channels", image.transmittanceChannels()},
      {"width", image.width()},
      {"height", image.height()},
      {"scene", o.scene},
      {"volume", scene.volume_source},
      {"step_world", scene.stepWorld()},
      {"early_termination", scene.termination},
      {"renderer_options", scene.renderer_options},
      {"exr", "light_independent.exr"},
      {"model_file", "light_independent.model.json"},
      {"timings_ms",
       {{"load", load_ms}, {"classify", classify_ms}, {"render", render_ms}, {"relight", relight_ms}}},
  };
  nlohmann::json images = nlohmann::json::array();
  for (const auto& out : outputs) images.push_back({{"light", out.name}, {"file", out.file}});
  report["images"] = images;
  const std::string report_path = (fs::path(o.out_dir) / "render.json").string();
  writeTextAtomically(report_path, report.dump(1) + "\n");
  if (!o.quiet)
    fmt::print("{}: {} with {} ({}), {}×{}: load {:.0f} ms, classify {:.0f} ms, render {:.0f} ms, "
               "relight {:.2f} ms/light → {}\n",
               o.scene, renderer->name(), model.name(), chosen.description, image.width(),
               image.height(), load_ms, classify_ms, render_ms, relight_ms, o.out_dir);
  return 0;
}

}  // namespace svr
