#include "harness/render_command.h"

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cctype>
#include <chrono>
#include <ctime>
#include <optional>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <sys/resource.h>

#include "harness/command.h"
#include "harness/image_files.h"
#include "harness/interrupt.h"
#include "harness/progress.h"
#include "harness/render_outputs.h"
#include "harness/render_distribution.h"
#include "renderers/core/gradient_volume.h"
#include "renderers/core/memory_budget.h"
#include "renderers/core/volume_brick.h"
#include "renderers/core/work_estimate.h"
#include "renderers/core/scene.h"
#include "renderers/scene_model.h"
#include "renderers/core/scene_render.h"
#include "renderers/registry.h"
#include "spectral/atomic_file.h"
#include "spectral/colorimetry.h"
#include "spectral/elapsed.h"
#include "spectral/error.h"
#include "spectral/light_mixer.h"
#include "spectral/post_illumination.h"
#include "harness/view/page_data.h"
#include "harness/view/standalone_page.h"

namespace svr {
namespace fs = std::filesystem;

namespace {

// Runs one phase of the command. In a distributed render every process then agrees on failures
// (RenderDistribution::agree), so a process that failed never leaves the others waiting in a
// collective.
template <class Body>
void phase(RenderDistribution* distribution, Body&& body) {
  if (!distribution) return body();
  std::exception_ptr failure;
  try {
    body();
  } catch (...) {
    failure = std::current_exception();
  }
  distribution->agree(failure);
}

// What the render command loads before any work: the spectra, the backend (unknown names and
// backends that cannot take a brick fail first), the scene with the command line's overrides.
struct Loaded {
  SpectrumLibrary library;
  Observer observer;
  Scene scene;
  std::unique_ptr<Renderer> renderer;
};

Loaded loadForRender(const RenderOptions& o, const WavelengthGrid& grid,
                     const VolumeLoadOptions& volume_options) {
  SpectrumLibrary library = SpectrumLibrary::load(o.data_dir, grid);
  Observer observer = Observer::cie1931(o.data_dir, grid);
  std::unique_ptr<Renderer> renderer = makeRenderer(o.renderer);
  if (o.distribution && !renderer->info().supports.bricks) {
    std::vector<std::string> able;
    for (const std::string& name : rendererNames())
      if (makeRenderer(name)->info().supports.bricks) able.push_back(name);
    throw Error(fmt::format("--renderer {}: this backend cannot render one brick of a "
                            "distributed render; use {}",
                            o.renderer, fmt::join(able, " or ")));
  }
  Scene scene = loadScene(o.scene, library, volume_options);
  if (o.width) scene.width = *o.width;
  if (o.height) scene.height = *o.height;
  checkRendererOptions(scene.renderer_options, o.scene + ": render.options");
  for (const auto& option : o.options)
    applyOptionAssignment(scene.renderer_options, option, "--option");
  if (!o.model.empty() && o.model != "auto") {  // a bad --model names the flag, not the scene
    try {
      const ModelName name = parseModelName(o.model);
      if (name.kind == ModelKind::kSpectral && name.k > grid.count)
        throw Error(fmt::format("spectral:{} asks for more bands than the {} samples of the grid",
                                name.k, grid.count));
    } catch (const Error& e) {
      throw Error(fmt::format("--model '{}': {}", o.model, e.what()));
    }
  }
  return {std::move(library), std::move(observer), std::move(scene), std::move(renderer)};
}

// Peak resident memory of this process so far.
std::uint64_t peakResidentBytes() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<std::uint64_t>(usage.ru_maxrss) * 1024;
}

// CPU time of this process's threads, in ms: the work a rank did, unlike its wall time not
// stretched by waiting or by sharing a core.
double processCpuMs() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return t.tv_sec * 1e3 + t.tv_nsec * 1e-6;
}

nlohmann::json boxJson(const VoxelBox& box) {
  return {{"lo", box.lo}, {"hi", box.hi}};
}

}  // namespace


