// Colour models on issue 40's stress corpus (bench/models/scene_corpus.h): every corpus scene
// rendered small by the raycaster with rgb, factor:3…16 and auto, each against spectral:81 at
// the same sampling (ModelProbe: what differs is the colour model alone), the figure per scene
// the mean over its lights and mixes of the mean ΔE2000. Prints per model the median, p95, max,
// share within 1.0, share worse than rgb and, for factor:k, share worse than factor:(k−1), with
// the median training time; --csv keeps every scene's figures (docs/colour-models.md's chart).
//
//   svr_model_bench [--count 300] [--first 0] [--seed 40] [--size 48] [--models rgb,factor:6,…]
//                   [--csv FILE] [-q] [--print] [--held-out-view]
//
// factor:k is chosen on a small render of the scene (renderers/model/factor_choice.h); at
// --size 48 or below that render is the one measured here, so use a larger size, or
// --held-out-view (the scene from another side), to measure a choice on a picture it was not
// made on.
//
// Models are trained afresh (a private cache, so auto reuses the factor:k the bench just
// trained, as it would reuse the user's cache).
#include <fmt/format.h>
#include <unistd.h>

#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <numeric>

#include "base/data_dir.h"
#include "base/error.h"
#include "bench/models/corpus_bench.h"
#include "bench/models/scene_corpus.h"
#include "renderers/model/scene_model.h"
#include "spectral/colorimetry.h"

