#pragma once
// Relighting on a device of a backend's (the gl backend's fragment shader) instead of the CPU
// kernels: the same folded 3×(k + kt) matrix of PostIlluminator::foldedMatrix, applied per
// pixel. A backend offers one through its registry entry; `svr relight --on BACKEND` picks it.

#include <Eigen/Core>
#include <cstdint>
#include <span>

#include "spectral/light_independent_image.h"

namespace svr {

class Relighter {
 public:
  virtual ~Relighter() = default;
  // Uploads the image; later relights reuse it.
  virtual void setImage(const LightIndependentImage& image) = 0;
  // sRGB8 of the folded matrix (RelitSpace::kLinearSrgb) applied to every pixel.
  virtual void relightSrgb8(const Eigen::MatrixXd& folded, std::span<std::uint8_t> rgb) const = 0;
};

}  // namespace svr
