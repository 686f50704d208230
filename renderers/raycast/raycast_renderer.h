#pragma once
// The reference backend (DESIGN §5): a ray per pixel, front to back, trilinear samples,
// gradients by central differences, Phong shading, early ray termination, empty-space skipping
// over min–max blocks, OpenMP over image tiles; orthographic and perspective cameras.
// The inner loop is compiled for the channel counts of core/channel_widths.h
// (raycast_kernel.h); spectral:31/81 and other counts take the dynamic path.

#include "renderers/core/renderer.h"

namespace svr {

class RaycastRenderer final : public Renderer {
 public:
  // dynamic_width: always use the dynamic-k kernel (tests compare it with the fixed ones).
  explicit RaycastRenderer(bool dynamic_width = false) : dynamic_width_(dynamic_width) {}
  const BackendInfo& info() const override;

 protected:
  LightIndependentImage renderImpl(const RenderRequest& request, const BackendOptions& options,
                                   ProgressCounter& progress) const override;

 private:
  bool dynamic_width_;
};

}  // namespace svr