// The render's work over a coarse lattice of the volume, for backends whose bricks pass the
// transmittance in front on; the others' bricks each work as if alone, and voxels share that out
// best (nullopt).
std::optional<WorkGrid> estimateRenderWork(const RenderOptions& o, const WavelengthGrid& grid,
                                           const VolumeLoadOptions& volume_options) {
  if (!makeRenderer(o.renderer)->info().supports.front_transmittance) return std::nullopt;
  const SpectrumLibrary library = SpectrumLibrary::load(o.data_dir, grid);
  const Observer observer = Observer::cie1931(o.data_dir, grid);
  VolumeLoadOptions coarse = volume_options;
  coarse.brick = nullptr;
  coarse.lattice = Dims{kWorkLatticeSamples, kWorkLatticeSamples, kWorkLatticeSamples};
  const Scene scene = loadScene(o.scene, library, coarse);
  const SceneModel model = makeSceneModel("rgb", scene, observer);
  return estimateWork(classifyScene(scene, *model.model), scene.camera,
                      o.width.value_or(scene.width), o.height.value_or(scene.height),
                      scene.termination);
}

// A distributed render's bricks, decided before any is read: equal time rather than equal
// voxels, where the backend allows. Only an optimisation: if the estimate fails, the bricks
// share voxels and the load that follows reports what is wrong with the scene or its volume, in
// the volume's own coordinates. Returns that failure's message, or "".
std::string splitIntoBricks(const RenderOptions& o, const WavelengthGrid& grid,
                            VolumeLoadOptions& volume_options) {
  RenderDistribution* const dist = o.distribution;
  std::string failure;
  std::optional<WorkGrid> work;
  if (dist->writes() && dist->processes() > 1 && o.balance == "work") try {
      work = estimateRenderWork(o, grid, volume_options);
    } catch (const std::exception& e) {
      failure = e.what();
    }
  dist->balance(work ? &*work : nullptr);
  volume_options.brick = [dist](const Dims& whole) { return dist->brick(whole); };
  return failure;
}

namespace {

// The model (in a distributed render, auto's choice agreed across the bricks) and the
// classification, with the memory of every image checked before any is allocated.
struct ModelAndClassification {
  SceneModel model;
  ClassifiedVolume classified;
};

ModelAndClassification chooseModelAndClassify(const RenderOptions& o, RenderDistribution* dist,
                                              const Scene& scene, const Observer& observer,
                                              std::uint64_t memory_budget) {
  std::optional<SceneModel> chosen_model;
  ClassifiedVolume classified;
  phase(dist, [&] {
    chosen_model = makeSceneModel(o.model.empty() ? scene.model : o.model, scene, observer);
  });
  if (dist && chosen_model->asked == "auto") {
    // Each brick's probe saw its own part of the volume: all take the most channels any asked
    // for (a factor:k, or spectral:81 past factor:16), so every brick renders one model.
    const int k = chosen_model->model->channels();
    const int agreed = static_cast<int>(dist->wholeRange({k, k}).second);
    if (agreed != k)
      phase(dist, [&] {
        SceneModel wider = makeSceneModel(
            agreed > 16 ? fmt::format("spectral:{}", agreed) : fmt::format("factor:{}", agreed),
            scene, observer);
        wider.description = fmt::format("auto: {} — the most channels any brick's probe asked "
                                        "for (this brick's: {})",
                                        wider.description, chosen_model->model->name());
        wider.asked = "auto";
        wider.target = scene.auto_target;
        chosen_model = std::move(wider);
      });
  }
  phase(dist, [&] {
    classified = classifyScene(scene, *chosen_model->model);
    // The light-independent image and every relit image, before any of them is allocated.
    const std::uint64_t relit_count = scene.lights.size() + scene.mixes.size();
    checkMemoryBudget(LightIndependentImage::bytesFor(scene.width, scene.height, classified.k,
                                                      classified.t_channels) +
                          3 * relit_count * std::uint64_t(scene.width) * scene.height,
                      memory_budget,
                      fmt::format("{}: a {}×{} image of {} + {} channels and {} relit images",
                                  o.scene, scene.width, scene.height, classified.k,
                                  classified.t_channels, relit_count));
  });
  if (dist)  // and its gradients quantise as the whole volume's would
    classified.brick->whole_field =
        dist->wholeField(fieldRangeOver(classified, ownInStored(*classified.brick)));
  return {std::move(*chosen_model), std::move(classified)};
}

}  // namespace

