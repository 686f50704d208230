#pragma once
// The one interface every colour model offers (DESIGN §4): coefficients of a spectrum, the
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

// "factor:6" → {kFactor, 6}; "rgb" → {kRgb, 3}. Throws svr::Error naming the text.
struct ModelName {
  ModelKind kind;
  int k;
  std::string str() const;
};
ModelName parseModelName(const std::string& text);

using XyzMatrix = Eigen::Matrix<double, 3, Eigen::Dynamic>;

class ColourModel {
 public:
  virtual ~ColourModel() = default;

  ModelKind kind() const { return kind_; }
  int channels() const { return static_cast<int>(white_.size()); }
  std::string name() const { return ModelName{kind_, channels()}.str(); }
  // How the basis was made, e.g. "refined" or "pca" for factor models; "" where there is one way.
  const std::string& variant() const { return variant_; }
  const WavelengthGrid& grid() const { return grid_; }

  // True when a product of spectra is the componentwise product of their coefficients.
  virtual bool componentwise() const = 0;
  // Coefficients of a spectrum (a light, a reflectance or a transmittance).
  virtual Eigen::VectorXd project(const Spectrum& s) const = 0;
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
  // whose coefficients are given: toXyz · diag(light) when componentwise.
  virtual Eigen::MatrixXd lightMatrix(const Eigen::VectorXd& light) const = 0;

  // Each model writes itself in its own file (componentwise_model.cpp, linear_model.cpp), on
  // jsonHead(): name, variant, grid and to_xyz; modelFromJson reads any of them back.
  virtual nlohmann::json toJson() const = 0;

 protected:
  nlohmann::json jsonHead() const;
  ColourModel(ModelKind kind, std::string variant, WavelengthGrid grid)
      : kind_(kind), variant_(std::move(variant)), grid_(grid) {}

  ModelKind kind_;
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
