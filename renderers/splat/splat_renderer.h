#pragma once
// The splatting backend (design.md §5, issue 5): every voxel that scatters or absorbs is a Gaussian
// kernel projected to an image footprint (kernels/splat_footprint.h: one for every splat of an
// orthographic view, evaluated in factors (footprint_factors.h), EWA ellipses with a
// screen-space low-pass per splat for perspective; splat_coverage.h), composited either through
// image-aligned sheet buffers (sheet_compositor.h, the default) or splat by splat
// (direct_compositor.h). OpenMP over fixed bands of image rows: identical bytes for any number
// of threads. Options and their measured defaults: kernels/splat_settings.h
// (`svr render --help-options splat`).

#include "renderers/render/renderer.h"
#include "renderers/memory/reuse_pool.h"
#include "spectral/relight_kernel.h"

namespace svr {
namespace splat {
struct SplatFrameMemory;
}

class SplatRenderer final : public Renderer {
 public:
  // force.dynamic_width: the any-k compositing loops (tests); the splats have one instruction set.
  explicit SplatRenderer(KernelForce force = {});
  ~SplatRenderer() override;
  const BackendInfo& info() const override;

 protected:
  // A frame's splat arrays (SplatFrameMemory: projections, sort keys, splat records, band lists;
  // about 100 bytes a listed voxel) and each thread's sheet buffer.
  std::uint64_t workingBytes(const RenderRequest& request,
                             const BackendOptions& options) const override;
  LightIndependentImage renderImpl(const RenderRequest& request, const BackendOptions& options,
                                   ProgressCounter& progress) const override;

 private:
  KernelForce force_;
  // The arrays of finished frames (projections, sort keys, splat and band lists), reused by the
  // next ones.
  mutable ReusePool<splat::SplatFrameMemory> pool_;
};

}  // namespace svr
