#include "harness/compare_command.h"

#include <fmt/format.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "harness/image_files.h"
#include "harness/progress.h"
#include "renderers/registry.h"
#include "spectral/atomic_file.h"
#include "spectral/error.h"
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
  const std::string script = std::string(SVR_HARNESS_DIR) + "/report.py";
  const std::string command = fmt::format("'{}' '{}' '{}'", python, script, out_dir);
  if (std::system(command.c_str()) != 0)
    throw Error(fmt::format("{}: the chart script failed ({}); is python3-matplotlib installed "
                            "(./setup.sh)?", out_dir, command));
}

CompareSummary runComparison(const CompareOptions& o) {
  const auto library = SpectrumLibrary::load(o.data_dir, WavelengthGrid::standard());
  Scene scene = loadScene(o.scene, library);
  if (o.width > 0) scene.width = o.width;
  if (o.height > 0) scene.height = o.height;
  const std::vector<std::string> renderers = o.renderers.empty() ? rendererNames() : o.renderers;
  for (const auto& r : renderers) makeRenderer(r);  // unknown names fail before any work
  checkRendererOptions(scene.renderer_options, o.scene + ": render.options");
  for (const auto& v : o.variants)  // a variant for an unknown backend would never run
    checkRendererOptions({{v.substr(0, v.find('.')), nlohmann::json::object()}},
                         fmt::format("--variant '{}'", v));
  const std::vector<std::string> models =
      o.models.empty() ? std::vector<std::string>{"rgb", "factor:3", "factor:4", "factor:6",
                                                  "factor:8", "spectral:31"}
                       : o.models;
  std::vector<RunSpec> specs;
  for (const auto& r : renderers)
    for (const auto& m : models) {
      specs.push_back({r, m, nlohmann::json::object()});
      for (const auto& v : o.variants) {
        const auto dot = v.find('.'), eq = v.find('=');
        if (dot == std::string::npos || eq == std::string::npos || eq < dot)
          throw Error(fmt::format("--variant '{}': expected BACKEND.KEY=VALUE", v));
        if (v.substr(0, dot) != r) continue;
        nlohmann::json value = nlohmann::json::parse(v.substr(eq + 1), nullptr, false);
        if (value.is_discarded()) value = v.substr(eq + 1);
        nlohmann::json options;
        options[r][v.substr(dot + 1, eq - dot - 1)] = value;
        specs.push_back({r, m, options});
      }
    }

  std::error_code ec;
  fs::create_directories(o.out_dir, ec);
  if (ec) throw Error(fmt::format("--out {}: cannot create the folder: {}", o.out_dir, ec.message()));

  Progress progress("compare", static_cast<int>(specs.size()) + 1, o.quiet);
  ComparisonSession session(scene, o.data_dir);
  progress.advance("reference");
  CompareSummary summary;
  summary.scene = o.scene;
  summary.reference_ms = session.referenceMs();
  for (const auto& spec : specs) {
    summary.runs.push_back(session.run(spec));
    progress.advance(spec.label());
  }

  // Images: the reference relit, then every run's relit image and error map.
  const int w = scene.width, h = scene.height;
  fs::create_directories(fs::path(o.out_dir) / "images" / "reference");
  {
    PostIlluminator post(session.referenceModel());
    if (scene.background) post.setBackground(session.referenceModel().project(*scene.background));
    for (const auto& ill : session.illuminations()) {
      std::vector<std::uint8_t> rgb(3 * session.reference().pixels());
      post.setLight(session.referenceModel().project(ill.spectrum));
      post.relightSrgb8(session.reference(), rgb);
      writeSrgbPng(rgb, w, h,
                   (fs::path(o.out_dir) / "images" / "reference" / (slug(ill.name) + ".png")).string());
    }
  }
  nlohmann::json report;
  report["scene"] = o.scene;
  report["width"] = w;
  report["height"] = h;
  report["reference"] = {{"renderer", "raycast"},
                         {"model", fmt::format("spectral:{}", WavelengthGrid::standard().count)},
                         {"render_ms", session.referenceMs()},
                         {"step_voxels", std::min(scene.step_voxels, 0.25)},
                         {"early_termination", 0}};
  nlohmann::json lights = nlohmann::json::array();
  for (const auto& ill : session.illuminations()) lights.push_back(ill.name);
  report["lights"] = lights;
  report["runs"] = nlohmann::json::array();
  bool all_pass = true;
  for (const auto& run : summary.runs) {
    const auto misses = checkTolerances(run, scene.tolerances);
    summary.exceedances.insert(summary.exceedances.end(), misses.begin(), misses.end());
    const std::string run_slug = slug(run.spec.label());
    fs::create_directories(fs::path(o.out_dir) / "images" / run_slug);
    fs::create_directories(fs::path(o.out_dir) / "maps" / run_slug);
    const auto tolerances = tolerancesFor(run.spec.renderer, scene.tolerances);
    double de_tolerance = 0.0;
    for (const auto& t : tolerances)
      if (t.metric == "de_mean") de_tolerance = t.limit;
    nlohmann::json jl = nlohmann::json::array();
    for (const auto& l : run.lights) {
      const std::string light_slug = slug(l.light);
      const std::string image = fmt::format("images/{}/{}.png", run_slug, light_slug);
      const std::string map = fmt::format("maps/{}/{}.pfm", run_slug, light_slug);
      writeSrgbPng(l.relit, w, h, (fs::path(o.out_dir) / image).string());
      writeFloatMap((fs::path(o.out_dir) / map).string(), w, h, l.error_map);
      bool pass = true;
      for (const auto& m : misses)
        if (m.light == l.light) pass = false;
      all_pass = all_pass && pass;
      jl.push_back({{"light", l.light},
                    {"de_mean", finiteOrNull(l.vs_reference.mean)},
                    {"de_p95", finiteOrNull(l.vs_reference.p95)},
                    {"de_max", finiteOrNull(l.vs_reference.max)},
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
    report["runs"].push_back({{"renderer", run.spec.renderer},
                              {"model", run.model_name},
                              {"model_asked", run.spec.model},
                              {"model_description", run.model_description},
                              {"model_choice", run.model_choice},
                              {"k", run.k},
                              {"options", run.spec.options},
                              {"label", run.spec.label()},
                              {"classify_ms", run.classify_ms},
                              {"render_ms", run.render_ms},
                              {"relight_ms", run.relight_ms},
                              {"render_fps", 1000.0 / std::max(run.render_ms, 1e-9)},
                              {"relight_fps", 1000.0 / std::max(run.relight_ms, 1e-9)},
                              {"tolerances", tol},
                              {"lights", jl}});
  }
  report["pass"] = all_pass;
  nlohmann::json misses = nlohmann::json::array();
  for (const auto& m : summary.exceedances) misses.push_back(m.str());
  report["exceedances"] = misses;
  writeJson((fs::path(o.out_dir) / "report.json").string(), report);
  if (o.charts) renderReportCharts(o.out_dir);
  return summary;
}

void printSummaryTable(const CompareSummary& s) {
  fmt::print("{}: reference raycast spectral:81 {:.0f} ms\n", s.scene, s.reference_ms);
  fmt::print("{:<40} {:>9} {:>11} {:>9} {:>9}  {}\n", "run", "ms/frame", "relight fps",
             "mean ΔE", "vs ray", "pass");
  for (const auto& run : s.runs) {
    double de = 0.0, vr = 0.0;
    for (const auto& l : run.lights) {
      de += l.vs_reference.mean / run.lights.size();
      if (l.vs_raycast) vr += l.vs_raycast->mean / run.lights.size();
    }
    bool pass = true;
    for (const auto& m : s.exceedances)
      if (m.run == run.spec.label()) pass = false;
    fmt::print("{:<40} {:>9.1f} {:>11.0f} {:>9.3f} {:>9.3f}  {}\n", run.spec.label(), run.render_ms,
               1000.0 / std::max(run.relight_ms, 1e-9), de, vr, pass ? "yes" : "NO");
  }
}

int runCompare(const CompareOptions& o) {
  const CompareSummary s = runComparison(o);
  if (!o.quiet) printSummaryTable(s);
  for (const auto& m : s.exceedances) fmt::print(stderr, "svr: tolerance: {}\n", m.str());
  if (!o.quiet) fmt::print("report: {}\n", (fs::path(o.out_dir) / "report.html").string());
  return s.exceedances.empty() ? 0 : 1;
}

}  // namespace svr
