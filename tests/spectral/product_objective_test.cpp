#include "spectral/product_objective.h"

#include <gtest/gtest.h>

#include <random>

#include "tests/spectral/test_data.h"

namespace svr {
namespace {

// A palette with strong absorbers (another chip's reflectance as the per-step transmittance) at
// shallow and deep steps: some coefficients of P·t fall outside [0, 1] and are clamped, some
// deep products are too dark to count, and some reflectance coefficients pass the hinge bounds.
TrainingSet strongAbsorberSet() {
  const auto& names = test::library().munsellNames();
  TrainingSet set;
  for (const char* light : {"D65", "A", "F11"})
    set.lights.push_back(test::observer().unitLuminance(test::library().get(light)));
  for (size_t i = 0; i < 24; ++i) {
    set.reflectances.push_back(test::library().get(names[i * 53 % names.size()]));
    set.absorbers.push_back(test::library().get(names[(i * 97 + 11) % names.size()]));
  }
  set.depths = {1, 4, 16, 64};
  return set;
}

Eigen::VectorXd residuals(const ProductObjective& objective, const Eigen::VectorXd& theta) {
  Eigen::VectorXd r;
  EXPECT_TRUE(objective.evaluate(theta, r));
  return r;
}

// Central differences of the residuals, step h in every parameter.
Eigen::MatrixXd numericJacobian(const ProductObjective& objective, const Eigen::VectorXd& theta) {
  Eigen::MatrixXd jac(objective.residuals(), objective.parameters());
  for (int p = 0; p < objective.parameters(); ++p) {
    const double h = 1e-6;
    Eigen::VectorXd plus = theta, minus = theta;
    plus[p] += h;
    minus[p] -= h;
    jac.col(p) = (residuals(objective, plus) - residuals(objective, minus)) / (2 * h);
  }
  return jac;
}

void expectExactJacobian(const TrainingSet& set, LightMatrixKind matrix, int k) {
  StartingSpan span;
  if (matrix == LightMatrixKind::kFull) {
    span = lightWeightedSpan(test::observer(), set, k);
  } else {
    span.basis = principalBasis(set, k);
    span.projection = span.basis.transpose();
  }
  const ProductObjective objective(test::observer(), set, span.basis, span.projection, matrix);
  // A sharpening-like T: identity plus a fixed random mixture, well away from singular.
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 0.3);
  Eigen::MatrixXd t = Eigen::MatrixXd::Identity(k, k);
  for (Eigen::Index i = 0; i < t.size(); ++i) t(i) += noise(rng);
  const Eigen::VectorXd theta = Eigen::Map<const Eigen::VectorXd>(t.data(), t.size());
  Eigen::VectorXd r;
  Eigen::MatrixXd jac;
  ASSERT_TRUE(objective.evaluate(theta, r, &jac));
  ASSERT_EQ(jac.rows(), objective.residuals());
  ASSERT_EQ(jac.cols(), k * k);
  EXPECT_EQ(r, residuals(objective, theta));  // the same residuals with or without the Jacobian
  const Eigen::MatrixXd numeric = numericJacobian(objective, theta);
  // Residual by residual: a kink (clamp, hinge, CIELAB's cbrt/linear join) inside ±h changes a
  // few rows; the rest agree to the differences' truncation error.
  int off = 0;
  for (Eigen::Index i = 0; i < jac.rows(); ++i) {
    const double scale = std::max(1.0, numeric.row(i).cwiseAbs().maxCoeff());
    if ((jac.row(i) - numeric.row(i)).cwiseAbs().maxCoeff() > 1e-4 * scale) ++off;
  }
  EXPECT_LE(off, jac.rows() / 200) << toString(matrix) << " k=" << k << ": " << off << " of "
                                   << jac.rows() << " rows differ";
  EXPECT_GT(jac.cwiseAbs().maxCoeff(), 1.0);  // not a zero matrix that agrees trivially
}

TEST(ProductObjective, JacobianIsTheDerivativeOfTheResiduals) {
  for (auto matrix : {LightMatrixKind::kProjected, LightMatrixKind::kFull})
    for (int k : {3, 6}) {
      expectExactJacobian(test::smallTrainingSet(), matrix, k);
      expectExactJacobian(strongAbsorberSet(), matrix, k);
    }
}

// Deep products the light does not come through visibly are not residuals at all.
TEST(ProductObjective, InvisibleDeepProductsAreLeftOut) {
  const TrainingSet set = strongAbsorberSet();
  const Eigen::MatrixXd b0 = principalBasis(set, 4);
  const ProductObjective objective(test::observer(), set, b0, b0.transpose(),
                                   LightMatrixKind::kProjected);
  const int all = static_cast<int>(set.lights.size() * set.reflectances.size() *
                                   (1 + set.depths.size()));
  const int hinge = 4 * static_cast<int>(set.reflectances.size());
  EXPECT_LT(objective.residuals() - hinge, 3 * all);
  EXPECT_GE(objective.residuals() - hinge,
            3 * static_cast<int>(set.lights.size() * set.reflectances.size()));
}

}  // namespace
}  // namespace svr
