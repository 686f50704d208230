#include "harness/render_outputs.h"

#include <fmt/format.h>

#include <cctype>
#include <chrono>
#include <filesystem>

#include "harness/image_files.h"
#include "harness/interrupt.h"
#include "harness/view/page_data.h"
#include "harness/view/standalone_page.h"
#include "renderers/render/scene_render.h"
#include "base/atomic_file.h"
#include "base/elapsed.h"
#include "base/error.h"
#include "spectral/post_illumination.h"

namespace svr {
namespace fs = std::filesystem;

namespace {

// A light or mix name as a file name: letters, digits, '-', '_' and '.' survive.
std::string fileStem(const std::string& name) {
  std::string out;
  for (char c : name)
    out += (std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == '.') ? c
                                                                                             : '_';
  return out.empty() ? "light" : out;
}

// One relit output: a scene light or a mix of them, as a spectrum at unit luminance (a mix:
// the weighted sum of its lights').
struct RelitOutput {
  std::string name, file;
  Spectrum light;
  std::vector<std::uint8_t> rgb;
};

std::vector<RelitOutput> sceneOutputs(const Scene& scene, const Observer& observer) {
  const std::vector<Spectrum> spectra = sceneIlluminations(scene, observer);
  std::vector<RelitOutput> outputs;
  for (size_t i = 0; i < scene.lights.size(); ++i)
    outputs.push_back({scene.lights[i].name, fileStem(scene.lights[i].name) + ".png", spectra[i], {}});
  for (size_t m = 0; m < scene.mixes.size(); ++m)
    outputs.push_back({scene.mixes[m].name, "mix_" + fileStem(scene.mixes[m].name) + ".png",
                       spectra[scene.lights.size() + m], {}});
  return outputs;
}


nlohmann::json renderReport(const RenderOptions& o, const Scene& scene, const Renderer& renderer,
                            const SceneModel& chosen, const LightIndependentImage& image,
                            const std::vector<RelitOutput>& outputs, const Timings& t,
                            const std::vector<std::string>& notes) {
  const ColourModel& model = *chosen.model;
  nlohmann::json images = nlohmann::json::array();
  for (const auto& out : outputs) images.push_back({{"light", out.name}, {"file", out.file}});
  nlohmann::json timings = {
      {"load", t.load}, {"classify", t.classify}, {"render", t.render}, {"relight", t.relight}};
  if (t.steady) timings["render_steady"] = *t.steady;
  return {
      {"renderer", renderer.name()},
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
      {"timings_ms", timings},
      {"images", images},
      {"notes", notes},
  };
}

}  // namespace

void writeRenderOutputs(const RenderOptions& o, const Scene& scene, const Renderer& renderer,
                        const SceneModel& chosen, const Observer& observer,
                        const LightIndependentImage& image, Timings t,
                        const std::vector<std::string>& notes,
                        const nlohmann::json& distributed) {
  using clock = std::chrono::steady_clock;
  const ColourModel& model = *chosen.model;
  const bool quiet = o.quiet;
  // From here on files are written: Ctrl-C waits for them to be complete (issue 9).
  const WritingOutputs writing;
  std::error_code mkdir_error;
  fs::create_directories(o.out_dir, mkdir_error);
  if (mkdir_error)
    throw Error(fmt::format("--out {}: cannot create the folder: {}", o.out_dir,
                            mkdir_error.message()));
  const auto t_relight = clock::now();
  PostIlluminator post(model);
  if (scene.background) post.setBackground(model.project(*scene.background));
  std::vector<RelitOutput> outputs = sceneOutputs(scene, observer);
  for (auto& out : outputs) {
    out.rgb.resize(3 * image.pixels());
    post.setLight(out.light);
    post.relightSrgb8(image, out.rgb);
  }
  t.relight = msSince(t_relight) / std::max<size_t>(outputs.size(), 1);

  const LightIndependentImage stored = o.half ? image.withStorage(SampleStorage::kHalf) : image;
  saveModel(model, (fs::path(o.out_dir) / "light_independent.model.json").string());
  writeLightIndependentExr(stored, (fs::path(o.out_dir) / "light_independent.exr").string(),
                           {{"model", model.name()}, {"model_file", "light_independent.model.json"},
                            {"scene", o.scene}, {"renderer", renderer.name()}});
  for (const auto& out : outputs)
    writeSrgbPng(out.rgb, image.width(), image.height(), (fs::path(o.out_dir) / out.file).string());
  if (o.html) {
    const PageLightContext context{model, observer, scene.background, image.transmittanceChannels()};
    const SampleChoice samples = chooseSamples(context, scene, image);
    const nlohmann::json info = pageSceneInfo(context, scene, chosen, renderer.name(),
                                              orbitViewOf(scene.camera), samples);
    writeTextAtomically((fs::path(o.out_dir) / "view.html").string(),
                        standalonePage(info, image.withStorage(samples.storage)));
  }
  nlohmann::json report = renderReport(o, scene, renderer, chosen, image, outputs, t, notes);
  if (!distributed.is_null()) report["distributed"] = {{"processes", distributed.size()}, {"per_process", distributed}};
  writeTextAtomically((fs::path(o.out_dir) / "render.json").string(), report.dump(1) + "\n");
  if (!quiet)
    fmt::print("{}: {} with {} ({}), {}×{}: load {:.0f} ms, classify {:.0f} ms, render {:.0f} ms{}, "
               "relight {:.2f} ms/light → {}\n",
               o.scene, renderer.name(), model.name(), chosen.description, image.width(),
               image.height(), t.load, t.classify, t.render,
               t.steady ? fmt::format(" (steady {:.0f} ms)", *t.steady) : "", t.relight, o.out_dir);
}

}  // namespace svr
