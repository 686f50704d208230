#pragma once
// GLSL sources of the gl splat renderer, specialised at compile time for the channel counts
// (k scattered channels, kt transmittance channels) and for what a pass writes:
//   kAccumulate  additive sums of per-splat quantities × kernel length: the sheet buffer
//                (τ_α, τ_t, E) or the optical depth behind T;
//   kDual        back-to-front C = c + a ⊙ C for 4 S channels through dual-source blending
//                (GL_ONE, GL_SRC1_COLOR): chromatic absorption;
//   kScalar      the scalar-α fast path: 3 S channels per target and 1 − a in alpha, blended
//                (GL_ONE, GL_ONE_MINUS_SRC_ALPHA) into up to 8 targets at once; alpha keeps T.
// Quantities are numbered as in the sheet buffer: 0 = τ_α (optical depth that scatters),
// 1 .. kt = τ_t (optical depth that attenuates), kt + 1 .. kt + k = E (σ_α-weighted colour).

#include <string>

namespace svr::gl {

enum class PassOutput { kAccumulate, kDual, kScalar };

// Compute shader: shades and classifies each sorted splat into its quantity record.
std::string prepareShader(int k, int kt);
// Splats: vertex shader (no attributes; one point sprite per splat, or, for footprints wider
// than the largest point, a quad of 6 vertices) and fragment shader.
std::string splatVertexShader(int k, int kt, PassOutput output, int targets, bool points);
std::string splatFragmentShader(int k, int kt, PassOutput output, int targets);
// Sheet compositing: over fullscreenVertexShader's triangle (gl_program.h), reading the sheet
// buffer, which has the S image's size and margin, so a fragment reads its own texel.
std::string compositeFragmentShader(int k, int kt, PassOutput output, int targets);

}  // namespace svr::gl