int runRender(const RenderOptions& o) {
  using clock = std::chrono::steady_clock;
  RenderDistribution* const dist = o.distribution;
  const bool writer = !dist || dist->writes();
  const bool quiet = o.quiet || !writer;
  Timings t;
  const auto t_load = clock::now();
  const WavelengthGrid grid = WavelengthGrid::standard();
  VolumeLoadOptions volume_options;
  if (o.memory_budget) volume_options.memory_budget = *o.memory_budget;
  std::string estimate_failure;
  if (dist) estimate_failure = splitIntoBricks(o, grid, volume_options);
  std::optional<Loaded> loaded;
  phase(dist, [&] { loaded.emplace(loadForRender(o, grid, volume_options)); });
  Scene& scene = loaded->scene;
  const Observer& observer = loaded->observer;
  const Renderer* const renderer = loaded->renderer.get();
  if (dist) {  // the classification's bins span the whole volume's values, on every brick
    VolumeBrick brick = *scene.volume.brick();
    brick.whole_range = dist->wholeRange(scene.volume.localRange());
    scene.volume.setBrick(brick);
  }
  t.load = msSince(t_load);

  const auto t_classify = clock::now();
  auto [chosen, classified] =
      chooseModelAndClassify(o, dist, scene, observer, volume_options.memory_budget);
  t.classify = msSince(t_classify);

  const auto t_render = clock::now();
  LightIndependentImage image;
  std::vector<std::string> notes;  // shown after the progress bar, not through it
  if (!estimate_failure.empty())
    notes.push_back("the bricks share voxels: estimating the work failed: " + estimate_failure);
  RenderRequest request = sceneRequest(scene, classified);
  request.memory_budget = volume_options.memory_budget;
  request.note = [&](const std::string& note) { notes.push_back(note); };
  double brick_render_ms = 0, brick_render_cpu_ms = 0, composite_ms = 0, front_wait_ms = 0;
  const auto renderFrame = [&](const ProgressFn& progress) {
    phase(dist, [&] {
      // Bricks behind others stop their rays where the whole render does.
      std::unique_ptr<FrontTransmittance> front;
      if (dist && renderer->info().supports.front_transmittance)
        front = dist->frontTransmittance(request.camera, request.width, request.height,
                                         classified.t_channels, scene.volume.spacing());
      request.front = front.get();
      const auto t0 = clock::now();
      const double cpu0 = processCpuMs();
      try {
        image = renderer->render(request, progress);
      } catch (...) {
        if (front) front->abandon();  // the bricks behind are not left waiting on this one
        throw;
      }
      brick_render_ms = msSince(t0);  // this process's own work, before waiting for the others
      brick_render_cpu_ms = processCpuMs() - cpu0;
      front_wait_ms = front ? front->waitedMs() : 0.0;
      request.front = nullptr;
    });
    if (dist) {
      const auto t1 = clock::now();
      image = dist->composite(image, request.camera, scene.volume.spacing());
      if (writer) image = renderer->finishBricks(std::move(image), request);
      composite_ms = msSince(t1);
    }
  };
  {
    Progress progress("render", 100, quiet);
    int shown = 0;
    renderFrame([&](double f) {
      while (shown < static_cast<int>(f * 100)) ++shown, progress.advance();
    });
  }
  t.render = msSince(t_render);
  if (o.steady) {
    request.note = nullptr;  // the first frame said it all
    const auto t_steady = clock::now();
    renderFrame(nullptr);
    t.steady = msSince(t_steady);
  }
  nlohmann::json distributed;
  if (dist) {
    const VolumeBrick& brick = *scene.volume.brick();
    distributed = dist->gather({{"own", boxJson(brick.own)},
                                {"stored", boxJson(brick.stored)},
                                {"volume_bytes", scene.volume.bytes()},
                                {"render_ms", brick_render_ms},
                                {"composite_ms", composite_ms},
                                {"render_cpu_ms", brick_render_cpu_ms},
                                {"front_wait_ms", front_wait_ms},
                                {"peak_resident_bytes", peakResidentBytes()}});
  }
  if (!writer) return 0;
  if (!quiet)
    for (const auto& note : notes) fmt::print(stderr, "svr: note: {}\n", note);
  writeRenderOutputs(o, scene, *renderer, chosen, observer, image, t, notes, distributed);
  return 0;
}

