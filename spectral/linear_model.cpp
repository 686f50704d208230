#include "spectral/linear_model.h"

#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include "base/error.h"

namespace svr {

LinearModel::LinearModel(const Observer& observer, Eigen::MatrixXd orthonormal_basis)
    : ColourModel(ModelKind::kLinear, "peercy", observer.grid()),
      basis_(std::move(orthonormal_basis)) {
  white_ = basis_.colwise().sum().transpose();
  to_xyz_ = observer.weightedCmf().transpose() * basis_;
}

LinearModel::LinearModel(WavelengthGrid grid, Eigen::MatrixXd orthonormal_basis, XyzMatrix to_xyz)
    : ColourModel(ModelKind::kLinear, "peercy", grid), basis_(std::move(orthonormal_basis)) {
  white_ = basis_.colwise().sum().transpose();
  to_xyz_ = std::move(to_xyz);
}

Eigen::VectorXd LinearModel::project(const Spectrum& s) const {
  if (!(s.grid() == grid_))
    throw Error(fmt::format("model {} is on {}, the spectrum on {}", name(), grid_.describe(),
                            s.grid().describe()));
  return basis_.transpose() * s.values();
}

Eigen::MatrixXd LinearModel::interaction(const Spectrum& s) const {
  if (!(s.grid() == grid_))
    throw Error(fmt::format("model {} is on {}, the spectrum on {}", name(), grid_.describe(),
                            s.grid().describe()));
  return basis_.transpose() * s.values().asDiagonal() * basis_;
}

Eigen::MatrixXd LinearModel::lightMatrix(const Spectrum& light_spectrum) const {
  const Eigen::VectorXd light = project(light_spectrum);
  // XYZ = toXyz · S · a with S column-major in the image: entry (i, j) is channel i + k·j,
  // so column (i + k·j) of the result is toXyz(:, i) · a(j).
  const int k = channels();
  Eigen::MatrixXd m(3, k * k);
  for (int j = 0; j < k; ++j) m.middleCols(j * k, k) = to_xyz_ * light[j];
  return m;
}

nlohmann::json LinearModel::toJson() const {
  nlohmann::json j = jsonHead();
  j["basis"] = matrixToJson(basis_);
  return j;
}

}  // namespace svr
