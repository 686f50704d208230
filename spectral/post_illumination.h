#pragma once
// Post-illumination (design.md §5): a light-independent image → relit pixels under any light or
// weighted mix of lights, XYZ = M(L) · (S + T ⊙ b), M(L) the model's light matrix
// (ColourModel::lightMatrix: toXyz · diag(P·L) projected, CMF · diag(L) · B full). A mix is the
// weighted sum of its lights' spectra, M being linear in L. Everything light-dependent is
// folded into one 3×P matrix per light change (P = image planes), so a frame costs one
// streaming pass over the planes: OpenMP over rows, SIMD across pixels.

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <span>

#include "spectral/colour_model.h"
#include "spectral/light_independent_image.h"
#include "spectral/relight_kernel.h"

namespace svr {

enum class RelitSpace { kLinearSrgb, kXyz };

class PostIlluminator {
 public:
  explicit PostIlluminator(const ColourModel& model);

  // light: the (mixed) light's spectrum; exposure scales the result.
  void setLight(const Spectrum& light, double exposure = 1.0);
  // Background reflectance coefficients, added as T ⊙ b where the image carries T.
  void setBackground(const Eigen::VectorXd& background);

  // 8-bit sRGB, interleaved RGB, row 0 at the top: out.size() must be 3·pixels.
  void relightSrgb8(const LightIndependentImage& image, std::span<std::uint8_t> out) const;
  // Linear float, interleaved, in linear sRGB or XYZ.
  void relightLinear(const LightIndependentImage& image, std::span<float> out,
                     RelitSpace space = RelitSpace::kLinearSrgb) const;

  // The folded 3×P matrix for an image with these planes (for tests and inspection).
  Eigen::MatrixXd foldedMatrix(const LightIndependentImage& image, RelitSpace space) const;
  const char* kernelIsa(const LightIndependentImage& image) const;
  void forceKernel(KernelForce force) { force_ = force; }

 private:
  void run(const LightIndependentImage& image, RelitSpace space, RelitEncoding encoding,
           float* out_float, std::uint8_t* out_srgb) const;

  const ColourModel& model_;
  Eigen::MatrixXd light_matrix_;  // 3 × imageChannels, to XYZ, exposure included
  Eigen::VectorXd background_;
  KernelForce force_;
  const std::uint8_t* srgb_lut_;  // the process's one table (post_illumination.cpp)
};

}  // namespace svr
