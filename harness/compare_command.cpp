#include "harness/compare_command.h"

#include <CLI/CLI.hpp>
#include <memory>
#include <fmt/format.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <variant>

#include "harness/command.h"
#include "harness/image_files.h"
#include "harness/progress.h"
#include "renderers/registry.h"
#include "base/atomic_file.h"
#include "base/data_dir.h"
#include "base/error.h"
#include "spectral/post_illumination.h"

namespace svr {
namespace fs = std::filesystem;

namespace {

std::string slug(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '.') out += c;
    else if (!out.empty() && out.back() != '_') out += '_';
  }
  while (!out.empty() && out.back() == '_') out.pop_back();
  return out.empty() ? "x" : out;
}

// Portable float map (grey, little-endian), rows bottom to top: numpy reads it in two lines.
void writeFloatMap(const std::string& path, int width, int height, const std::vector<float>& v) {
  writeFileAtomically(path, [&](const std::string& tmp) {
    std::ofstream f(tmp, std::ios::binary);
    f << "Pf\n" << width << " " << height << "\n-1.0\n";
    for (int y = height - 1; y >= 0; --y)
      f.write(reinterpret_cast<const char*>(v.data() + static_cast<std::size_t>(y) * width),
              static_cast<std::streamsize>(width * sizeof(float)));
    f.flush();
    if (!f) throw Error(fmt::format("{}: write failed", path));
  });
}

void writeJson(const std::string& path, const nlohmann::json& j) {
  writeTextAtomically(path, j.dump(1) + "\n");
}

nlohmann::json finiteOrNull(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); }

}  // namespace

void renderReportCharts(const std::string& out_dir) {
  // Debian's interpreter: it has python3-matplotlib (setup.sh installs it).
  const std::string python = fs::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
  const std::string script = scriptDir() + "/report.py";
  const std::string command = fmt::format("'{}' '{}' '{}'", python, script, out_dir);
  if (std::system(command.c_str()) != 0)
    throw Error(fmt::format("{}: the chart script failed ({}); is python3-matplotlib installed "
                            "(./setup.sh)?", out_dir, command));
}

