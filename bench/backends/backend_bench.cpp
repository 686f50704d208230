// Every backend on issue 49's view corpus (bench/backends/view_corpus.h): each view rendered by
// every backend with rgb and factor:6, and measured against the raycaster with the same model
// (the algorithm's error alone, as the harness measures it), the figure
// per view the mean over its lights and mixes of the mean ΔE2000. Prints per backend and model
// the median, p95 and max over the views it rendered, the share within the harness's tolerance
// against the raycaster and within 1.0, the shares skipped (a camera the backend does not take) and failed, and the
// median frame time; --csv keeps every view's figures.
//
//   svr_backend_bench [--count 200] [--first 0] [--seed 40] [--renderers …] [--models rgb,factor:6]
//                     [--option BACKEND.KEY=VALUE …] [--csv FILE] [-q] [--print]
#include <fmt/format.h>
#include <unistd.h>

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>

#include "base/data_dir.h"
#include "base/error.h"
#include "bench/backends/backend_agreement.h"
#include "bench/backends/view_corpus.h"
#include "bench/models/corpus_bench.h"
#include "renderers/registry.h"

namespace svr {
namespace {

struct Options {
  int count = 200, first = 0;
  unsigned seed = SceneCorpus::kDefaultSeed;
  std::vector<std::string> renderers, models{"rgb", "factor:6"};
  std::vector<std::string> options;  // BACKEND.KEY=VALUE, as svr's --option
  std::string csv;
  bool quiet = false;
  bool print = false;  // print the views' JSON instead of running them
};

Options parse(int argc, char** argv) {
  Options o;
  CLI::App app{"every backend on issue 49's view corpus, against the raycaster", "svr_backend_bench"};
  app.add_option("--count", o.count, "views")->check(CLI::Range(0, 1000000));
  app.add_option("--first", o.first, "index of the first view")->check(CLI::Range(0, 1000000));
  app.add_option("--seed", o.seed, "corpus seed");
  app.add_option("--renderers", o.renderers, "backends (default: every one built but the raycaster)")
      ->delimiter(',');
  app.add_option("--models", o.models, "models, comma-separated")->delimiter(',');
  app.add_option("--option", o.options,
                 "BACKEND.KEY=VALUE over each view's render.options (repeatable), e.g. "
                 "shearwarp.slice_samples=1");
  app.add_option("--csv", o.csv, "every view's figures to this file");
  app.add_flag("-q,--quiet", o.quiet, "no progress");
  app.add_flag("--print", o.print, "print the views' JSON instead of running them");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    std::exit(app.exit(e));
  }
  if (o.renderers.empty())
    for (const auto& r : rendererNames())
      if (r != referenceRendererName()) o.renderers.push_back(r);
  for (const auto& r : o.renderers) backendEntry(r);  // unknown names fail before any work
  return o;
}

void printTable(const Options& o, const std::map<std::string, std::vector<Agreement>>& runs,
                const std::map<std::string, std::vector<double>>& raycast_ms) {
  fmt::print("{:<22} {:>7} {:>7} {:>7} {:>8} {:>7} {:>8} {:>7} {:>8}\n", "backend model", "median",
             "p95", "max", "in tol.", "≤1.0", "skipped", "failed", "ms");
  for (const auto& r : o.renderers)
    for (const auto& m : o.models) {
      const auto& outcomes = runs.at(r + " " + m);
      std::vector<double> de, ms;
      int tolerance = 0, within_1 = 0, skipped = 0, failed = 0;
      for (const auto& x : outcomes) {
        skipped += x.status == Agreement::Status::kSkipped;
        failed += x.status == Agreement::Status::kFailed;
        if (x.status != Agreement::Status::kRendered) continue;
        de.push_back(std::isfinite(x.vs_raycast) ? x.vs_raycast : INFINITY);
        ms.push_back(x.ms);
        tolerance += x.within_tolerance;
        within_1 += x.vs_raycast <= 1.0;
      }
      // Shares of every view: a skipped or failed view is neither within the tolerance nor 1.0.
      const double n = double(outcomes.size());
      auto pct = [&](int c) { return fmt::format("{:.0f}%", 100.0 * c / n); };
      fmt::print("{:<22} {:>7.2f} {:>7.2f} {:>7.2f} {:>8} {:>7} {:>8} {:>7} {:>8.1f}\n", r + " " + m,
                 quantile(de, 0.5), quantile(de, 0.95), quantile(de, 1.0), pct(tolerance),
                 pct(within_1), pct(skipped), pct(failed), quantile(ms, 0.5));
    }
  for (const auto& m : o.models)
    fmt::print("{:<22} {:>7} {:>7} {:>7} {:>8} {:>7} {:>8} {:>7} {:>8.1f}\n",
               std::string(referenceRendererName()) + " " + m, "", "", "", "", "", "", "",
               quantile(raycast_ms.at(m), 0.5));
}

int benchMain(int argc, char** argv) {
  const Options o = parse(argc, argv);
  const PrivateModelCache cache("svr_backend_bench");  // factor:6 trained afresh
  const std::string data = defaultDataDir();
  const auto spectra = std::make_shared<const SessionSpectra>(data);
  const SpectrumLibrary& library = spectra->library;
  const SceneCorpus scenes(data, library, o.seed, 96);
  const ViewCorpus views(scenes, library, o.seed);
  if (o.print) {
    for (int i = o.first; i < o.first + o.count; ++i) fmt::print("{}\n", views.sceneJson(i).dump());
    return 0;
  }
  std::ofstream csv;
  if (!o.csv.empty()) {
    csv.open(o.csv);
    if (!csv) throw Error(fmt::format("{}: cannot write the CSV", o.csv));
    csv << "view,camera,renderer,model,status,vs_raycast_mean,vs_raycast_p95,ms,note\n";
  }
  const bool progress = !o.quiet && isatty(STDERR_FILENO);
  std::map<std::string, std::vector<Agreement>> runs;
  std::map<std::string, std::vector<double>> raycast_ms;  // per model: the reference frames'
  for (int i = o.first; i < o.first + o.count; ++i) {
    if (progress) std::cerr << fmt::format("\rview {} of {}", i - o.first + 1, o.count);
    const Scene scene = views.scene(i);
    for (const auto& m : o.models) {
      const BackendFrame raycast = renderBackendFrame(spectra, scene, referenceRendererName(), m,
                                                        o.options);
      raycast_ms[m].push_back(raycast.ms);
      for (const auto& r : o.renderers) {
        const Agreement x = agreementWithRaycast(spectra, scene, raycast, r, m, o.options);
        runs[r + " " + m].push_back(x);
        if (!csv) continue;
        const char* status[] = {"rendered", "skipped", "failed"};
        csv << fmt::format("{},{},{},{},{},{},{},{},{}\n", i, csvField(views.describe(i)), r, m,
                           status[int(x.status)], x.vs_raycast, x.vs_raycast_p95, x.ms,
                           csvField(x.note));
      }
    }
  }
  if (progress) std::cerr << "\n";
  fmt::print("{} views of corpus seed {} from {}, each backend against raycast with the same "
             "model, mean ΔE2000 over the scene's lights\n", o.count, o.seed, o.first);
  if (o.count > 0) printTable(o, runs, raycast_ms);
  return 0;
}

}  // namespace
}  // namespace svr

int main(int argc, char** argv) {
  return svr::runCorpusBench("svr_backend_bench", svr::benchMain, argc, argv);
}
