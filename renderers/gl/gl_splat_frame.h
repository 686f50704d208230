#pragma once
// gl.mode=splat (design.md §5, issue 6): the CPU splat backend's algorithm (renderers/splat) on
// OpenGL 4.5 core. Every voxel that scatters or absorbs is one Gaussian-footprint quad; the
// voxel list is built and uploaded once per classification (gl_voxel_list.h), and each render
// projects and depth-sorts it on the CPU (the splat backend's Projector, so positions and
// footprints are the same numbers), shades and classifies the sorted splats in a compute
// shader, and composites back to front:
//   direct  every splat in turn, C = c_i + a_i ⊙ C;
//   sheet   image-aligned sheets (Mueller & Crawfis 1998): each sheet's share of every kernel
//           is summed into a sheet buffer, then the sheet is composited like one raycast sample.
// Chromatic absorption composites 4 S channels per pass with dual-source blending
// (GL_ONE, GL_SRC1_COLOR: one draw buffer at a time) and takes T = exp(−Σ τ_t) from an
// additive optical-depth pass; achromatic absorption (kt = 1) takes the scalar-α fast path,
// 3 S channels plus T in alpha per target, up to 8 targets in one pass. ⌈k/4⌉ (⌈k/3⌉) RGBA32F
// layers hold S; any k works, the passes just repeat.
//
// The voxel list, entries and extinction tables are the CPU backend's own (SplatVoxels), the
// shade is its cell-averaged two-sided Phong, the blend of entries its opacity-weighted one.
// Differences from it, measured in tests/renderers/gl/gl_splat_test.cpp:
// - no early ray termination (back-to-front compositing cannot stop early): S keeps the
//   contributions behind T < termination that the CPU drops, and T goes on falling below it;
// - T is exp(−Σ τ) rather than a running product, the kernel exp(−q/2) and the sheet CDF are
//   evaluated, not tabulated, and the shading runs in float: rounding-level differences.
// Output is identical for any OpenMP or llvmpipe (LP_NUM_THREADS) thread count: llvmpipe
// blends each tile's fragments in primitive order, and the CPU side joins in a fixed order.

#include <cstdint>
#include <memory>

#include "renderers/classification/derived_cache.h"
#include "renderers/render/renderer.h"
#include "renderers/kernels/splat_settings.h"
#include "renderers/gl/gl_context.h"
#include "renderers/gl/gl_objects.h"
#include "renderers/gl/gl_voxel_list.h"

namespace svr::gl {

struct GlState;

// The voxel list, the tables and the shading nodes of the classification last rendered.
struct SplatUpload {
  // By identity: the classification's derived-data cache, which lives exactly as long as the
  // classification (a weak pointer, so a new classification at the same address never passes
  // for the old one).
  std::weak_ptr<DerivedCache> uploaded_for;
  std::shared_ptr<const GlVoxelList> list;
  GlObject voxels, tables, nodes;
  // Uploads them unless cv is the classification uploaded. Needs `context` current.
  void ensure(const GlContext& context, const ClassifiedVolume& cv);
};

// One frame; the context current. Throws svr::Error beyond the context's limits.
LightIndependentImage renderSplats(GlState& state, const RenderRequest& request,
                                   const splat::SplatSettings& settings, ProgressCounter& progress);

// The RGBA32F targets a frame allocates (S, the sheet buffer, optical depth, read-back).
std::uint64_t splatWorkingBytes(const RenderRequest& request);

}  // namespace svr::gl
