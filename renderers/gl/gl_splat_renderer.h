#pragma once
// The OpenGL backend (DESIGN §5, issue 6): the CPU splat backend's algorithm (renderers/splat)
// on OpenGL 4.5 core, offscreen through OSMesa. Every voxel that scatters or absorbs is one
// Gaussian-footprint quad; the voxel list is built and uploaded once per classification
// (gl_voxel_list.h), and each render projects and depth-sorts it on the CPU (the splat
// backend's Projector, so positions and footprints are the same numbers), shades and classifies
// the sorted splats in a compute shader, and composites back to front:
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
//
// One OSMesa context per renderer instance, created at the first render and used by one render
// at a time (a mutex): renders on several instances run in parallel, each on its own context.
// Output is identical for any OpenMP or llvmpipe (LP_NUM_THREADS) thread count: llvmpipe
// blends each tile's fragments in primitive order, and the CPU side joins in a fixed order.
//
// Options: the splat backend's, with its defaults (core/splat_settings.h; `svr render
// --help-options gl`).

#include <memory>
#include <mutex>
#include <string>

#include "renderers/core/renderer.h"

namespace svr {

class GlSplatRenderer final : public Renderer {
 public:
  GlSplatRenderer();
  ~GlSplatRenderer() override;
  const BackendInfo& info() const override;

 protected:
  // The RGBA32F targets (S, the sheet buffer, optical depth) and the read-back buffer.
  std::uint64_t workingBytes(const RenderRequest& request,
                             const BackendOptions& options) const override;
  // Throws svr::Error when no context can be made, a shader fails, or the image or volume
  // exceeds the context's limits (named in the message).
  LightIndependentImage renderImpl(const RenderRequest& request, const BackendOptions& options,
                                   ProgressCounter& progress) const override;

 private:
  struct State;
  class Frame;
  mutable std::mutex mutex_;
  mutable std::unique_ptr<State> state_;
};

}  // namespace svr
