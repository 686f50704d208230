#pragma once
// Shear-warp (Lacroute & Levoy 1994; design.md §5) on the shared spectral core: factor the
// orthographic view into a shear of the slices along the principal axis and a 2D affine warp;
// composite the run-length-encoded classified slices front to back into an intermediate image
// at volume resolution (bilinear within a slice, opacity and transmission corrected for the
// slice spacing √(1 + s_i² + s_j²)), skipping transparent cell runs and opaque intermediate
// pixels; then warp every channel (S and T) to the final image.
//
// Orthographic cameras only (BackendInfo: perspective shear-warp is not implemented, so the
// harness skips it for a perspective camera). Options: `svr render --help-options shearwarp`.
//
// The run-length encoding is built once per classification and principal axis, and cached on
// the classification (RleVolume::of): the first view along an axis pays for it, later views not.
//
// Sampling follows the render (docs/backends.md): by default, slices between the voxel slices
// (trilinear) keep the ray's samples no farther apart than render.step, and the intermediate
// image is as fine as the screen. Known failures, measured in the tests and docs rather than
// hidden: label maps take one sample a slice, the principal axis switches (and the image pops)
// at 45°, and perspective cameras are refused.

#include "renderers/render/renderer.h"
#include "renderers/memory/reuse_pool.h"
#include "spectral/relight_kernel.h"

namespace svr {
namespace shearwarp {
struct IntermediateImage;
struct ShearWarpFactorization;
}

class ShearWarpRenderer final : public Renderer {
 public:
  const BackendInfo& info() const override;
  // Bricks come back as intermediate images (volume resolution × supersample along the slice
  // axes); the composited one is warped here.
  LightIndependentImage finishBricks(LightIndependentImage composited,
                                     const RenderRequest& request) const override;

 protected:
  // The intermediate image, at volume resolution × supersample along the slice axes.
  std::uint64_t workingBytes(const RenderRequest& request,
                             const BackendOptions& options) const override;
  LightIndependentImage renderImpl(const RenderRequest& request, const BackendOptions& options,
                                   ProgressCounter& progress) const override;
  void requireFinite(const LightIndependentImage& image,
                     const RenderRequest& request) const override;

 public:
  // force: the kernel's instruction set and dynamic-k path (tests compare them).
  explicit ShearWarpRenderer(KernelForce force = {});
  ~ShearWarpRenderer() override;

 private:
  // The final image warped from the intermediate one (every sample written and checked).
  LightIndependentImage warped(const shearwarp::IntermediateImage& intermediate,
                               const shearwarp::ShearWarpFactorization& view,
                               const RenderRequest& req) const;
  KernelForce force_;
  // Intermediate images of finished frames, reused by the next ones (allocating and zeroing a
  // fresh one cost about 16 ns per output pixel, some 10 of 37 ms at 800²).
  mutable ReusePool<shearwarp::IntermediateImage> pool_;
};

}  // namespace svr
