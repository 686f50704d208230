#include "spectral/componentwise_model.h"

#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include "base/error.h"

namespace svr {

ComponentwiseModel::ComponentwiseModel(ModelKind kind, std::string variant, WavelengthGrid grid,
                                       Eigen::MatrixXd projection, XyzMatrix to_xyz,
                                       Eigen::MatrixXd basis, LightMatrixKind light_matrix,
                                       XyzMatrix spectrum_to_xyz)
    : ColourModel(kind, std::move(variant), grid),
      projection_(std::move(projection)),
      basis_(std::move(basis)),
      spectrum_to_xyz_(std::move(spectrum_to_xyz)) {
  to_xyz_ = std::move(to_xyz);
  white_ = projection_.rowwise().sum();
  light_matrix_ = light_matrix;
  if (light_matrix == LightMatrixKind::kFull &&
      (basis_.rows() != grid.count || basis_.cols() != projection_.rows() ||
       spectrum_to_xyz_.cols() != grid.count))
    throw Error(fmt::format("model {}: full-spectrum light matrices need an {}×{} basis and the "
                            "3×{} colour-matching functions",
                            name(), grid.count, projection_.rows(), grid.count));
}

Eigen::VectorXd ComponentwiseModel::project(const Spectrum& s) const {
  if (!(s.grid() == grid_))
    throw Error(fmt::format("model {} is on {}, the spectrum on {}", name(), grid_.describe(),
                            s.grid().describe()));
  return projection_ * s.values();
}

Eigen::MatrixXd ComponentwiseModel::interaction(const Spectrum& s) const {
  return project(s).asDiagonal();
}

Eigen::MatrixXd ComponentwiseModel::lightMatrix(const Spectrum& light) const {
  if (light_matrix_ == LightMatrixKind::kFull) {
    if (!(light.grid() == grid_))
      throw Error(fmt::format("model {} is on {}, the light on {}", name(), grid_.describe(),
                              light.grid().describe()));
    return spectrum_to_xyz_ * light.values().asDiagonal() * basis_;
  }
  return to_xyz_ * project(light).asDiagonal();
}

std::unique_ptr<ComponentwiseModel> makeRgbModel(const Observer& observer) {
  const WavelengthGrid grid = observer.grid();
  const Eigen::Matrix3d to_rgb = xyzToLinearSrgbMatrix();
  // Linear sRGB of the spectrum; the flat spectrum 1 gets (1,1,1) after the per-channel scale,
  // and toXyz undoes that scale so XYZ of a light×reflectance product stays in physical units.
  const Eigen::MatrixXd rgb = to_rgb * observer.weightedCmf().transpose();  // 3×n
  const Eigen::Vector3d white_rgb = rgb.rowwise().sum();
  Eigen::MatrixXd projection = white_rgb.cwiseInverse().asDiagonal() * rgb;
  XyzMatrix to_xyz = linearSrgbToXyzMatrix() * white_rgb.asDiagonal();
  return std::make_unique<ComponentwiseModel>(ModelKind::kRgb, "", grid, projection, to_xyz,
                                              Eigen::MatrixXd());
}

std::unique_ptr<ComponentwiseModel> makeSpectralModel(const Observer& observer, int n,
                                                      LightMatrixKind light_matrix) {
  const WavelengthGrid grid = observer.grid();
  if (n < 1 || n > grid.count)
    throw Error(fmt::format("spectral:{} needs 1..{} bands on the grid {}", n, grid.count,
                            grid.describe()));
  Eigen::MatrixXd basis = Eigen::MatrixXd::Zero(grid.count, n);
  for (int i = 0; i < grid.count; ++i) basis(i, static_cast<int>(static_cast<long>(i) * n / grid.count)) = 1.0;
  Eigen::MatrixXd projection = basis.transpose();
  for (int b = 0; b < n; ++b) projection.row(b) /= projection.row(b).sum();
  XyzMatrix to_xyz = observer.weightedCmf().transpose() * basis;
  return std::make_unique<ComponentwiseModel>(ModelKind::kSpectral, n == grid.count ? "" : "bands",
                                              grid, projection, to_xyz, basis, light_matrix,
                                              observer.weightedCmf().transpose());
}

nlohmann::json ComponentwiseModel::toJson() const {
  nlohmann::json j = jsonHead();
  j["projection"] = matrixToJson(projection_);
  j["basis"] = matrixToJson(basis_);
  if (light_matrix_ == LightMatrixKind::kFull) j["spectrum_to_xyz"] = matrixToJson(spectrum_to_xyz_);
  return j;
}

}  // namespace svr
