#pragma once
// The reference backend (design.md §5): a ray per pixel, front to back, trilinear samples, Phong
// shading with gradients precomputed at the voxels (kernels/gradient_volume.h; central differences
// on the fly when they do not fit the memory budget), early ray termination, empty-space
// skipping over min–max blocks, OpenMP over image tiles; orthographic and perspective cameras.
// The inner loop is compiled for the channel counts of simd/channel_widths.h
// (raycast_kernel.h); spectral:31/81 and other counts take the dynamic path.

#include "renderers/render/renderer.h"
#include "spectral/relight_kernel.h"

namespace svr {

class RaycastRenderer final : public Renderer {
 public:
  // force: always the dynamic-k kernel, or one instruction set's kernels (tests compare them
  // with the fixed widths and the widest instruction set, which are the default).
  explicit RaycastRenderer(KernelForce force = {}) : force_(force) {}
  const BackendInfo& info() const override;

 protected:
  LightIndependentImage renderImpl(const RenderRequest& request, const BackendOptions& options,
                                   ProgressCounter& progress) const override;

 private:
  KernelForce force_;
};

}  // namespace svr
