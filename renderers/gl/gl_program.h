#pragma once
// A linked GLSL program. Compile and link failures are svr::Error carrying the program's name
// and the driver's log (the line numbers refer to the source as given), never a silent
// fallback to a program that draws nothing.

#include <string>
#include <utility>
#include <vector>

#include "renderers/gl/gl_context.h"

namespace svr::gl {

struct ShaderStage {
  GLenum type;  // GL_VERTEX_SHADER, GL_FRAGMENT_SHADER, GL_COMPUTE_SHADER
  std::string source;
};

class GlProgram {
 public:
  // Needs `context` current; so does the destructor.
  GlProgram(const GlContext& context, std::string name, const std::vector<ShaderStage>& stages);
  ~GlProgram();
  GlProgram(const GlProgram&) = delete;
  GlProgram& operator=(const GlProgram&) = delete;

  GLuint id() const { return id_; }
  const std::string& name() const { return name_; }
  // Uniform setters; a uniform the compiler removed as unused is silently skipped, as GL does.
  void set(const char* uniform, int value) const;
  void set(const char* uniform, float value) const;
  void set(const char* uniform, float x, float y) const;
  void set(const char* uniform, float x, float y, float z) const;
  void set(const char* uniform, int x, int y, int z) const;
  void set(const char* uniform, const float (&xyzw)[4]) const;
  void set(const char* uniform, const std::vector<float>& values) const;

 private:
  const GlApi& gl_;
  std::string name_;
  GLuint id_ = 0;
};

// The vertex shader of one triangle covering the viewport (no inputs), for passes that run a
// fragment shader per pixel.
std::string fullscreenVertexShader();

}  // namespace svr::gl
