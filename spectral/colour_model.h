#pragma once
// The one interface every colour model offers (design.md §4): coefficients of a spectrum, the
// coefficients of flat white, a 3×k matrix to XYZ, and the product of a spectrum with
// coefficients. `rgb`, `spectral:n` and `factor:k` take products componentwise; `linear:k`
// (Peercy 1993) uses a k×k matrix per interaction.

#include <Eigen/Core>
#include <memory>
#include <nlohmann/json_fwd.hpp>
#include <string>

#include "spectral/spectrum.h"

namespace svr {

enum class ModelKind { kRgb, kSpectral, kFactor, kLinear };

std::string toString(ModelKind kind);

// How a light becomes the 3×k matrix that relights a light-independent pixel (issue 19):
//   kProjected  toXyz · diag(P·L): the light is projected like any spectrum and its product
//               with the pixel is taken componentwise in the model (the paper's method; the
//               only one rgb has, having no basis);
//   kFull       CMF · diag(L) · B with the grid's weights: the pixel's spectrum B·c times the
//               light's full spectrum. The last product is exact, the cost per frame the same,
//               and it is still linear in L, so mixes of lights mix their matrices.
// A model is trained for one of them (factor_training.h), so the choice is part of its name.
enum class LightMatrixKind { kProjected, kFull };
std::string toString(LightMatrixKind kind);

// "factor:6" → {kFactor, 6, kFull}; "factor:6/projected" → {kFactor, 6, kProjected}; "rgb" →
// {kRgb, 3, kProjected}. The light matrix defaults to full for the models with a spectral basis
// (factor, spectral) and is projected for rgb and linear, which have no other. Throws
// svr::Error naming the text.
struct ModelName {
  ModelKind kind;
  int k;
  LightMatrixKind light_matrix = defaultLightMatrix(kind);
  std::string str() const;
  static LightMatrixKind defaultLightMatrix(ModelKind kind) {
    return kind == ModelKind::kFactor || kind == ModelKind::kSpectral ? LightMatrixKind::kFull
                                                                      : LightMatrixKind::kProjected;
  }
};
ModelName parseModelName(const std::string& text);

using XyzMatrix = Eigen::Matrix<double, 3, Eigen::Dynamic>;

class ColourModel {
 public:
  virtual ~ColourModel() = default;

  ModelKind kind() const { return kind_; }
  int channels() const { return static_cast<int>(white_.size()); }
  std::string name() const { return ModelName{kind_, channels(), light_matrix_}.str(); }
  LightMatrixKind lightMatrixKind() const { return light_matrix_; }
  // How the basis was made, e.g. "refined" or "pca" for factor models; "" where there is one way.
  const std::string& variant() const { return variant_; }
  const WavelengthGrid& grid() const { return grid_; }

  // True when a product of spectra is the componentwise product of their coefficients.
  virtual bool componentwise() const = 0;
  // Coefficients of a spectrum (a light, a reflectance or a transmittance).
  virtual Eigen::VectorXd project(const Spectrum& s) const = 0;
  // Coefficients of a per-step transmittance t (0 ≤ t ≤ 1), as every renderer and the model's
  // training take them: project(t) clamped to [0, 1] per channel. A transmittance cannot exceed
  // 1, and a projection can (a sharpened basis has negative lobes): a channel of 1.02 would grow
  // 158-fold over 256 steps, one of −0.1 flip sign every step. With the clamp no channel of T
  // grows along a ray, however deep the absorption, for any model (issue 40).
  Eigen::VectorXd projectTransmittance(const Spectrum& t) const {
    return project(t).cwiseMax(0.0).cwiseMin(1.0);
  }
  // The k×k matrix that multiplies coefficients by the spectrum s (diagonal when componentwise).
  virtual Eigen::MatrixXd interaction(const Spectrum& s) const = 0;
  // Coefficients of the flat spectrum 1.
  const Eigen::VectorXd& white() const { return white_; }
  // XYZ = toXyz() · coefficients (the grid's quadrature weights included).
  const XyzMatrix& toXyz() const { return to_xyz_; }

  // Channels of the light-independent image this model's renderers produce: k when
  // componentwise; k² for linear:k (the scattered radiance is a k×k matrix applied to the light).
  virtual int imageChannels() const { return channels(); }
  // The 3 × imageChannels() matrix that takes a light-independent pixel to XYZ under the light
  // spectrum L, as lightMatrixKind() says: toXyz · diag(P·L) when componentwise and projected,
  // CMF · diag(L) · B when full. Linear in L.
  virtual Eigen::MatrixXd lightMatrix(const Spectrum& light) const = 0;

  // Each model writes itself in its own file (componentwise_model.cpp, linear_model.cpp), on
  // jsonHead(): name, variant, grid and to_xyz; modelFromJson reads any of them back.
  virtual nlohmann::json toJson() const = 0;

 protected:
  nlohmann::json jsonHead() const;
  ColourModel(ModelKind kind, std::string variant, WavelengthGrid grid)
      : kind_(kind), variant_(std::move(variant)), grid_(grid) {}

  ModelKind kind_;
  LightMatrixKind light_matrix_ = LightMatrixKind::kProjected;
  std::string variant_;
  WavelengthGrid grid_;
  Eigen::VectorXd white_;
  XyzMatrix to_xyz_;
};

// A matrix as rows of numbers (the model files' layout).
nlohmann::json matrixToJson(const Eigen::MatrixXd& m);

// Loads any model saved with toJson(); `source` names the file in errors.
std::unique_ptr<ColourModel> modelFromJson(const nlohmann::json& j, const std::string& source);
void saveModel(const ColourModel& model, const std::string& path);
std::unique_ptr<ColourModel> loadModel(const std::string& path);

}  // namespace svr
