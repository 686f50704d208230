#pragma once
// The shading field and its gradient at every voxel, precomputed once per classification and
// interleaved — (f, ∂f/∂x, ∂f/∂y, ∂f/∂z) as four floats a voxel — so that a raycaster sample
// takes its value and its normal from one trilinear reconstruction of 16-byte vectors: eight
// aligned loads and eight multiply-adds, where the value alone was an eight-lane gather and the
// on-the-fly gradient six more trilinear reconstructions (the central difference of the
// interpolated field at p ± e for each axis). Trilinear interpolation is linear in the field,
// so interpolating per-voxel central differences is that central difference exactly wherever
// p ± e stays inside the grid; they differ only in the last voxel layer, where both clamp.
//
// Memory: 16 bytes a voxel, four times a float volume (134 MB for the 256×256×128 engine). The
// raycaster takes it only when it fits the memory budget beside what is already held, and
// falls back to on-the-fly gradients with a note otherwise.

#include <cstdint>
#include <memory>
#include <vector>

#include "renderers/core/classification.h"

namespace svr {

struct GradientVolume {
  Dims dims{0, 0, 0};
  // Per voxel, x fastest: the shading field (the values of a scalar volume), then its
  // gradient in world units. 16-byte aligned (the vector's allocation is), for the kernels'
  // vector loads.
  std::vector<float> vg;

  // Bytes a volume of these dimensions takes.
  static std::uint64_t bytesFor(const Dims& dims);
};

// Central differences of cv's shading field at every voxel (one-sided at the border, as the
// raycaster's clamped sampling gives), in world units, with the field itself; in parallel.
GradientVolume buildGradientVolume(const ClassifiedVolume& cv);

// The gradients of cv, built on first use and kept with the classification (its DerivedCache).
std::shared_ptr<const GradientVolume> gradientsOf(const ClassifiedVolume& cv);

}  // namespace svr