namespace commands {

CommandEntry render() {
  return {"render", "render a scene once, relight it under every scene light and mix",
          [](CLI::App& sub, CommandContext& context) {
            auto o = std::make_shared<RenderOptions>();
            auto budget = std::make_shared<std::string>();
            auto help_options = std::make_shared<std::string>();
            sub.add_option("SCENE", o->scene, "scene JSON (see docs/scenes.md)");
            sub.add_option("--renderer", o->renderer,
                           fmt::format("backend: {}", fmt::join(rendererNames(), ", ")))
                ->capture_default_str();
            sub.add_option("--model", o->model,
                           "colour model: rgb, factor:k, spectral:n or auto (default: the scene's)");
            sub.add_option("--out", o->out_dir, "output folder");
            sub.add_option("--width", o->width, "image width (default: the scene's)");
            sub.add_option("--height", o->height, "image height (default: the scene's)");
            sub.add_flag("--half", o->half, "store the light-independent EXR as half floats");
            sub.add_flag("--html", o->html,
                         "also write view.html: the image with the light dial and sliders, "
                         "relit in the browser, one file that works offline");
            sub.add_flag("--steady", o->steady,
                         "render the view a second time and report that steady frame's time "
                         "too (timings_ms.render_steady): the first frame also builds what the "
                         "backend keeps per classification");
            sub.add_option("--option", o->options,
                           "backend option BACKEND.KEY=VALUE (repeatable), e.g. splat.mode=sheet; "
                           "--help-options lists them");
            sub.add_option("--memory-budget", *budget,
                           "most bytes of voxels and images, e.g. 512M or 2G (default: the "
                           "memory available now)");
            sub.add_flag("-q,--quiet", o->quiet, "no progress bar or summary");
            if (context.distribution)
              sub.add_option("--balance", o->balance,
                             "how the kd-split shares the volume out among the ranks: work "
                             "(bricks that take equal time, estimated from a 128³ lattice of the "
                             "volume; raycast, each brick within 1.25× its share of the voxels) "
                             "or voxels (equal memory)")
                  ->check(CLI::IsMember({"work", "voxels"}))
                  ->capture_default_str();
            addCacheFlag(sub);
            sub.add_option("--help-options", *help_options,
                           "print every backend's options (or BACKEND's) and exit")
                ->expected(0, 1)
                ->default_str("all");
            sub.callback([o, budget, help_options, &sub, &context] {
              if (sub.count("--help-options")) {
                fmt::print("{}", describeBackends(*help_options == "all" ? "" : *help_options));
                return;
              }
              if (o->scene.empty() || o->out_dir.empty())
                throw Error("render: SCENE and --out DIR are required");
              o->data_dir = context.data_dir;
              if (!budget->empty()) o->memory_budget = parseByteSize(*budget, "--memory-budget");
              if (o->width) checkImageSize("render", "--width", *o->width);
              if (o->height) checkImageSize("render", "--height", *o->height);
              installInterruptHandler();
              o->distribution = context.distribution;
              context.status = runRender(*o);
            });
          }};
}

}  // namespace commands

}  // namespace svr
