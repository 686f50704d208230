#include "harness/model_error_command.h"

#include <CLI/CLI.hpp>
#include <memory>
#include <fmt/format.h>

#include <chrono>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>

#include "harness/command.h"
#include "harness/progress.h"
#include "base/atomic_file.h"
#include "spectral/colorimetry.h"
#include "spectral/componentwise_model.h"
#include "base/error.h"
#include "spectral/factor_training.h"
#include "spectral/model_error.h"
#include "spectral/palette.h"
#include "spectral/spectrum_library.h"

namespace svr {
namespace {

struct ModelEntry {
  std::unique_ptr<ColourModel> model;
  std::string label;  // "factor:6 refined"
  FactorTrainingReport training;
  double train_seconds = 0.0;
};

std::string label(const ColourModel& m) {
  return m.variant().empty() ? m.name() : fmt::format("{} {}", m.name(), m.variant());
}

nlohmann::json statsJson(const ModelErrorRow& r) {
  auto num = [&](double v) { return r.stats.finite ? nlohmann::json(v) : nlohmann::json(); };
  return {{"model", r.model},        {"k", r.k},           {"variant", r.variant},
          {"light_matrix", r.light_matrix},
          {"set", r.set},            {"case", r.evaluation_case},
          {"mean", num(r.stats.mean)}, {"p95", num(r.stats.p95)}, {"max", num(r.stats.max)},
          {"finite", r.stats.finite}};
}

void printTable(const std::string& set, const std::vector<ModelErrorRow>& rows,
                const std::vector<std::string>& order) {
  fmt::print("\nset {}: mean ΔE2000 (p95 and max for the single product)\n", set);
  fmt::print("{:<28} {:>8} {:>8} {:>8} {:>9} {:>9} {:>9} {:>9}  {}\n", "model", "product", "p95",
             "max", "absorb4", "absorb16", "absorb64", "absorb256", "finite");
  std::map<std::string, std::map<std::string, const ModelErrorRow*>> by_model;
  for (const auto& r : rows)
    if (r.set == set)
      by_model[r.name + (r.variant.empty() ? "" : " " + r.variant)]
              [r.evaluation_case] = &r;
  auto cell = [](const ModelErrorRow* r, double ErrorStats::*field) {
    if (!r) return std::string("-");
    return fmt::format("{:.3f}", r->stats.*field);
  };
  for (const auto& name : order) {
    auto it = by_model.find(name);
    if (it == by_model.end()) continue;
    auto& c = it->second;
    bool finite = true;
    for (auto& [k, r] : c) finite = finite && r->stats.finite;
    fmt::print("{:<28} {:>8} {:>8} {:>8} {:>9} {:>9} {:>9} {:>9}  {}\n", name,
               cell(c["product"], &ErrorStats::mean), cell(c["product"], &ErrorStats::p95),
               cell(c["product"], &ErrorStats::max), cell(c["absorb4"], &ErrorStats::mean),
               cell(c["absorb16"], &ErrorStats::mean), cell(c["absorb64"], &ErrorStats::mean),
               cell(c["absorb256"], &ErrorStats::mean), finite ? "yes" : "NO");
  }
}

// Smallest k of the refined factor model whose product and absorb256 means are within target,
// for each light matrix.
void printSmallestK(const std::string& set, const std::vector<ModelErrorRow>& rows) {
  for (const char* matrix : {"full", "projected"}) {
    for (double target : {1.0, 0.3}) {
      int best = -1;
      std::map<int, double> worst;
      for (const auto& r : rows)
        if (r.set == set && r.model == "factor" && r.variant == "refined" &&
            r.light_matrix == matrix &&
            (r.evaluation_case == "product" || r.evaluation_case == "absorb256"))
          worst[r.k] = std::max(worst[r.k], r.stats.finite ? r.stats.mean : INFINITY);
      for (auto& [k, v] : worst)
        if (v <= target) {
          best = k;
          break;
        }
      if (best > 0)
        fmt::print("set {}: smallest factor k with mean ΔE2000 ≤ {} (single and deep), {} light "
                   "matrices: {}\n", set, target, matrix, best);
      else
        fmt::print("set {}: no factor k in range reaches mean ΔE2000 ≤ {}, {} light matrices\n",
                   set, target, matrix);
    }
  }
}

}  // namespace

namespace {

// What the models are trained on and evaluated against: a palette's lights × materials (with
// its absorbers), or the standard Munsell split under the named lights, or those lights over
// the reflectances asked for.
struct ModelErrorSets {
  TrainingSet training;
  std::vector<EvaluationSet> evaluation;
};

ModelErrorSets modelErrorSets(const ModelErrorOptions& o, const SpectrumLibrary& library,
                              const Observer& observer, const std::vector<std::string>& light_names) {
  TrainingSet training;
  std::vector<EvaluationSet> sets;
  if (!o.palette.empty()) {
    const Palette palette = loadPalette(o.palette, library);
    std::vector<Spectrum> lights, materials;
    for (const auto& l : palette.lights) lights.push_back(observer.unitLuminance(l.spectrum));
    for (const auto& m : palette.materials) materials.push_back(m.spectrum);
    sets.push_back(makeEvaluationSet("palette", lights, materials, 1));
    training = TrainingSet{lights, materials, sets.back().absorbers, {16, 64, 256}};
  } else {
    auto standard = standardSets(library, observer, light_names);
    training = standard.training;
    if (o.reflectances.empty()) {
      sets = std::move(standard.evaluation);
    } else {
      std::vector<Spectrum> refl;
      for (const auto& name : o.reflectances) {
        const std::vector<std::string>* family =
            name == "munsell" ? &library.munsellNames()
                              : (name == "colorchecker" ? &library.colorCheckerNames() : nullptr);
        if (family)
          for (const auto& n : *family) refl.push_back(library.get(n));
        else
          refl.push_back(library.get(name));
      }
      sets.push_back(makeEvaluationSet("reflectances", training.lights, refl, 1));
    }
  }
  return {std::move(training), std::move(sets)};
}

// report.json of the run: every row's statistics, each model's training figures, the lights.
void writeModelErrorJson(const std::string& path, const std::vector<ModelErrorRow>& rows,
                         const std::vector<ModelEntry>& models,
                         const std::vector<std::string>& light_names) {
  nlohmann::json out;
  out["rows"] = nlohmann::json::array();
  for (const auto& r : rows) out["rows"].push_back(statsJson(r));
  nlohmann::json training_info = nlohmann::json::array();
  for (const auto& m : models)
    training_info.push_back({{"model", m.model->name()},
                             {"variant", m.model->variant()},
                             {"train_seconds", m.train_seconds},
                             {"start", m.training.start},
                             {"objective_start", std::isfinite(m.training.objective_start)
                                                     ? nlohmann::json(m.training.objective_start)
                                                     : nlohmann::json()},
                             {"objective_final", m.training.objective_final},
                             {"iterations", m.training.iterations}});
  out["training"] = training_info;
  out["lights"] = light_names;
  writeTextAtomically(path, out.dump(1) + "\n");
  fmt::print("wrote {}\n", path);
}

}  // namespace

int runModelError(const ModelErrorOptions& o) {
  if (o.k_min < 3 || o.k_max > 16 || o.k_min > o.k_max)
    throw Error(fmt::format("model-error: --k range {}..{} must lie within 3..16", o.k_min, o.k_max));
  const WavelengthGrid grid = WavelengthGrid::standard();
  const auto library = SpectrumLibrary::load(o.data_dir, grid);
  const auto observer = Observer::cie1931(o.data_dir, grid);
  const auto light_names = o.lights.empty() ? standardLightNames() : o.lights;

  auto [training, sets] = modelErrorSets(o, library, observer, light_names);

  std::vector<ModelEntry> models;
  const int nk = o.k_max - o.k_min + 1;
  const LightMatrixKind matrices[] = {LightMatrixKind::kFull, LightMatrixKind::kProjected};
  Progress progress("training", nk * (o.contrast ? 7 : 5) + 2, o.quiet);
  auto timed = [&](auto&& make) {
    const auto t0 = std::chrono::steady_clock::now();
    ModelEntry e = make();
    e.train_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    e.label = label(*e.model);
    progress.advance(e.label);
    return e;
  };
  models.push_back(timed([&] { return ModelEntry{makeRgbModel(observer), {}, {}, 0.0}; }));
  models.push_back(timed([&] { return ModelEntry{makeSpectralModel(observer, grid.count), {}, {}, 0.0}; }));
  // Both light matrices of every model with a spectral basis (issue 19: charted side by side).
  for (auto matrix : matrices)
    for (int k = o.k_min; k <= o.k_max; ++k)
      models.push_back(timed([&] {
        return ModelEntry{makeSpectralModel(observer, k, matrix), {}, {}, 0.0};
      }));
  for (int k = o.k_min; k <= o.k_max; ++k)
    models.push_back(timed([&] { return ModelEntry{trainLinearModel(observer, training, k), {}, {}, 0.0}; }));
  // Unsharpened PCA is always shown as the contrast sharpening must beat; closed-form
  // sharpening only on request (it is unstable: finite at some k, not at others).
  std::vector<FactorVariant> variants{FactorVariant::kPca, FactorVariant::kRefined};
  if (o.contrast) variants.insert(variants.begin() + 1, FactorVariant::kSharp);
  for (auto matrix : matrices)
    for (auto variant : variants)
      for (int k = o.k_min; k <= o.k_max; ++k)
        models.push_back(timed([&] {
          ModelEntry e;
          e.model = trainFactorModel(observer, training, k, variant, matrix, &e.training);
          return e;
        }));

  std::vector<ModelErrorRow> rows;
  {
    Progress eval("evaluating", static_cast<int>(models.size()), o.quiet);
    for (const auto& m : models) {
      for (const auto& set : sets) {
        auto r = evaluateModel(*m.model, observer, set);
        rows.insert(rows.end(), r.begin(), r.end());
      }
      eval.advance(m.label);
    }
  }

  fmt::print("Colour-model accuracy against the exact {}-sample spectral product\n", grid.count);
  fmt::print("lights: {}; {} training signals\n", fmt::format("{}", fmt::join(
      o.palette.empty() ? light_names : std::vector<std::string>{"(palette)"}, ", ")),
      training.lights.size() * training.reflectances.size());
  std::vector<std::string> order;
  for (const auto& m : models) order.push_back(m.label);
  for (const auto& set : sets) printTable(set.name, rows, order);
  fmt::print("\n");
  for (const auto& set : sets) printSmallestK(set.name, rows);
  fmt::print("\nfactor training (refined): start, objective before → after, LM iterations, s\n");
  for (const auto& m : models)
    if (m.model->variant() == "refined")
      fmt::print("  {:<20} {:<8} {:10.4g} → {:10.4g} {:3d} it {:6.2f} s  min|w| {:.3g}\n", m.label,
                 m.training.start, m.training.objective_start, m.training.objective_final,
                 m.training.iterations, m.train_seconds, m.training.white_min_abs);

  if (!o.json_path.empty()) writeModelErrorJson(o.json_path, rows, models, light_names);
  return 0;
}

namespace commands {

CommandEntry model_error() {
  return {"model-error", "accuracy of every colour model against the exact spectral product",
          [](CLI::App& sub, CommandContext& context) {
            auto o = std::make_shared<ModelErrorOptions>();
            sub.add_option("--lights", o->lights,
                           "library light names (default A D65 F2 F7 F11 LED-B1)")
                ->delimiter(',');
            sub.add_option("--reflectances", o->reflectances,
                           "reflectance names, or 'munsell' / 'colorchecker', as the test set")
                ->delimiter(',');
            sub.add_option("--palette", o->palette,
                           "palette JSON (data/palettes/): train and test on its own lights × materials")
                ->check(CLI::ExistingFile);
            sub.add_option("--json", o->json_path, "write every row as JSON to this file");
            sub.add_option("--kmin", o->k_min, "smallest k")->capture_default_str();
            sub.add_option("--kmax", o->k_max, "largest k")->capture_default_str();
            sub.add_flag("--contrast", o->contrast,
                         "also show closed-form (unrefined) sharpening, which is unstable");
            sub.add_flag("-q,--quiet", o->quiet, "no progress bar");
            runOnParse(sub, context, o, &runModelError);
          }};
}

}  // namespace commands

}  // namespace svr
