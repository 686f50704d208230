#include "renderers/gl/gl_splat_shaders.h"

#include <fmt/format.h>

#include "renderers/gl/gl_shader_sources.h"

namespace svr::gl {
namespace {

std::string header(int k, int kt, PassOutput output, int targets) {
  return fmt::format(
      "#version 450 core\n"
      "#define K {}\n#define KT {}\n#define STRIDE (1 + KT + K)\n#define NOUT {}\n"
      "#define OUTPUT {}\n",
      k, kt, targets, static_cast<int>(output));
}

}  // namespace

// The shaders' text is in shaders/: splat_prepare.glsl (the compute pass), splat_quantities.glsl
// (which quantities a splat pass needs, as v_q[0 .. NQ): the vertex shader loads them once per
// splat corner, so fragments only scale them by the kernel length; sourceOf(i) is the quantity
// behind v_q[i], or −1 for a channel past K), splat_vertex.glsl, splat_fragment.glsl,
// sheet_quantity.glsl and sheet_main.glsl (compositing a sheet), and splat_emit.glsl (the output
// stage the splat and composite fragment shaders share: quantity(q) gives quantity q of what
// this fragment composites, one splat's kernel length or one sheet).

std::string prepareShader(int k, int kt) {
  return header(k, kt, PassOutput::kAccumulate, 1) + glsl("splat_prepare.glsl");
}

std::string splatVertexShader(int k, int kt, PassOutput output, int targets, bool points) {
  return header(k, kt, output, targets) + (points ? "#define POINTS 1\n" : "#define POINTS 0\n") +
         glsl("splat_quantities.glsl") + glsl("splat_vertex.glsl");
}

std::string splatFragmentShader(int k, int kt, PassOutput output, int targets) {
  return header(k, kt, output, targets) + glsl("splat_quantities.glsl") +
         glsl("splat_fragment.glsl");
}

std::string compositeFragmentShader(int k, int kt, PassOutput output, int targets) {
  return header(k, kt, output, targets) + glsl("sheet_quantity.glsl") + glsl("splat_emit.glsl") +
         glsl("sheet_main.glsl");
}

}  // namespace svr::gl
