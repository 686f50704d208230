#include "spectral/model_error.h"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "base/error.h"

namespace svr {

ErrorStats summarize(std::vector<double> values) {
  ErrorStats s;
  const auto bad = std::remove_if(values.begin(), values.end(),
                                  [](double v) { return !std::isfinite(v); });
  s.finite = bad == values.end();
  values.erase(bad, values.end());
  if (values.empty()) return s;
  double sum = 0.0;
  for (double v : values) sum += v;
  s.mean = sum / values.size();
  std::sort(values.begin(), values.end());
  const size_t rank = static_cast<size_t>(std::ceil(0.95 * values.size()));
  s.p95 = values[std::clamp<size_t>(rank, 1, values.size()) - 1];
  s.max = values.back();
  return s;
}

namespace {

// Coefficients t raised to the m-th power under the model's product.
Eigen::MatrixXd matrixPower(Eigen::MatrixXd base, int m) {
  Eigen::MatrixXd result = Eigen::MatrixXd::Identity(base.rows(), base.cols());
  while (m > 0) {
    if (m & 1) result = result * base;
    base = base * base;
    m >>= 1;
  }
  return result;
}

}  // namespace

std::vector<ModelErrorRow> evaluateModel(const ColourModel& model, const Observer& observer,
                                         const EvaluationSet& set) {
  if (set.absorbers.size() != set.reflectances.size())
    throw Error(fmt::format("evaluation set '{}': {} absorbers for {} reflectances", set.name,
                            set.absorbers.size(), set.reflectances.size()));
  const auto& cmf = observer.weightedCmf();
  const int nl = static_cast<int>(set.lights.size());
  const int nr = static_cast<int>(set.reflectances.size());
  const int k = model.channels();
  const bool diag = model.componentwise();

  // Componentwise models relight through their own light matrix (projected or full); linear:k
  // applies its interaction matrices to the light's coefficients.
  std::vector<Eigen::VectorXd> light_coeffs;
  std::vector<Eigen::MatrixXd> light_matrices;
  std::vector<Xyz> whites;
  for (const auto& l : set.lights) {
    light_coeffs.push_back(model.project(l));
    if (diag) light_matrices.push_back(model.lightMatrix(l));
    whites.push_back(observer.xyz(l));
  }
  std::vector<int> cases{0};
  for (int m : absorptionDepths()) cases.push_back(m);

  std::vector<ModelErrorRow> rows;
  for (int m : cases) {
    std::vector<double> de(static_cast<size_t>(nl) * nr);
#pragma omp parallel for schedule(dynamic, 8)
    for (int j = 0; j < nr; ++j) {
      const Eigen::VectorXd& refl = set.reflectances[j].values();
      const Eigen::VectorXd trans = set.absorbers[j].values().array().pow(m).matrix();
      // The light-free coefficients (componentwise), or the operator that takes the light's
      // coefficients to them (linear:k).
      Eigen::VectorXd c;
      Eigen::MatrixXd op;
      if (diag) {
        c = model.project(set.reflectances[j]);
        if (m > 0) {
          const Eigen::VectorXd t = model.projectTransmittance(set.absorbers[j]);
          for (int i = 0; i < k; ++i) c[i] *= std::pow(t[i], m);
        }
      } else {
        op = model.interaction(set.reflectances[j]);
        if (m > 0) op = op * matrixPower(model.interaction(set.absorbers[j]), m);
      }
      for (int l = 0; l < nl; ++l) {
        const Eigen::VectorXd& light = set.lights[l].values();
        // Exposure: both XYZ scaled so the light filtered by t^m has Y = 1.
        const double scale = m == 0 ? 1.0 : 1.0 / cmf.col(1).dot(light.cwiseProduct(trans));
        const Xyz exact = cmf.transpose() * light.cwiseProduct(refl).cwiseProduct(trans) * scale;
        const Xyz approx = (diag ? Xyz(light_matrices[l] * c)
                                 : Xyz(model.toXyz() * (op * light_coeffs[l]))) * scale;
        de[static_cast<size_t>(l) * nr + j] =
            deltaE2000(xyzToLab(exact, whites[l]), xyzToLab(approx, whites[l]));
      }
    }
    rows.push_back({toString(model.kind()), k, model.variant(),
                    toString(model.lightMatrixKind()), model.name(), set.name,
                    m == 0 ? "product" : fmt::format("absorb{}", m), summarize(std::move(de))});
  }
  return rows;
}

}  // namespace svr

namespace svr {

std::vector<std::string> standardLightNames() { return {"A", "D65", "F2", "F7", "F11", "LED-B1"}; }

std::vector<Spectrum> unitLights(const SpectrumLibrary& library, const Observer& observer,
                                 const std::vector<std::string>& names) {
  std::vector<Spectrum> lights;
  for (const auto& n : names) lights.push_back(observer.unitLuminance(library.get(n)));
  return lights;
}

EvaluationSet makeEvaluationSet(std::string name, std::vector<Spectrum> lights,
                                std::vector<Spectrum> reflectances, unsigned seed) {
  EvaluationSet set{std::move(name), std::move(lights), std::move(reflectances), {}};
  const auto partner = partnerIndices(static_cast<int>(set.reflectances.size()), seed);
  for (size_t j = 0; j < set.reflectances.size(); ++j)
    set.absorbers.push_back(weakAbsorber(set.reflectances[partner[j]]));
  return set;
}

StandardSets standardSets(const SpectrumLibrary& library, const Observer& observer,
                          const std::vector<std::string>& light_names) {
  const auto lights = unitLights(library, observer, light_names);
  const auto& munsell = library.munsellNames();
  const int n = static_cast<int>(munsell.size());
  auto order = shuffledIndices(n, 0);
  const int n_train = static_cast<int>(std::lround(n * 2.0 / 3.0));
  std::vector<int> train_idx(order.begin(), order.begin() + n_train);
  std::vector<int> test_idx(order.begin() + n_train, order.end());
  std::sort(train_idx.begin(), train_idx.end());
  std::sort(test_idx.begin(), test_idx.end());
  auto spectra = [&](const std::vector<int>& idx) {
    std::vector<Spectrum> out;
    for (int i : idx) out.push_back(library.get(munsell[i]));
    return out;
  };
  std::vector<Spectrum> cc;
  for (const auto& name : library.colorCheckerNames()) cc.push_back(library.get(name));

  StandardSets sets;
  sets.evaluation.push_back(makeEvaluationSet("train", lights, spectra(train_idx), 1));
  sets.evaluation.push_back(makeEvaluationSet("test", lights, spectra(test_idx), 1));
  sets.evaluation.push_back(makeEvaluationSet("colorchecker", lights, cc, 1));
  const auto& train = sets.evaluation.front();
  sets.training = TrainingSet{lights, train.reflectances, train.absorbers, {16, 64, 256}};
  return sets;
}

}  // namespace svr
