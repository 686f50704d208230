#pragma once
// gl.mode=raycast (issue 18): the CPU raycaster (renderers/raycast) as a fragment shader, one
// ray per pixel, marched front to back with its per-sample maths: the same lattice of sample
// positions (t0 + (i + ½)·Δs in voxel coordinates), trilinear reconstruction, the sample
// table's opacity-weighted blend of classified entries (scalar bins or eight corner labels),
// two-sided Phong from the precomputed gradients (or central differences on the fly),
// x-ray materials and scalar or spectral transmittance, early termination, and empty-space
// skipping over the classification's min–max octree.
//
// Uploaded once per classification (RaycastUpload): the volume as a 3D texture — the gradient
// volume's (f, ∇f) as RGBA16_SNORM, exactly its int16, filtered by the texture unit — the
// label map as R16UI, the sample table as an RGBA32F texture, and per 4³ block the edge of the
// largest empty block around it as R8UI. Each frame draws one triangle into ⌈k/4⌉ S and
// ⌈kt/4⌉ T layers of RGBA32F (up to 8 at once; more channels take more passes, each marching
// the whole ray) and reads them back.
//
// Differences from the CPU raycaster, all at rounding level (tests/renderers/gl/
// gl_raycast_test.cpp measures them): the ray set-up runs in float, not double; the texture
// unit's trilinear weights are its own (llvmpipe: float; GPUs: typically 8-bit fractions);
// pow is the driver's. Each pixel is independent, so the output does not depend on the
// number of llvmpipe threads.

#include <cstdint>
#include <memory>

#include "renderers/classification/derived_cache.h"
#include "renderers/kernels/gradient_volume.h"
#include "renderers/render/renderer.h"
#include "renderers/gl/gl_context.h"
#include "renderers/gl/gl_framebuffer.h"
#include "renderers/gl/gl_objects.h"

namespace svr::gl {

struct GlState;

struct RaycastUpload {
  std::weak_ptr<DerivedCache> uploaded_for;  // by identity, as SplatUpload
  bool precomputed = false;                  // field holds (f, ∇f), else the shading field
  GlObject field, labels, table, empty;
  float decode_scale[4] = {1, 1, 1, 1}, decode_offset[4] = {0, 0, 0, 0};
  std::unique_ptr<LayeredTarget> target;     // kept while the image size and k stay
  // Uploads cv (with `gradients`, or the shading field when null) unless it is the one
  // uploaded in the same form. Needs `context` current; svr::Error beyond its limits.
  void ensure(const GlContext& context, const ClassifiedVolume& cv,
              const GradientVolume* gradients);
};

// One frame; the context current. `gradients`: null for central differences per sample.
LightIndependentImage renderRaycast(GlState& state, const RenderRequest& request,
                                    const GradientVolume* gradients, ProgressCounter& progress);

// The RGBA32F target and the read-back buffer of a frame.
std::uint64_t raycastWorkingBytes(const RenderRequest& request);
// Bytes the uploads take on the device (textures), for the memory budget.
std::uint64_t raycastDeviceBytes(const ClassifiedVolume& cv, bool precomputed_gradients);

}  // namespace svr::gl
