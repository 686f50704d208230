#pragma once
// GLSL of gl.mode=raycast (gl_raycast_frame.h): one fragment shader that marches the ray of its
// pixel front to back with the CPU raycaster's per-sample maths (renderers/raycast), drawn over
// fullscreenVertexShader's triangle. Channel counts and the volume's kind are compile-time
// constants, so each combination is its own program.

#include <string>

namespace svr::gl {

struct RaycastShaderKey {
  int k = 3, kt = 1;
  bool labels = false;                // a label map (8 corner labels a sample), else scalar bins
  bool precomputed_gradients = true;  // (f, ∇f) in one texture, else central differences
  // The output layers this pass writes: S in layers 0 … ⌈k/4⌉ − 1, then T in ⌈kt/4⌉ layers.
  int first_layer = 0, layers = 1;
};

std::string raycastFragmentShader(const RaycastShaderKey& key);

}  // namespace svr::gl
