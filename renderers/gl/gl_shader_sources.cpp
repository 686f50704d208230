#include "renderers/gl/gl_shader_sources.h"

#include <stdexcept>

namespace svr::gl {

std::string glsl(std::string_view name) {
  const GlslFile* file = findGlslFile(name);
  if (!file)
    throw std::logic_error("renderers/gl/shaders/" + std::string(name) +
                           " is not embedded (renderers/gl/CMakeLists.txt lists the shaders)");
  return std::string(file->bytes);
}

}  // namespace svr::gl