namespace {

// One --variant: BACKEND.KEY=VALUE, or several for one backend joined by commas
// ("shearwarp.slice_samples=4,shearwarp.supersample=2"), as {backend: {key: value, …}}.
std::pair<std::string, nlohmann::json> parseVariant(const std::string& text) {
  std::string backend;
  nlohmann::json options = nlohmann::json::object();
  std::size_t begin = 0;
  while (begin <= text.size()) {
    const std::size_t end = std::min(text.find(',', begin), text.size());
    const std::string one = text.substr(begin, end - begin);
    nlohmann::json checked = nlohmann::json::object();
    applyOptionAssignment(checked, one, "--variant");  // unknown backends or keys fail here
    const OptionAssignment a = parseOptionAssignment(one, "--variant");
    if (!backend.empty() && a.backend != backend)
      throw Error(fmt::format("--variant '{}': '{}' is for backend '{}', its first option for "
                              "'{}'; a variant sets the options of one backend",
                              text, one, a.backend, backend));
    backend = a.backend;
    options[backend][a.key] = a.value;
    begin = end + 1;
  }
  return {backend, options};
}

// Every backend × model, and every --variant of a backend beside its plain run.
std::vector<RunSpec> runSpecs(const CompareOptions& o, const std::vector<std::string>& renderers,
                              const std::vector<std::string>& models) {
  std::vector<std::pair<std::string, nlohmann::json>> variants;
  for (const auto& v : o.variants) variants.push_back(parseVariant(v));
  std::vector<RunSpec> specs;
  for (const auto& r : renderers)
    for (const auto& m : models) {
      specs.push_back({r, m, nlohmann::json::object()});
      for (const auto& [backend, options] : variants)
        if (backend == r) specs.push_back({r, m, options});
    }
  return specs;
}

void writeReferenceImages(const ComparisonSession& session, const std::string& out_dir) {
  const Scene& scene = session.scene();
  fs::create_directories(fs::path(out_dir) / "images" / "reference");
  PostIlluminator post(session.referenceModel());
  if (scene.background) post.setBackground(session.referenceModel().project(*scene.background));
  for (const auto& ill : session.illuminations()) {
    std::vector<std::uint8_t> rgb(3 * session.reference().pixels());
    post.setLight(ill.spectrum);
    post.relightSrgb8(session.reference(), rgb);
    writeSrgbPng(rgb, scene.width, scene.height,
                 (fs::path(out_dir) / "images" / "reference" / (slug(ill.name) + ".png")).string());
  }
}

// One run's entry of report.json, writing its relit images and error maps as it goes.
nlohmann::json runReport(const RunResult& run, const Scene& scene,
                         const std::vector<Exceedance>& misses, const std::string& out_dir) {
  const std::string run_slug = slug(run.spec.label());
  fs::create_directories(fs::path(out_dir) / "images" / run_slug);
  fs::create_directories(fs::path(out_dir) / "maps" / run_slug);
  const auto tolerances = tolerancesFor(run.spec.renderer, scene.tolerances,
                                       runBackendOptions(run.spec, scene.renderer_options));
  double de_tolerance = 0.0;
  for (const auto& t : tolerances)
    if (t.metric == "de_mean") de_tolerance = t.limit;
  nlohmann::json jl = nlohmann::json::array();
  for (const auto& l : run.lights) {
    const std::string light_slug = slug(l.light);
    const std::string image = fmt::format("images/{}/{}.png", run_slug, light_slug);
    const std::string map = fmt::format("maps/{}/{}.pfm", run_slug, light_slug);
    writeSrgbPng(l.relit, scene.width, scene.height, (fs::path(out_dir) / image).string());
    writeFloatMap((fs::path(out_dir) / map).string(), scene.width, scene.height, l.error_map);
    const bool pass = std::none_of(misses.begin(), misses.end(), [&](const Exceedance& m) {
      return m.run == run.spec.label() && m.light == l.light;
    });
    jl.push_back({{"light", l.light},
                  {"de_mean", finiteOrNull(l.vs_reference.mean)},
                  {"de_p95", finiteOrNull(l.vs_reference.p95)},
                  {"de_max", finiteOrNull(l.vs_reference.max)},
                  {"de_model_mean", finiteOrNull(l.model_error.mean)},
                  {"de_model_p95", finiteOrNull(l.model_error.p95)},
                  {"de_sampling_mean", finiteOrNull(l.sampling_error.mean)},
                  {"de_sampling_p95", finiteOrNull(l.sampling_error.p95)},
                  {"de_vs_raycast_mean", finiteOrNull(l.vs_raycast ? l.vs_raycast->mean : 0.0)},
                  {"de_vs_raycast_p95", finiteOrNull(l.vs_raycast ? l.vs_raycast->p95 : 0.0)},
                  {"transmittance_error", finiteOrNull(l.transmittance_error)},
                  {"finite", l.vs_reference.finite},
                  {"tolerance", de_tolerance},
                  {"pass", pass},
                  {"image", image},
                  {"error_map", map}});
  }
  nlohmann::json tol = nlohmann::json::object();
  for (const auto& t : tolerances) tol[t.metric] = t.limit;
  return {{"renderer", run.spec.renderer},
          {"model", run.model_name},
          {"model_asked", run.spec.model},
          {"model_description", run.model_description},
          {"model_choice", run.model_choice},
          {"k", run.k},
          {"options", run.spec.options},
          {"label", run.spec.label()},
          {"classify_ms", run.classify_ms},
          {"render_ms", run.render_ms},
          {"first_render_ms", run.first_render_ms},
          {"relight_ms", run.relight_ms},
          {"render_fps", 1000.0 / std::max(run.render_ms, 1e-9)},
          {"relight_fps", 1000.0 / std::max(run.relight_ms, 1e-9)},
          {"tolerances", tol},
          {"lights", jl}};
}

}  // namespace

