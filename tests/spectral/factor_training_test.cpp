#include "spectral/factor_training.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "base/error.h"
#include "spectral/componentwise_model.h"
#include "spectral/model_error.h"
#include "tests/spectral/test_data.h"

namespace svr {
namespace {

double meanError(const ColourModel& m, const EvaluationSet& set, const std::string& which) {
  for (const auto& r : evaluateModel(m, test::observer(), set))
    if (r.evaluation_case == which) return r.stats.finite ? r.stats.mean : INFINITY;
  return INFINITY;
}

EvaluationSet trainingAsEvaluation() {
  const auto& t = test::smallTrainingSet();
  return {"train", t.lights, t.reflectances, t.absorbers};
}

constexpr LightMatrixKind kBothMatrices[] = {LightMatrixKind::kFull, LightMatrixKind::kProjected};

TEST(FactorTraining, ReproducesTrainingProductsBetterAsKGrows) {
  const auto set = trainingAsEvaluation();
  for (auto matrix : kBothMatrices) {
    double previous = INFINITY;
    for (int k : {3, 5, 7, 9}) {
      const auto m = trainFactorModel(test::observer(), test::smallTrainingSet(), k,
                                      FactorVariant::kRefined, matrix);
      const double e = meanError(*m, set, "product");
      EXPECT_LT(e, previous) << m->name();
      previous = e;
    }
    EXPECT_LT(previous, 1.0);  // k = 9 on its own training set
  }
}

TEST(FactorTraining, RefinementLowersTheObjectiveAndReportsIt) {
  for (auto matrix : kBothMatrices) {
    FactorTrainingReport report;
    trainFactorModel(test::observer(), test::smallTrainingSet(), 6, FactorVariant::kRefined,
                     matrix, &report);
    EXPECT_GT(report.iterations, 0);
    EXPECT_LT(report.objective_final, report.objective_start);
    EXPECT_EQ(report.borders_nm.size(), 5u);
    EXPECT_FALSE(report.start.empty());
  }
}

// Projected, sharpening changes single products; full, a single product depends on the span
// alone (C·diag(L)·B·P is T-free), so sharpening shows in the deep products.
TEST(FactorTraining, SharpenedBeatsUnsharpenedPca) {
  const auto set = trainingAsEvaluation();
  for (auto matrix : kBothMatrices) {
    const auto pca = trainFactorModel(test::observer(), test::smallTrainingSet(), 6,
                                      FactorVariant::kPca, matrix);
    const auto refined = trainFactorModel(test::observer(), test::smallTrainingSet(), 6,
                                          FactorVariant::kRefined, matrix);
    if (matrix == LightMatrixKind::kProjected) {
      EXPECT_LT(meanError(*refined, set, "product"), meanError(*pca, set, "product"));
    } else {
      EXPECT_NEAR(meanError(*refined, set, "product"), meanError(*pca, set, "product"), 1e-6);
      EXPECT_LT(meanError(*refined, set, "absorb256"), meanError(*pca, set, "absorb256"));
    }
  }
}

// The full-spectrum span: orthonormal, P·B = I, and what it reconstructs is weighed by the
// lights: at k = 6 the training reflectances come back at mean ΔE2000 < 0.5 under its lights,
// less than a third of what the colour signals' span gives them, though a spectrum itself may
// differ where the lights and the eye see little.
TEST(FactorTraining, LightWeightedSpanReconstructsWhatTheLightsShow) {
  const auto& set = test::smallTrainingSet();
  const StartingSpan span = lightWeightedSpan(test::observer(), set, 6);
  EXPECT_TRUE((span.basis.transpose() * span.basis).isIdentity(1e-10));
  EXPECT_TRUE((span.projection * span.basis).isIdentity(1e-9));
  const Eigen::MatrixXd signals = principalBasis(set, 6);
  auto meanReconstruction = [&](const Eigen::MatrixXd& reconstruct) {
    double sum = 0;
    int n = 0;
    for (const auto& light : set.lights)
      for (const auto& r : set.reflectances) {
        const Spectrum back(r.grid(), reconstruct * r.values());
        const Xyz white = test::observer().xyz(light);
        sum += deltaE2000(xyzToLab(test::observer().xyz(light * r), white),
                          xyzToLab(test::observer().xyz(light * back), white));
        ++n;
      }
    return sum / n;
  };
  const double weighted = meanReconstruction(span.basis * span.projection);
  EXPECT_LT(weighted, 0.5);
  EXPECT_LT(3 * weighted, meanReconstruction(signals * signals.transpose()));
}

TEST(FactorTraining, PrincipalBasisIsOrthonormalWithPositiveMean) {
  const Eigen::MatrixXd b = principalBasis(test::smallTrainingSet(), 8);
  EXPECT_TRUE((b.transpose() * b).isIdentity(1e-10));
  for (int i = 0; i < 8; ++i) EXPECT_GT(b.col(i).sum(), 0.0);
}

// Every model a renderer may use, k = 3..10, held-out chips: the coefficients of t^256 stay
// finite and bounded (no blow-up through a near-zero white coefficient), and so does the
// relit XYZ.
// rgb as a factor:k candidate relights every product, deep ones included, as rgb does: the
// split channels carry each coefficient in halves.
TEST(FactorTraining, RgbInKChannelsRelightsAsRgb) {
  const auto rgb = makeRgbModel(test::observer());
  const auto& set = test::smallTrainingSet();
  for (int k = 3; k <= 8; ++k) {
    const auto m = rgbFactorModel(test::observer(), k);
    ASSERT_EQ(m->channels(), k);
    EXPECT_EQ(m->name(), fmt::format("factor:{}/projected", k));
    for (const Spectrum& light : set.lights)
      for (size_t j = 0; j < set.reflectances.size(); ++j)
        for (int depth : {0, 16}) {
          auto relit = [&](const ComponentwiseModel& model) {
            Eigen::VectorXd c = model.project(set.reflectances[j]);
            if (!set.absorbers.empty())
              c = c.cwiseProduct(
                  model.project(set.absorbers[j]).array().pow(depth).matrix());
            return Eigen::Vector3d(model.lightMatrix(light) * c);
          };
          const Eigen::Vector3d want = relit(*rgb);
          EXPECT_LE((relit(*m) - want).norm(), 1e-12 * (1 + want.norm())) << k;
        }
  }
  EXPECT_THROW(rgbFactorModel(test::observer(), 2), Error);
}

TEST(ColourModels, StayFiniteAndBoundedUnderDeepAbsorption) {
  std::vector<Spectrum> held_out;
  const auto& names = test::library().munsellNames();
  for (size_t i = 3; i < names.size(); i += 11) held_out.push_back(test::library().get(names[i]));
  const auto set = makeEvaluationSet(
      "held-out", unitLights(test::library(), test::observer(), standardLightNames()), held_out, 5);
  std::vector<std::unique_ptr<ColourModel>> models;
  models.push_back(makeRgbModel(test::observer()));
  for (int k = 3; k <= 10; ++k) {
    models.push_back(makeSpectralModel(test::observer(), k));
    models.push_back(trainLinearModel(test::observer(), test::smallTrainingSet(), k));
    for (auto matrix : kBothMatrices)
      models.push_back(trainFactorModel(test::observer(), test::smallTrainingSet(), k,
                                        FactorVariant::kRefined, matrix));
  }
  for (const auto& m : models) {
    SCOPED_TRACE(m->name() + " " + m->variant());
    for (size_t j = 0; j < set.absorbers.size(); ++j) {
      if (m->componentwise()) {
        const Eigen::ArrayXd t = m->project(set.absorbers[j]).array().pow(256);
        ASSERT_TRUE(t.allFinite());
        ASSERT_LE(t.abs().maxCoeff(), 1.5);  // true t^256 lies in [0, 1]
      }
    }
    for (const auto& row : evaluateModel(*m, test::observer(), set)) {
      EXPECT_TRUE(row.stats.finite) << row.evaluation_case;
      EXPECT_LT(row.stats.mean, 30.0) << row.evaluation_case;
    }
  }
}

TEST(Sampling, PartnersAreNeverThemselvesAndShuffleIsAPermutation) {
  const auto p = partnerIndices(100, 1);
  for (int i = 0; i < 100; ++i) {
    EXPECT_NE(p[i], i);
    EXPECT_GE(p[i], 0);
    EXPECT_LT(p[i], 100);
  }
  auto s = shuffledIndices(50, 0);
  EXPECT_EQ(s, shuffledIndices(50, 0));  // deterministic
  std::sort(s.begin(), s.end());
  for (int i = 0; i < 50; ++i) EXPECT_EQ(s[i], i);
}

}  // namespace
}  // namespace svr
