#pragma once
// Shear-warp (Lacroute & Levoy 1994; DESIGN §5) on the shared spectral core: factor the
// orthographic view into a shear of the slices along the principal axis and a 2D affine warp;
// composite the run-length-encoded classified slices front to back into an intermediate image
// at volume resolution (bilinear within a slice, opacity and transmission corrected for the
// slice spacing √(1 + s_i² + s_j²)), skipping transparent cell runs and opaque intermediate
// pixels; then warp every channel (S and T) to the final image.
//
// Orthographic cameras only: perspective shear-warp is not implemented, and a perspective
// camera is refused with an svr::Error.
//
// Options (render.options.shearwarp):
//   "supersample": 1..4 intermediate pixels per voxel along each slice axis (default 1). Trades
//   speed for less of the blur that a volume-resolution intermediate image shows under zoom.
//
// Known failures, measured in the tests and the issue note rather than hidden: resampling is 2D
// only (bilinear in a slice, none between slices), the sample spacing grows towards 45°, the
// principal axis switches (and the image pops) at 45°, and zooming in blurs.

#include "renderers/core/renderer.h"
#include "renderers/shearwarp/rle_volume.h"

namespace svr {

class ShearWarpRenderer final : public Renderer {
 public:
  std::string name() const override { return "shearwarp"; }
  // Encodes the classified volume for this view's principal axis, then renders.
  LightIndependentImage render(const RenderRequest& request,
                               const ProgressFn& progress) const override;
  // Renders with an encoding made once per classification (its volume must be
  // request.volume), so a series of views pays for the encoding once per axis.
  LightIndependentImage render(const shearwarp::RleVolume& encoded, const RenderRequest& request,
                               const ProgressFn& progress) const;
};

}  // namespace svr
