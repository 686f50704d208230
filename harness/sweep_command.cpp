#include "harness/sweep_command.h"

#include <CLI/CLI.hpp>
#include <memory>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <variant>
#include <glm/geometric.hpp>

#include "harness/command.h"
#include "harness/compare_command.h"
#include "harness/comparison.h"
#include "harness/progress.h"
#include "renderers/registry.h"
#include "base/atomic_file.h"
#include "base/error.h"

namespace svr {
namespace fs = std::filesystem;

namespace {

struct ParamRange {
  std::string name;
  double from, to, step;
};

ParamRange parseRange(const std::string& text) {
  const auto eq = text.find('=');
  ParamRange r;
  int read = 0;
  if (eq != std::string::npos) {
    r.name = text.substr(0, eq);
    read = std::sscanf(text.c_str() + eq + 1, "%lf:%lf:%lf", &r.from, &r.to, &r.step);
  }
  if (eq == std::string::npos || read != 3 || r.name.empty())
    throw Error(fmt::format("--param '{}': expected NAME=FROM:TO:STEP, e.g. azimuth=0:90:1", text));
  if (!std::isfinite(r.from) || !std::isfinite(r.to) || !(r.step > 0) || r.to < r.from)
    throw Error(fmt::format("--param '{}': needs FROM ≤ TO and STEP > 0", text));
  if ((r.to - r.from) / r.step > 1000)
    throw Error(fmt::format("--param '{}': more than 1000 values", text));
  static const char* known[] = {"azimuth", "elevation", "zoom", "step", "k", "depth"};
  if (std::find(std::begin(known), std::end(known), r.name) == std::end(known) &&
      r.name.find('.') == std::string::npos)
    throw Error(fmt::format("--param '{}': unknown parameter '{}'; expected azimuth, elevation, "
                            "zoom, step, k, depth or BACKEND.KEY",
                            text, r.name));
  return r;
}

// The scene (and model, and options) at one value of the parameter.
void apply(const ParamRange& p, double v, const Scene& base, Scene& s, std::string& model,
           nlohmann::json& options) {
  if (p.name == "azimuth" || p.name == "elevation" || p.name == "zoom") {
    OrbitView view = orbitViewOf(base.camera);
    (p.name == "azimuth" ? view.azimuth : p.name == "elevation" ? view.elevation : view.zoom) = v;
    if (p.name == "zoom" && !(v > 0)) throw Error(fmt::format("--param zoom: {} must be > 0", v));
    s.camera = orbitCamera(base.camera, view);
  } else if (p.name == "step") {
    if (!(v > 0)) throw Error(fmt::format("--param step: {} must be > 0", v));
    s.step_voxels = v;
  } else if (p.name == "k") {
    model = fmt::format("factor:{}", static_cast<int>(std::lround(v)));
  } else if (p.name == "depth") {
    if (!(v >= 0)) throw Error(fmt::format("--param depth: {} must be ≥ 0", v));
    for (size_t i = 0; i < s.transfer_function.materials.size(); ++i)
      s.transfer_function.materials[i].extinction = base.transfer_function.materials[i].extinction * v;
  } else {
    const auto dot = p.name.find('.');
    // Whole values as integers, so integer options (shearwarp.supersample) take them.
    const nlohmann::json value =
        v == std::round(v) && std::abs(v) < 1e9 ? nlohmann::json(std::llround(v)) : nlohmann::json(v);
    options[p.name.substr(0, dot)][p.name.substr(dot + 1)] = value;
  }
}

}  // namespace

SweepResult runSweepStudy(const SweepOptions& o) {
  const ParamRange range = parseRange(o.param);
  const auto library = SpectrumLibrary::load(o.data_dir, WavelengthGrid::standard());
  Scene base = loadScene(o.scene, library);
  base.width = o.width;
  base.height = o.height;
  const std::vector<std::string> renderers = o.renderers.empty() ? rendererNames() : o.renderers;
  for (const auto& r : renderers) backendEntry(r);  // unknown names fail before any work
  SweepResult result;
  result.param = range.name;
  for (double v = range.from; v <= range.to + 1e-9 * std::max(1.0, std::abs(range.to)); v += range.step)
    result.values.push_back(v);
  for (const auto& r : renderers) result.curves.push_back({r, {}, {}, {}});
  // Every value is checked before anything renders: a mistyped backend, key or an
  // out-of-range value fails as in svr render.
  checkRendererOptions(base.renderer_options, o.scene + ": render.options");
  for (double v : result.values) {
    Scene s = base;
    std::string model = o.model;
    nlohmann::json options = nlohmann::json::object();
    apply(range, v, base, s, model, options);
    checkRendererOptions(options, fmt::format("--param '{}' at {}", o.param, v));
    checkModelName(model, fmt::format("--param '{}' at {}: model", o.param, v));
  }

  Progress progress("sweep", static_cast<int>(result.values.size()), o.quiet);
  for (double v : result.values) {
    Scene s = base;
    std::string model = o.model;
    nlohmann::json options = nlohmann::json::object();
    apply(range, v, base, s, model, options);
    ComparisonSession session(s, o.data_dir);
    for (auto& curve : result.curves) {
      auto outcome = session.tryRun({curve.renderer, model, options});
      if (const auto* failed = std::get_if<FailedRun>(&outcome)) {
        curve.de_mean.push_back(NAN);
        curve.ms.push_back(NAN);
        curve.errors.push_back(failed->error);
        continue;
      }
      const RunResult& run = std::get<RunResult>(outcome);
      curve.errors.emplace_back();
      double de = 0.0;
      bool finite = true;
      for (const auto& l : run.lights) {
        de += l.vs_reference.mean / run.lights.size();
        finite = finite && l.vs_reference.finite;
      }
      curve.de_mean.push_back(finite ? de : NAN);
      curve.ms.push_back(run.render_ms);
    }
    progress.advance(fmt::format("{} = {}", range.name, v));
  }

  // Flags: non-finite values, blow-ups (mean ΔE2000 > 50), and jumps (a change between
  // neighbouring values more than 4× the median change and above 0.5).
  for (auto& curve : result.curves) {
    std::vector<double> steps;
    for (size_t i = 1; i < curve.de_mean.size(); ++i)
      if (std::isfinite(curve.de_mean[i]) && std::isfinite(curve.de_mean[i - 1]))
        steps.push_back(std::abs(curve.de_mean[i] - curve.de_mean[i - 1]));
    std::vector<double> sorted = steps;
    std::sort(sorted.begin(), sorted.end());
    const double median = sorted.empty() ? 0.0 : sorted[sorted.size() / 2];
    for (size_t i = 0; i < curve.de_mean.size(); ++i) {
      const double v = result.values[i], de = curve.de_mean[i];
      if (!curve.errors[i].empty())
        curve.flags.push_back(fmt::format("failed at {}: {}", v, curve.errors[i]));
      else if (!std::isfinite(de)) curve.flags.push_back(fmt::format("non-finite at {}", v));
      else if (de > 50) curve.flags.push_back(fmt::format("blow-up at {} (mean ΔE2000 {:.1f})", v, de));
      if (i > 0 && std::isfinite(de) && std::isfinite(curve.de_mean[i - 1])) {
        const double jump = std::abs(de - curve.de_mean[i - 1]);
        if (jump > 0.5 && jump > 4 * median)
          curve.flags.push_back(fmt::format("jump at {} ({:.2f} → {:.2f})", v,
                                            curve.de_mean[i - 1], de));
      }
    }
  }

  std::error_code ec;
  fs::create_directories(o.out_dir, ec);
  if (ec) throw Error(fmt::format("--out {}: cannot create the folder: {}", o.out_dir, ec.message()));
  nlohmann::json j = {{"scene", o.scene}, {"param", range.name}, {"values", result.values},
                      {"model", o.model}};
  j["renderers"] = nlohmann::json::array();
  const auto finiteOrNull = [](const std::vector<double>& values) {
    nlohmann::json out = nlohmann::json::array();
    for (double d : values) out.push_back(std::isfinite(d) ? nlohmann::json(d) : nlohmann::json());
    return out;
  };
  for (const auto& c : result.curves)
    j["renderers"].push_back({{"renderer", c.renderer},
                              {"de_mean", finiteOrNull(c.de_mean)},
                              {"ms", finiteOrNull(c.ms)},
                              {"errors", c.errors},
                              {"flags", c.flags}});
  const fs::path path = fs::path(o.out_dir) / "sweep.json";
  writeTextAtomically(path.string(), j.dump(1) + "\n");
  if (o.charts) renderReportCharts(o.out_dir);
  return result;
}

int runSweep(const SweepOptions& o) {
  const SweepResult r = runSweepStudy(o);
  if (!o.quiet) {
    for (const auto& c : r.curves) {
      // The worst finite value (a failed or non-finite run is flagged below, not ranked).
      const auto worst = std::max_element(c.de_mean.begin(), c.de_mean.end(), [](double a, double b) {
        return std::isfinite(b) && (!std::isfinite(a) || a < b);
      });
      fmt::print("{}: {} values of {}; worst mean ΔE2000 {:.3f} at {}\n", c.renderer,
                 r.values.size(), r.param, worst == c.de_mean.end() ? NAN : *worst,
                 worst == c.de_mean.end() ? NAN : r.values[worst - c.de_mean.begin()]);
      for (const auto& f : c.flags) fmt::print("  flag: {}\n", f);
    }
    fmt::print("sweep: {}\n", (fs::path(o.out_dir) / "sweep.json").string());
  }
  int status = 0;
  for (const auto& c : r.curves)
    for (std::size_t i = 0; i < c.errors.size(); ++i)
      if (!c.errors[i].empty()) {
        fmt::print(stderr, "svr: error: {} at {} = {} failed: {}\n", c.renderer, r.param,
                   r.values[i], c.errors[i]);
        status = 2;
      }
  return status;
}

namespace commands {

CommandEntry sweep() {
  return {"sweep", "ΔE2000 and time against one parameter, with jumps and blow-ups flagged",
          [](CLI::App& sub, CommandContext& context) {
            auto o = std::make_shared<SweepOptions>();
            auto size = std::make_shared<int>(0);
            sub.add_option("SCENE", o->scene, "scene JSON")->required();
            sub.add_option("--param", o->param,
                           "NAME=FROM:TO:STEP; NAME: azimuth, elevation, zoom, step, k, depth or "
                           "BACKEND.KEY")
                ->required();
            sub.add_option("--renderers", o->renderers, "backends (default: all)")->delimiter(',');
            sub.add_option("--model", o->model, "colour model")->capture_default_str();
            auto* size_option = sub.add_option("--size", *size, "image width and height (default 96)");
            auto* width = sub.add_option("--width", o->width, "image width (default 96)");
            auto* height = sub.add_option("--height", o->height, "image height (default 96)");
            size_option->excludes(width)->excludes(height);
            sub.add_option("--out", o->out_dir, "output folder")->required();
            sub.add_flag("-q,--quiet", o->quiet, "no progress bar");
            addCacheFlag(sub);
            sub.callback([o, size, size_option, width, height, &context] {
              o->data_dir = context.data_dir;
              if (size_option->count()) {
                checkImageSize("sweep", "--size", *size);
                o->width = o->height = *size;
              }
              if (width->count()) checkImageSize("sweep", "--width", o->width);
              if (height->count()) checkImageSize("sweep", "--height", o->height);
              context.status = runSweep(*o);
            });
          }};
}

}  // namespace commands

}  // namespace svr