CompareSummary runComparison(const CompareOptions& o) {
  const auto library = SpectrumLibrary::load(o.data_dir, WavelengthGrid::standard());
  return runComparison(loadScene(o.scene, library), o);
}

CompareSummary runComparison(Scene scene, const CompareOptions& o) {
  if (o.width > 0) scene.width = o.width;
  if (o.height > 0) scene.height = o.height;
  const std::vector<std::string> renderers = o.renderers.empty() ? rendererNames() : o.renderers;
  for (const auto& r : renderers) backendEntry(r);  // unknown names fail before any work
  checkRendererOptions(scene.renderer_options, o.scene + ": render.options");
  const std::vector<std::string> models =
      o.models.empty() ? std::vector<std::string>{"rgb", "factor:3", "factor:4", "factor:6",
                                                  "factor:8", "spectral:31"}
                       : o.models;
  for (const auto& m : models) checkModelName(m, "--models");  // as for the backends
  const std::vector<RunSpec> specs = runSpecs(o, renderers, models);

  std::error_code ec;
  fs::create_directories(o.out_dir, ec);
  if (ec) throw Error(fmt::format("--out {}: cannot create the folder: {}", o.out_dir, ec.message()));

  Progress progress("compare", static_cast<int>(specs.size()) + 1, o.quiet);
  ComparisonSession session(scene, o.data_dir);
  progress.advance("reference");
  CompareSummary summary;
  summary.scene = o.scene;
  summary.reference_ms = session.referenceMs();
  summary.reference_step = session.referenceStep();
  for (const auto& spec : specs) {
    if (const auto why = session.unsupported(spec.renderer)) {
      const std::string note = fmt::format("{} skipped: {}", spec.label(), *why);
      if (std::find(summary.skipped.begin(), summary.skipped.end(), note) == summary.skipped.end())
        summary.skipped.push_back(note);
    } else {
      auto outcome = session.tryRun(spec);
      if (auto* run = std::get_if<RunResult>(&outcome)) summary.runs.push_back(std::move(*run));
      else summary.failed.push_back(std::get<FailedRun>(std::move(outcome)));
    }
    progress.advance(spec.label());
  }
  for (const auto& run : summary.runs) {
    const auto misses = checkTolerances(run, scene.tolerances, scene.renderer_options);
    summary.exceedances.insert(summary.exceedances.end(), misses.begin(), misses.end());
  }

  writeReferenceImages(session, o.out_dir);
  nlohmann::json report;
  report["scene"] = o.scene;
  report["width"] = scene.width;
  report["height"] = scene.height;
  report["reference"] = Reference().toJson(session.referenceStep(), session.referenceMs());
  nlohmann::json lights = nlohmann::json::array();
  for (const auto& ill : session.illuminations()) lights.push_back(ill.name);
  report["lights"] = lights;
  report["runs"] = nlohmann::json::array();
  for (const auto& run : summary.runs)
    report["runs"].push_back(runReport(run, scene, summary.exceedances, o.out_dir));
  report["pass"] = summary.exceedances.empty() && summary.failed.empty();
  nlohmann::json misses = nlohmann::json::array();
  for (const auto& m : summary.exceedances) misses.push_back(m.str());
  report["exceedances"] = misses;
  report["skipped"] = summary.skipped;
  report["failed"] = nlohmann::json::array();
  for (const auto& f : summary.failed)
    report["failed"].push_back({{"renderer", f.spec.renderer},
                                {"model_asked", f.spec.model},
                                {"options", f.spec.options},
                                {"label", f.spec.label()},
                                {"error", f.error}});
  writeJson((fs::path(o.out_dir) / "report.json").string(), report);
  if (o.charts) renderReportCharts(o.out_dir);
  summary.report = std::move(report);
  return summary;
}