namespace svr {
namespace {

struct Options {
  int count = 300, first = 0, size = 48;
  unsigned seed = SceneCorpus::kDefaultSeed;
  std::vector<std::string> models;
  std::string csv;
  bool quiet = false;
  bool print = false;  // print the scenes' JSON instead of running them
  bool held_out_view = false;  // measure on another view than the one models are chosen on
};

struct Run {
  double error = NAN;  // mean over the scene's lights and mixes; inf: not finite
  double train_s = 0;
  std::string status = "ok", chosen;
};

Options parse(int argc, char** argv) {
  Options o;
  CLI::App app{"colour models on issue 40's stress corpus", "svr_model_bench"};
  app.add_option("--count", o.count, "scenes")->check(CLI::Range(0, 1000000));
  app.add_option("--first", o.first, "index of the first scene")->check(CLI::Range(0, 1000000));
  app.add_option("--seed", o.seed, "corpus seed");
  app.add_option("--size", o.size, "pixels on a side")->check(CLI::Range(1, 16384));
  app.add_option("--models", o.models, "models, comma-separated (default rgb, factor:3…16, auto)")
      ->delimiter(',');
  app.add_option("--csv", o.csv, "every scene's figures to this file");
  app.add_flag("-q,--quiet", o.quiet, "no progress");
  app.add_flag("--print", o.print, "print the scenes' JSON instead of running them");
  app.add_flag("--held-out-view", o.held_out_view,
               "measure each model on the scene seen from another side (azimuth + 135°, "
               "elevation + 30°), not on the view it was chosen on");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    std::exit(app.exit(e));
  }
  if (o.models.empty()) {
    o.models.push_back("rgb");
    for (int k = 3; k <= 16; ++k) o.models.push_back(fmt::format("factor:{}", k));
    o.models.push_back("auto");
  }
  return o;
}

Run runModel(const std::string& name, const Scene& scene, const Observer& observer,
             const ModelProbe& probe) {
  Run run;
  try {
    const auto t0 = std::chrono::steady_clock::now();
    const SceneModel m = makeSceneModel(name, scene, observer);
    run.train_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    run.chosen = m.model->name();
    const std::vector<double> each = probe.errors(*m.model);
    run.error = std::accumulate(each.begin(), each.end(), 0.0) / double(each.size());
    if (!std::isfinite(run.error)) run.status = "non-finite";
  } catch (const std::exception& e) {
    run.status = fmt::format("failed: {}", e.what());
    run.error = INFINITY;
  }
  return run;
}

// The table: per model over the scenes; comparisons with rgb and factor:(k−1) scene by scene.
void printTable(const Options& o, const std::map<std::string, std::vector<Run>>& runs) {
  fmt::print("{:<10} {:>7} {:>7} {:>7} {:>7} {:>7} {:>8} {:>8} {:>8} {:>8} {:>6}\n", "model",
             "median", "p95", "max", "≤1.0", ">rgb", ">rgb+.3", ">k-1", ">k-1+.5", "train s",
             "fail");
  const auto rgb_runs = runs.find("rgb");
  const std::vector<Run>* rgb = rgb_runs == runs.end() ? nullptr : &rgb_runs->second;
  for (const auto& name : o.models) {
    const auto& r = runs.at(name);
    std::vector<double> e, t;
    int within = 0, worse = 0, much_worse = 0, fail = 0, up = 0, much_up = 0;
    const std::vector<Run>* prev = nullptr;
    if (name.rfind("factor:", 0) == 0) {
      const std::string p = fmt::format("factor:{}", std::stoi(name.substr(7)) - 1);
      if (runs.count(p)) prev = &runs.at(p);
    }
    for (size_t i = 0; i < r.size(); ++i) {
      if (r[i].status != "ok") ++fail;
      e.push_back(r[i].error);
      t.push_back(r[i].train_s);
      within += r[i].error <= 1.0;
      if (rgb) {
        worse += r[i].error > (*rgb)[i].error + 0.05;
        much_worse += r[i].error > (*rgb)[i].error + 0.3;
      }
      if (prev) {
        up += r[i].error > (*prev)[i].error + 0.05;
        much_up += r[i].error > (*prev)[i].error + 0.5;
      }
    }
    const double n = double(r.size());
    auto pct = [&](int c) { return fmt::format("{:.1f}%", 100.0 * c / n); };
    fmt::print("{:<10} {:>7.3f} {:>7.3f} {:>7.2f} {:>7} {:>7} {:>8} {:>8} {:>8} {:>8.3f} {:>6}\n",
               name, quantile(e, 0.5), quantile(e, 0.95), quantile(e, 1.0), pct(within),
               rgb ? pct(worse) : "-", rgb ? pct(much_worse) : "-", prev ? pct(up) : "-",
               prev ? pct(much_up) : "-",
               quantile(t, 0.5), fail);
  }
}

int benchMain(int argc, char** argv) {
  const Options o = parse(argc, argv);
  const PrivateModelCache cache("svr_model_bench");
  const std::string data = defaultDataDir();
  const SpectrumLibrary library = SpectrumLibrary::load(data, WavelengthGrid::standard());
  const Observer observer = Observer::cie1931(data, WavelengthGrid::standard());
  const SceneCorpus corpus(data, library, o.seed, o.size);
  if (o.print) {
    for (int i = o.first; i < o.first + o.count; ++i) fmt::print("{}\n", corpus.sceneJson(i).dump());
    return 0;
  }
  const bool progress = !o.quiet && isatty(STDERR_FILENO);
  std::map<std::string, std::vector<Run>> runs;
  std::ofstream csv;
  if (!o.csv.empty()) {
    csv.open(o.csv);
    if (!csv) throw Error(fmt::format("{}: cannot write the CSV", o.csv));
    csv << "scene,model,error,train_s,status,chosen\n";
  }
  for (int i = o.first; i < o.first + o.count; ++i) {
    if (progress) std::cerr << fmt::format("\rscene {} of {}", i - o.first + 1, o.count);
    const Scene scene = corpus.scene(i);
    Scene measured = scene;
    if (o.held_out_view) {
      OrbitView view = orbitViewOf(scene.camera);
      view.azimuth += 135.0;
      view.elevation = std::clamp(view.elevation + 30.0, -80.0, 80.0);
      measured.camera = orbitCamera(scene.camera, view);
    }
    const ModelProbe probe(measured, observer);
    for (const auto& name : o.models) {
      const Run run = runModel(name, scene, observer, probe);
      runs[name].push_back(run);
      if (csv) {
        csv << fmt::format("{},{},{},{},{},{}\n", i, name, run.error, run.train_s,
                           csvField(run.status), run.chosen);
      }
    }
  }
  if (progress) std::cerr << "\n";
  fmt::print("{} scenes of corpus seed {} from {}, {}² raycast{}, mean ΔE2000 against "
             "spectral:81 at the same sampling\n", o.count, o.seed, o.first, o.size,
             o.held_out_view ? " from a held-out view" : "");
  if (o.count > 0) printTable(o, runs);
  return 0;
}

}  // namespace
}  // namespace svr

int main(int argc, char** argv) {
  return svr::runCorpusBench("svr_model_bench", svr::benchMain, argc, argv);
}
