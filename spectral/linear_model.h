#pragma once
// Peercy's linear model (SIGGRAPH 1993): coefficients in an orthonormal PCA basis B0 (n×k);
// the interaction with a spectrum s is the k×k matrix B0ᵀ·diag(s)·B0, built from the full
// spectrum. (Building it from the projection of s instead makes tⁿ grow instead of decay.)

#include "spectral/colorimetry.h"
#include "spectral/colour_model.h"

namespace svr {

class LinearModel final : public ColourModel {
 public:
  LinearModel(const Observer& observer, Eigen::MatrixXd orthonormal_basis);
  LinearModel(WavelengthGrid grid, Eigen::MatrixXd orthonormal_basis, XyzMatrix to_xyz);

  bool componentwise() const override { return false; }
  Eigen::VectorXd project(const Spectrum& s) const override;
  Eigen::MatrixXd interaction(const Spectrum& s) const override;
  int imageChannels() const override { return channels() * channels(); }
  // XYZ = toXyz · S · a for a k×k scattered-radiance matrix S stored column-major, a = the
  // light's coefficients (projected: this model has no other light matrix).
  Eigen::MatrixXd lightMatrix(const Spectrum& light) const override;
  nlohmann::json toJson() const override;

  const Eigen::MatrixXd& basis() const { return basis_; }

 private:
  Eigen::MatrixXd basis_;  // n×k, orthonormal columns
};

}  // namespace svr
