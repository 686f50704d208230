#include "spectral/model_error.h"

#include <gtest/gtest.h>

#include <map>

#include "spectral/componentwise_model.h"
#include "spectral/factor_training.h"
#include "tests/spectral/test_data.h"

namespace svr {
namespace {

TEST(Summarize, MeanNearestRankP95AndMax) {
  std::vector<double> v;
  for (int i = 1; i <= 100; ++i) v.push_back(i);
  const ErrorStats s = summarize(v);
  EXPECT_DOUBLE_EQ(s.mean, 50.5);
  EXPECT_DOUBLE_EQ(s.p95, 95.0);
  EXPECT_DOUBLE_EQ(s.max, 100.0);
  EXPECT_TRUE(s.finite);
  EXPECT_FALSE(summarize({1.0, NAN, 3.0}).finite);
  EXPECT_DOUBLE_EQ(summarize({1.0, INFINITY, 3.0}).mean, 2.0);
}

TEST(StandardSets, SplitIsTwoThirdsOneThirdAndDisjoint) {
  const auto sets = standardSets(test::library(), test::observer(), standardLightNames());
  ASSERT_EQ(sets.evaluation.size(), 3u);
  EXPECT_EQ(sets.evaluation[0].reflectances.size(), 846u);
  EXPECT_EQ(sets.evaluation[1].reflectances.size(), 423u);
  EXPECT_EQ(sets.evaluation[2].reflectances.size(), 24u);
  EXPECT_EQ(sets.training.lights.size(), 6u);
  // No held-out chip is in the training set.
  for (const auto& t : sets.evaluation[1].reflectances)
    for (const auto& r : sets.training.reflectances) ASSERT_FALSE(t.values() == r.values());
}

TEST(ModelError, ExactSpectralModelHasZeroErrorInEveryCase) {
  const auto exact = makeSpectralModel(test::observer(), 81);
  const auto& t = test::smallTrainingSet();
  const EvaluationSet set{"small", t.lights, t.reflectances, t.absorbers};
  const auto rows = evaluateModel(*exact, test::observer(), set);
  ASSERT_EQ(rows.size(), 5u);
  for (const auto& r : rows) {
    EXPECT_LT(r.stats.max, 1e-6) << r.evaluation_case;
    EXPECT_TRUE(r.stats.finite);
  }
}

// The acceptance figures of the spectral-core issue on the standard held-out set (the numpy
// prototype's figures are 1.22 / 1.96 at k = 8 and 0.65 / 0.97 at k = 9).
TEST(ModelError, RefinedFactorModelBeatsRgbAndReachesOneAtNine) {
  const auto sets = standardSets(test::library(), test::observer(), standardLightNames());
  const EvaluationSet& test_set = sets.evaluation[1];
  // The unsharpened PCA contrast overflows under t^256 (its first coefficient of t is ≈ 8.7);
  // every other model must stay finite.
  auto means = [&](const ColourModel& m) {
    std::map<std::string, double> out;
    for (const auto& r : evaluateModel(m, test::observer(), test_set)) {
      if (m.variant() != "pca") {
        EXPECT_TRUE(r.stats.finite) << m.name() << " " << r.evaluation_case;
      }
      out[r.evaluation_case] = r.stats.mean;
    }
    return out;
  };
  const auto rgb = means(*makeRgbModel(test::observer()));
  EXPECT_NEAR(rgb.at("product"), 2.5, 0.2);  // prototype: 2.60 (its own test split)
  const auto train = [&](int k, FactorVariant variant, LightMatrixKind matrix) {
    return means(*trainFactorModel(test::observer(), sets.training, k, variant, matrix));
  };
  const auto k8 = train(8, FactorVariant::kRefined, LightMatrixKind::kProjected);
  EXPECT_LT(k8.at("product"), rgb.at("product"));
  EXPECT_LT(k8.at("absorb256"), rgb.at("absorb256"));
  const auto k9 = train(9, FactorVariant::kRefined, LightMatrixKind::kProjected);
  EXPECT_LE(k9.at("product"), 1.0);
  EXPECT_LE(k9.at("absorb256"), 1.0);
  const auto pca9 = train(9, FactorVariant::kPca, LightMatrixKind::kProjected);
  EXPECT_LT(k9.at("product"), pca9.at("product"));
}

// Issue 19, goal 5: with full-spectrum light matrices a generic basis reaches mean ≤ 1 on the
// held-out single and deepest products at k ≤ 8 (measured 0.37 / 0.83 at k = 6), which the
// projected model needs k = 9 for.
TEST(ModelError, FullLightMatricesReachOneAtSixOnTheGenericSet) {
  const auto sets = standardSets(test::library(), test::observer(), standardLightNames());
  const EvaluationSet& test_set = sets.evaluation[1];
  const auto model = trainFactorModel(test::observer(), sets.training, 6, FactorVariant::kRefined,
                                      LightMatrixKind::kFull);
  for (const auto& r : evaluateModel(*model, test::observer(), test_set)) {
    EXPECT_TRUE(r.stats.finite) << r.evaluation_case;
    EXPECT_LE(r.stats.mean, 1.0) << r.evaluation_case;
  }
}

}  // namespace
}  // namespace svr
