#include "renderers/gl/gl_program.h"

#include <fmt/format.h>

#include "base/error.h"
#include "renderers/gl/gl_shader_sources.h"

namespace svr::gl {
namespace {

const char* stageName(GLenum type) {
  switch (type) {
    case GL_VERTEX_SHADER: return "vertex";
    case GL_FRAGMENT_SHADER: return "fragment";
    case GL_COMPUTE_SHADER: return "compute";
    default: return "shader";
  }
}

}  // namespace

GlProgram::GlProgram(const GlContext& context, std::string name,
                     const std::vector<ShaderStage>& stages)
    : gl_(context.api()), name_(std::move(name)) {
  context.check(fmt::format("before building program '{}'", name_));
  std::vector<GLuint> shaders;
  const auto cleanup = [&] {
    for (GLuint s : shaders) gl_.DeleteShader(s);
  };
  for (const ShaderStage& stage : stages) {
    const GLuint shader = gl_.CreateShader(stage.type);
    shaders.push_back(shader);
    const char* text = stage.source.c_str();
    gl_.ShaderSource(shader, 1, &text, nullptr);
    gl_.CompileShader(shader);
    GLint ok = GL_FALSE, length = 0;
    gl_.GetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (!ok) {
      gl_.GetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
      std::string log(length > 0 ? length : 1, '\0');
      gl_.GetShaderInfoLog(shader, static_cast<GLsizei>(log.size()), nullptr, log.data());
      cleanup();
      throw Error(fmt::format("gl: program '{}': the {} shader does not compile:\n{}", name_,
                              stageName(stage.type), log.c_str()));
    }
  }
  id_ = gl_.CreateProgram();
  for (GLuint s : shaders) gl_.AttachShader(id_, s);
  gl_.LinkProgram(id_);
  for (GLuint s : shaders) gl_.DetachShader(id_, s);
  cleanup();
  GLint ok = GL_FALSE, length = 0;
  gl_.GetProgramiv(id_, GL_LINK_STATUS, &ok);
  if (!ok) {
    gl_.GetProgramiv(id_, GL_INFO_LOG_LENGTH, &length);
    std::string log(length > 0 ? length : 1, '\0');
    gl_.GetProgramInfoLog(id_, static_cast<GLsizei>(log.size()), nullptr, log.data());
    gl_.DeleteProgram(id_);
    throw Error(fmt::format("gl: program '{}' does not link:\n{}", name_, log.c_str()));
  }
  context.check(fmt::format("building program '{}'", name_));
}

GlProgram::~GlProgram() { gl_.DeleteProgram(id_); }

void GlProgram::set(const char* u, int v) const {
  gl_.ProgramUniform1i(id_, gl_.GetUniformLocation(id_, u), v);
}
void GlProgram::set(const char* u, float v) const {
  gl_.ProgramUniform1f(id_, gl_.GetUniformLocation(id_, u), v);
}
void GlProgram::set(const char* u, float x, float y) const {
  gl_.ProgramUniform2f(id_, gl_.GetUniformLocation(id_, u), x, y);
}
void GlProgram::set(const char* u, float x, float y, float z) const {
  gl_.ProgramUniform3f(id_, gl_.GetUniformLocation(id_, u), x, y, z);
}
void GlProgram::set(const char* u, int x, int y, int z) const {
  gl_.ProgramUniform3i(id_, gl_.GetUniformLocation(id_, u), x, y, z);
}
void GlProgram::set(const char* u, const float (&v)[4]) const {
  gl_.ProgramUniform4f(id_, gl_.GetUniformLocation(id_, u), v[0], v[1], v[2], v[3]);
}
void GlProgram::set(const char* u, const std::vector<float>& v) const {
  gl_.ProgramUniform1fv(id_, gl_.GetUniformLocation(id_, u), static_cast<GLsizei>(v.size()),
                        v.data());
}

std::string fullscreenVertexShader() {
  return glsl("fullscreen_vertex.glsl");
}

}  // namespace svr::gl