void printSummaryTable(const CompareSummary& s) {
  const ReferenceStep& step = s.reference_step;
  fmt::print("{}: reference {} at step {} voxel ({} from its half: mean ΔE2000 {:.3f}, probed at "
             "{}) {:.0f} ms\n",
             s.scene, Reference().label(), step.step_voxels,
             step.converged ? "converged" : "NOT converged", step.halving_de2000, step.probe_size,
             s.reference_ms);
  // ms/frame: a steady frame; first: the classification's first frame, which builds what the
  // backend keeps (encodings, gradients, uploads).
  // mean ΔE: against the reference; model and sampling: that error's two parts (LightResult).
  fmt::print("{:<40} {:>9} {:>9} {:>11} {:>9} {:>9} {:>9} {:>9}  {}\n", "run", "ms/frame",
             "first ms", "relight fps", "mean ΔE", "model", "sampling", "vs ray", "pass");
  for (const auto& run : s.runs) {
    double de = 0.0, model = 0.0, sampling = 0.0, vr = 0.0;
    const double n = static_cast<double>(run.lights.size());
    for (const auto& l : run.lights) {
      de += l.vs_reference.mean / n;
      model += l.model_error.mean / n;
      sampling += l.sampling_error.mean / n;
      if (l.vs_raycast) vr += l.vs_raycast->mean / n;
    }
    bool pass = true;
    for (const auto& m : s.exceedances)
      if (m.run == run.spec.label()) pass = false;
    fmt::print("{:<40} {:>9.1f} {:>9.1f} {:>11.0f} {:>9.3f} {:>9.3f} {:>9.3f} {:>9.3f}  {}\n",
               run.spec.label(), run.render_ms, run.first_render_ms,
               1000.0 / std::max(run.relight_ms, 1e-9), de, model, sampling, vr,
               pass ? "yes" : "NO");
  }
  for (const auto& f : s.failed) fmt::print("{:<40} FAILED (error below)\n", f.spec.label());
}

void printSummaryNotes(const CompareSummary& s) {
  for (const auto& note : s.skipped) fmt::print(stderr, "svr: note: {}\n", note);
  for (const auto& m : s.exceedances) fmt::print(stderr, "svr: tolerance: {}\n", m.str());
  for (const auto& f : s.failed)
    fmt::print(stderr, "svr: error: run '{}' failed: {}\n", f.spec.label(), f.error);
}

int compareExitStatus(const CompareSummary& s) {
  if (!s.failed.empty()) return 2;
  return s.exceedances.empty() ? 0 : 1;
}

int runCompare(const CompareOptions& o) {
  const CompareSummary s = runComparison(o);
  if (!o.quiet) printSummaryTable(s);
  printSummaryNotes(s);
  if (!o.quiet) fmt::print("report: {}\n", (fs::path(o.out_dir) / "report.html").string());
  return compareExitStatus(s);
}

namespace commands {

CommandEntry compare() {
  return {"compare", "reference and every backend × model on one scene: ΔE2000, times, report",
          [](CLI::App& sub, CommandContext& context) {
            auto o = std::make_shared<CompareOptions>();
            sub.add_option("SCENE", o->scene, "scene JSON")->required();
            sub.add_option("--renderers", o->renderers, "backends (default: all)")->delimiter(',');
            sub.add_option("--models", o->models,
                           "models (default rgb,factor:3,factor:4,factor:6,factor:8,spectral:31)")
                ->delimiter(',');
            sub.add_option("--variant", o->variants,
                           "extra run with backend options, BACKEND.KEY=VALUE[,BACKEND.KEY=VALUE…] "
                           "for one backend (repeatable)");
            sub.add_option("--out", o->out_dir, "report folder")->required();
            auto* width = sub.add_option("--width", o->width, "image width (default: the scene's)");
            auto* height =
                sub.add_option("--height", o->height, "image height (default: the scene's)");
            sub.add_flag("-q,--quiet", o->quiet, "no progress bar or table");
            addCacheFlag(sub);
            sub.callback([o, width, height, &context] {
              o->data_dir = context.data_dir;
              if (width->count()) checkImageSize("compare", "--width", o->width);
              if (height->count()) checkImageSize("compare", "--height", o->height);
              context.status = runCompare(*o);
            });
          }};
}

}  // namespace commands

}  // namespace svr
