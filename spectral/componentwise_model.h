#pragma once
// A colour model whose products are componentwise: coefficients c = P·s (P is k×n) and
// XYZ = toXyz·c. This one type serves rgb, spectral:n (band means) and factor:k (a sharpened
// basis B with P = B⁺), so every renderer kernel has one contract.

#include "spectral/colorimetry.h"
#include "spectral/colour_model.h"

namespace svr {

class ComponentwiseModel final : public ColourModel {
 public:
  // basis: n×k spectra the coefficients weigh (for reconstruction and for the record; may be
  // empty for rgb, which has no spectral basis). Full-spectrum light matrices need the basis
  // and spectrum_to_xyz, the observer's weighted colour-matching functions (3×n).
  ComponentwiseModel(ModelKind kind, std::string variant, WavelengthGrid grid,
                     Eigen::MatrixXd projection, XyzMatrix to_xyz, Eigen::MatrixXd basis,
                     LightMatrixKind light_matrix = LightMatrixKind::kProjected,
                     XyzMatrix spectrum_to_xyz = XyzMatrix());

  bool componentwise() const override { return true; }
  Eigen::VectorXd project(const Spectrum& s) const override;
  Eigen::MatrixXd interaction(const Spectrum& s) const override;
  Eigen::MatrixXd lightMatrix(const Spectrum& light) const override;
  nlohmann::json toJson() const override;

  const Eigen::MatrixXd& projection() const { return projection_; }
  const Eigen::MatrixXd& basis() const { return basis_; }
  const XyzMatrix& spectrumToXyz() const { return spectrum_to_xyz_; }

 private:
  Eigen::MatrixXd projection_;  // k×n
  Eigen::MatrixXd basis_;       // n×k, or empty
  XyzMatrix spectrum_to_xyz_;   // 3×n, full light matrices only
};

// Linear sRGB of the spectrum (reflectance under E), scaled so flat white is (1, 1, 1).
std::unique_ptr<ComponentwiseModel> makeRgbModel(const Observer& observer);
// n contiguous equal bands of the grid, band means; n = grid size is exact up to sampling.
// With full light matrices a band's light is its full spectrum, not its band mean.
std::unique_ptr<ComponentwiseModel> makeSpectralModel(
    const Observer& observer, int n, LightMatrixKind light_matrix = LightMatrixKind::kFull);

}  // namespace svr
