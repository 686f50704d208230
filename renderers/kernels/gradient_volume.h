#pragma once
// The shading field and its gradient at every voxel, precomputed once per classification and
// interleaved — (f, ∂f/∂x, ∂f/∂y, ∂f/∂z) as four int16 a voxel — so that a raycaster sample
// takes its value and its normal from one trilinear reconstruction of 8-byte vectors: eight
// loads and eight multiply-adds, where the value alone was an eight-lane gather and the
// on-the-fly gradient six more trilinear reconstructions (the central difference of the
// interpolated field at p ± e for each axis). Trilinear interpolation is linear in the field,
// so interpolating per-voxel central differences is that central difference exactly wherever
// p ± e stays inside the grid; they differ only in the last voxel layer, where both clamp.
//
// Quantisation: the field to 16 bits over its range (1/64 of a classification bin at 1024
// bins; 8-bit volumes map exactly within 0.002 of a unit), the gradient to 15 bits over its
// largest component. Four floats a voxel measured 5 % slower (twice the memory traffic) and
// three int16 plus the float values took three gathers a sample.
//
// Memory: 8 bytes a voxel, twice a float volume (67 MB for the 256×256×128 engine). The
// raycaster takes it only when it fits the memory budget beside what is already held, and
// falls back to on-the-fly gradients with a note otherwise.

#include <cstdint>
#include <memory>
#include <vector>

#include "renderers/classification/classification.h"
#include "renderers/render/renderer.h"

namespace svr {

struct GradientVolume {
  Dims dims{0, 0, 0};
  // Per voxel, x fastest: the shading field (the values of a scalar volume), then its
  // gradient in world units, each quantised: decoded lane j = q · scale[j] + offset[j] (the
  // blend of a sample's corners decodes the same way, as its weights sum to 1).
  std::unique_ptr<std::int16_t[]> q;  // count values (allocated without zeroing)
  std::size_t count = 0;
  float scale[4] = {1, 1, 1, 1}, offset[4] = {0, 0, 0, 0};

  // Bytes a volume of these dimensions takes.
  static std::uint64_t bytesFor(const Dims& dims);
};

// Central differences of cv's shading field at every voxel (one-sided at the border, as the
// raycaster's clamped sampling gives), in world units, with the field itself; in parallel.
GradientVolume buildGradientVolume(const ClassifiedVolume& cv);

// The shading field's range and largest gradient component over the voxels of `box` (cv's
// own index space) — what a brick contributes to the whole volume's quantisation.
FieldRange fieldRangeOver(const ClassifiedVolume& cv, const VoxelBox& box);

// The gradients of cv, built on first use and kept with the classification (its DerivedCache).
std::shared_ptr<const GradientVolume> gradientsOf(const ClassifiedVolume& cv);

// The gradients of req.volume when they fit the memory budget beside what the classification
// and the image already hold. When they do not: with `required`, an svr::Error naming the
// budget; otherwise null (the caller takes gradients on the fly), with a note through req.note.
// `who` ("raycast") starts the note and the error.
std::shared_ptr<const GradientVolume> gradientsWithinBudget(const RenderRequest& req,
                                                            bool required,
                                                            const std::string& who);

}  // namespace svr
