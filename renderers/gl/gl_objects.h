#pragma once
// Owning handles for GL object names (buffers, textures, framebuffers, vertex arrays): the name
// is deleted when the handle dies, so the context must be current then. Destroying the context
// frees whatever it still owns; these handles matter for objects replaced while it lives (a new
// classification's voxel list, a bigger image).

#include <array>
#include <cstddef>
#include <cstring>
#include <utility>

#include "renderers/gl/gl_api.h"

namespace svr::gl {

class GlObject {
 public:
  // glDeleteBuffers, glDeleteTextures, glDeleteFramebuffers and glDeleteVertexArrays share
  // this signature.
  using Deleter = void(APIENTRYP)(GLsizei, const GLuint*);
  GlObject() = default;
  GlObject(GLuint id, Deleter deleter) : id_(id), deleter_(deleter) {}
  GlObject(GlObject&& o) noexcept
      : id_(std::exchange(o.id_, 0)), deleter_(std::exchange(o.deleter_, nullptr)) {}
  GlObject& operator=(GlObject&& o) noexcept {
    if (this != &o) {
      reset();
      id_ = std::exchange(o.id_, 0);
      deleter_ = std::exchange(o.deleter_, nullptr);
    }
    return *this;
  }
  GlObject(const GlObject&) = delete;
  GlObject& operator=(const GlObject&) = delete;
  ~GlObject() { reset(); }
  void reset() {
    if (id_ && deleter_) deleter_(1, &id_);
    id_ = 0;
  }
  GLuint id() const { return id_; }
  explicit operator bool() const { return id_ != 0; }

 private:
  GLuint id_ = 0;
  Deleter deleter_ = nullptr;
};

// An immutable-storage buffer of `bytes` (at least 16: GL refuses empty storage), filled from
// `data` when given. flags: GL_DYNAMIC_STORAGE_BIT where it is rewritten with SubData.
inline GlObject makeBuffer(const GlApi& gl, std::size_t bytes, const void* data,
                           GLbitfield flags = 0) {
  GLuint id = 0;
  gl.CreateBuffers(1, &id);
  // GL reads the whole storage size from `data`: a smaller source is padded with zeros first.
  std::array<std::byte, 16> padded{};
  const void* source = bytes ? data : nullptr;
  if (source && bytes < padded.size()) {
    std::memcpy(padded.data(), data, bytes);
    source = padded.data();
  }
  gl.NamedBufferStorage(id, static_cast<GLsizeiptr>(bytes < 16 ? 16 : bytes), source, flags);
  return {id, gl.DeleteBuffers};
}

inline GlObject makeVertexArray(const GlApi& gl) {
  GLuint id = 0;
  gl.CreateVertexArrays(1, &id);
  return {id, gl.DeleteVertexArrays};
}

}  // namespace svr::gl
