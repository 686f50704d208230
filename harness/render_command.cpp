#include "harness/render_command.h"

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <chrono>
#include <memory>
#include <nlohmann/json.hpp>

#include "base/elapsed.h"
#include "base/error.h"
#include "harness/brick_steps.h"
#include "harness/command.h"
#include "harness/image_files.h"
#include "harness/interrupt.h"
#include "harness/progress.h"
#include "harness/render_outputs.h"
#include "harness/render_session.h"
#include "renderers/registry.h"
#include "renderers/render/backend_options.h"

namespace svr {
namespace {

FrameSettings frameSettings(const RenderOptions& o) {
  FrameSettings s;
  s.renderer = o.renderer;
  s.model = o.model;
  s.width = o.width;
  s.height = o.height;
  s.options = o.options;
  s.memory_budget = o.memory_budget;
  s.distribution = o.distribution;
  s.balance = o.balance;
  return s;
}

}  // namespace

// The command's flags become a frame's settings, and the one route from a scene to a frame
// (harness/render_session.h) does the rest: load, model, classify, render, relight, write.
int runRender(const RenderOptions& o) {
  RenderDistribution* const dist = o.distribution;
  const bool writer = !dist || dist->writes();
  const bool quiet = o.quiet || !writer;
  const auto t_spectra = std::chrono::steady_clock::now();
  std::shared_ptr<const SessionSpectra> spectra;
  phase(dist, [&] { spectra = std::make_shared<const SessionSpectra>(o.data_dir); });
  const double spectra_ms = msSince(t_spectra);
  const std::unique_ptr<RenderSession> session =
      RenderSession::load(spectra, o.scene, frameSettings(o));
  Timings t;
  t.load = spectra_ms + session->timings().load;
  t.classify = session->timings().model + session->timings().classify;
  {
    Progress progress("render", 100, quiet);
    int shown = 0;
    t.render = session->render([&](double f) {
      while (shown < static_cast<int>(f * 100)) ++shown, progress.advance();
    });
  }
  if (o.steady) t.steady = session->render();
  const nlohmann::json bricks = dist ? session->gatherBricks() : nlohmann::json();
  if (!writer) return 0;
  if (!quiet)
    for (const auto& note : session->notes()) fmt::print(stderr, "svr: note: {}\n", note);
  writeRenderOutputs(o, session->scene(), session->renderer(), session->model(),
                     spectra->observer, session->image(), t, session->notes(), bricks);
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
