#pragma once
// Gradients of the shading field precomputed at the voxels, once per classification, so that a
// sample's normal is one trilinear reconstruction instead of six (the on-the-fly central
// difference of the trilinear field takes f at p ± e for each axis). Trilinear interpolation is
// linear in the field, so interpolating per-voxel central differences gives the same gradient
// as the central difference of the interpolated field wherever p ± e stays inside the grid;
// they differ only in the last voxel layer, where both clamp.
//
// Stored compact: three int16 per voxel (6 bytes, 1.5× a float volume) with one scale for the
// volume. Normals are directions, so 15 bits relative to the largest gradient keep them within
// a fraction of a degree wherever the gradient is more than about 1/1000 of the largest.

#include <cstdint>
#include <memory>
#include <vector>

#include "renderers/core/classification.h"

namespace svr {

struct GradientVolume {
  Dims dims{0, 0, 0};
  float scale = 1.f;               // world-unit gradient per quantum
  std::vector<std::int16_t> q;     // x, y, z per voxel; voxels x fastest; then kPadding zeros
  // Past the last voxel, so that a 32-bit load of a voxel's z (the raycaster's AVX2 gather)
  // stays inside the allocation.
  static constexpr int kPadding = 2;

  // Bytes the gradients of a volume of these dimensions take.
  static std::uint64_t bytesFor(const Dims& dims);
};

// Central differences of cv's shading field at every voxel (one-sided at the border, as the
// raycaster's clamped sampling gives), in world units; built in parallel.
GradientVolume buildGradientVolume(const ClassifiedVolume& cv);

// The gradients of cv, built on first use and kept with the classification (its DerivedCache).
std::shared_ptr<const GradientVolume> gradientsOf(const ClassifiedVolume& cv);

}  // namespace svr
