#include "renderers/gl/gl_raycast_shaders.h"

#include <fmt/format.h>

#include "renderers/gl/gl_shader_sources.h"

namespace svr::gl {

// The key as #defines, then shaders/raycast_declarations.glsl (the uniforms, the per-ray state
// and the helpers: sampling, classification, blocks, shading) and shaders/raycast_main.glsl
// (one ray per fragment: march the lattice, composite S and T, write the asked layers).
std::string raycastFragmentShader(const RaycastShaderKey& key) {
  return fmt::format(
             "#version 450 core\n#define K {}\n#define KT {}\n#define LABELS {}\n"
             "#define PRECOMPUTED {}\n#define FIRST {}\n#define NOUT {}\n",
             key.k, key.kt, key.labels ? 1 : 0, key.precomputed_gradients ? 1 : 0,
             key.first_layer, key.layers) +
         glsl("raycast_declarations.glsl") + glsl("raycast_main.glsl");
}

}  // namespace svr::gl
