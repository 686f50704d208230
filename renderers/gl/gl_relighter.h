#pragma once
// Post-illumination on OpenGL (design.md §5, issue 6): the same maths as PostIlluminator's relight
// kernels — rgb = M · (plane_0, …, plane_{P−1}) with M the folded 3×P matrix, clamped to
// [0, 1], sRGB-encoded, 8 bits — in a fragment shader over the planes held in a texture. The
// image is uploaded once (setImage); each relight sends only the 3×P matrix as uniforms, draws
// one triangle into an RGBA8 target and reads the pixels back. A non-finite result is reported
// with its pixel, as the CPU kernels do. Owns its OSMesa context; one thread at a time.

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <span>

#include "renderers/render/relighter.h"
#include "spectral/light_independent_image.h"

namespace svr {

class GlRelighter final : public Relighter {
 public:
  GlRelighter();  // throws svr::Error when no GL 4.5 context can be made
  ~GlRelighter() override;
  GlRelighter(const GlRelighter&) = delete;
  GlRelighter& operator=(const GlRelighter&) = delete;

  // Uploads the planes (float or half). Throws svr::Error beyond the context's limits.
  void setImage(const LightIndependentImage& image) override;
  // folded: 3 × planes, to linear sRGB (PostIlluminator::foldedMatrix(image, kLinearSrgb)).
  // rgb: interleaved 8-bit sRGB, 3 × pixels, row 0 at the top (PostIlluminator's layout).
  void relightSrgb8(const Eigen::MatrixXd& folded, std::span<std::uint8_t> rgb) const override;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace svr
