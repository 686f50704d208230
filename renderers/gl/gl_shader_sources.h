#pragma once
// The gl backend's GLSL, kept as files in renderers/gl/shaders/ and embedded in the binary at
// build time (cmake/EmbedFiles.cmake, as the viewer's page is), so that shaders read as GLSL and
// the binary needs no files beside it. A program's source is assembled from a header of
// #defines (channel counts, what a pass writes) and one or more of these files.

#include <string>
#include <string_view>

namespace svr {

struct GlslFile {
  std::string_view path;  // "raycast_main.glsl", …
  std::string_view content_type;
  std::string_view bytes;
};

// The embedded file at this path, or nullptr (defined by the generated svr_gl_glsl.cpp).
const GlslFile* findGlslFile(std::string_view path);

namespace gl {

// The text of shaders/NAME. A name that is not embedded is a mistake in the build, reported as
// std::logic_error.
std::string glsl(std::string_view name);

}  // namespace gl
}  // namespace svr
