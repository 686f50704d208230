#pragma once
// Accuracy of a colour model against the exact spectral product (design.md §4): ΔE2000 between
// the model's and the exact XYZ of light × reflectance (the "product" case) and of
// light × reflectance × t^m (the "absorbM" cases, exposure-normalised so the light filtered by
// t^m has Y = 1). Lab is taken against the light's own white (Y = 1).

#include <string>
#include <vector>

#include "spectral/colorimetry.h"
#include "spectral/colour_model.h"

namespace svr {

struct ErrorStats {
  double mean = 0.0, p95 = 0.0, max = 0.0;
  bool finite = true;  // false when any difference is NaN/Inf; the numbers then cover the finite
};
// Mean, 95th percentile (nearest rank) and maximum; flags and skips non-finite values.
ErrorStats summarize(std::vector<double> values);

struct EvaluationSet {
  std::string name;                    // "train", "test", "colorchecker", "palette", …
  std::vector<Spectrum> lights;        // unit luminance
  std::vector<Spectrum> reflectances;
  std::vector<Spectrum> absorbers;     // paired with reflectances
};

struct ModelErrorRow {
  std::string model;  // "factor"
  int k = 0;
  std::string variant;
  std::string light_matrix;  // "full" or "projected"
  std::string name;          // the model's name: "factor:6", "factor:6/projected", …
  std::string set;
  std::string evaluation_case;  // "product", "absorb4", "absorb16", "absorb64", "absorb256"
  ErrorStats stats;
};

inline const std::vector<int>& absorptionDepths() {
  static const std::vector<int> depths{4, 16, 64, 256};
  return depths;
}

// Every case (product and each depth) of one model on one set.
std::vector<ModelErrorRow> evaluateModel(const ColourModel& model, const Observer& observer,
                                         const EvaluationSet& set);

}  // namespace svr

#include "spectral/factor_training.h"
#include "spectral/spectrum_library.h"

namespace svr {

// The standard benchmark of design.md §4: lights (default A, D65, F2, F7, F11, LED-B1, each at unit
// luminance); Munsell split 2/3 train, 1/3 held-out test (seed 0); ColorChecker as a second
// test set; deep absorbers t = 0.97 + 0.03·r of a partner chip (seed 1) in each set.
struct StandardSets {
  TrainingSet training;
  std::vector<EvaluationSet> evaluation;  // train, test, colorchecker
};
std::vector<std::string> standardLightNames();
StandardSets standardSets(const SpectrumLibrary& library, const Observer& observer,
                          const std::vector<std::string>& light_names);
// An evaluation set over given reflectances, with partner absorbers drawn with `seed`.
EvaluationSet makeEvaluationSet(std::string name, std::vector<Spectrum> lights,
                                std::vector<Spectrum> reflectances, unsigned seed);
// Unit-luminance copies of library lights.
std::vector<Spectrum> unitLights(const SpectrumLibrary& library, const Observer& observer,
                                 const std::vector<std::string>& names);

}  // namespace svr
