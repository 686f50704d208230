#pragma once
// What the gl backend uploads once per classification: the CPU splat backend's view-independent
// voxel list (splat/splat_voxels.h: the same voxels that scatter or absorb, entries, fractions
// and per-unit-length extinction tables) in the layout the prepare shader reads, plus the
// per-entry tables. Built on first use and cached on the classification (ClassifiedVolume::
// derived), so every gl renderer instance and context reuses it; the shading field's dual-grid
// cell means (the CPU splat's shading) are made at upload time, as a 3D texture.

#include <cstdint>
#include <memory>
#include <vector>

#include "renderers/classification/classification.h"
#include "renderers/kernels/splat_voxels.h"

namespace svr::gl {

// One voxel as the prepare shader reads it (std430: vec4 + ivec4).
struct GpuVoxel {
  float x, y, z;          // world position of the voxel centre
  float frac;             // weight of entry + 1 (0 for label maps)
  std::int32_t i, j, k;   // voxel index: its cell's corners are dual-grid nodes i..i+1, …
  std::int32_t entry;     // classification entry
};
static_assert(sizeof(GpuVoxel) == 32);

struct GlVoxelList {
  GlVoxelList(const ClassifiedVolume& volume,
              std::shared_ptr<const splat::SplatVoxels> splat_voxels);
  // The classification's instance, built on first use.
  static std::shared_ptr<const GlVoxelList> of(const ClassifiedVolume& volume);

  std::shared_ptr<const splat::SplatVoxels> splat_voxels;
  std::vector<GpuVoxel> voxels;  // in the order of splat_voxels->voxels()
  // Per-entry tables, one float array: σ_α (entries), σ_t (entries × kt), ρ (entries × k),
  // specular weight (entries), white (k); σ in extinction per world unit.
  std::vector<float> tables;
};

}  // namespace svr::gl
