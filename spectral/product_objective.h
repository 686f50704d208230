#pragma once
// The objective factor training minimises (factor_training.h): the product error of the
// white-normalised model B = B0·T·diag(w), P = diag(w)⁻¹·T⁻¹·P0, w = T⁻¹·P0·1, as a function of
// the sharpening transform T, with its exact Jacobian.
//
// Residuals are CIELAB differences (against each light's own white, deep products
// exposure-normalised), so the least-squares objective weighs errors as ΔE does, plus a hinge
// on reflectance coefficients outside [kCoeffLo, kCoeffHi]. Lab residuals measured better than
// XYZ ones on the held-out Munsell set (k = 9: 0.56 / 0.87 against 0.64 / 0.99 single / deep).
// Projected light matrices predict toXyz · (P·L ⊙ P·R ⊙ (P·t)^m); full ones
// C · diag(L) · B · (P·R ⊙ (P·t)^m), with P·t clamped to [0, 1] as renderers take it
// (ColourModel::projectTransmittance).

#include <Eigen/Core>
#include <vector>

#include "spectral/colorimetry.h"
#include "spectral/factor_training.h"

namespace svr {

class ProductObjective {
 public:
  static constexpr int kMaxSamples = 1000;  // refinement uses an evenly spaced subset
  static constexpr double kCoeffLo = -1.0, kCoeffHi = 3.0;  // bounds on reflectance coefficients
  static constexpr double kBoundWeight = 1.0;

  // b0 (n×k) and p0 (k×n): the starting span, T acts on its k channels.
  ProductObjective(const Observer& observer, const TrainingSet& set, const Eigen::MatrixXd& b0,
                   const Eigen::MatrixXd& p0, LightMatrixKind light_matrix);

  int parameters() const { return k_ * k_; }
  int residuals() const { return static_cast<int>(products_.size()) * 3 + k_ * n_; }

  // Residuals for T = theta (k×k, column-major), and with `jacobian` their derivatives
  // (residuals() × parameters()). False where the model is singular, not finite or cancels by
  // more than kMaxCancellation: the optimiser treats such a point as infinitely bad.
  bool evaluate(const Eigen::VectorXd& theta, Eigen::VectorXd& r,
                Eigen::MatrixXd* jacobian = nullptr) const;

  // The cost minimised: Σ ρ(|r_p|²) over the products' Lab residuals r_p, with the soft-L1
  // ρ(s) = 2c²(√(1 + s/c²) − 1), c = kRobustScale, plus the hinges squared. ρ is quadratic
  // below c and grows like 2c·|r| above it, so the cost follows the mean ΔE the candidates are
  // judged by: with plain squares a handful of deep products a model cannot fit (Lab errors in
  // the hundreds once exposure-normalised) outweighed every other product, and training
  // converged to models worse on the palette than k equal bands.
  static constexpr double kRobustScale = 1.0;
  double cost(const Eigen::VectorXd& r) const;
  // Scales each product's rows of r and the Jacobian by √ρ'(|r_p|²): a Gauss–Newton step on
  // the scaled system is one of iteratively reweighted least squares on cost(), whose gradient
  // Jᵀ·diag(ρ')·r it reproduces exactly.
  void reweigh(Eigen::VectorXd& r, Eigen::MatrixXd& jacobian) const;
  // cost() at T, infinite where evaluate fails.
  double value(const Eigen::MatrixXd& t) const;

 private:
  // One Lab residual: light l through reflectance j at depth index c (0: no absorber).
  // Deep products the light does not come through visibly (Y < kVisibleDepthY) are left out:
  // the image is black there whatever the model does.
  struct Product {
    int c, l, j;
    double scale;  // exposure normalisation: the filtered light's Y is 1
    Eigen::Vector3d exact;
  };
  struct State;  // what one T makes: coefficients, white scale, colour matrices
  bool makeState(const Eigen::VectorXd& theta, State& s) const;
  // The three rows of one product, given its q = cl ⊙ cr ⊙ ct^m and its predicted XYZ.
  void productJacobian(const State& s, const Product& p, const Eigen::VectorXd& q, const Xyz& xyz,
                       Eigen::Ref<Eigen::MatrixXd> rows) const;

  int k_, n_ = 0;
  std::vector<int> depths_;
  bool full_;
  Eigen::MatrixXd al_, ar_, at_, cb_, whites_;
  std::vector<Eigen::MatrixXd> cb_light_;
  Eigen::VectorXd a1_;
  std::vector<Product> products_;
};

}  // namespace svr
