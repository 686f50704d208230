#pragma once
// Float render targets: a stack of width×height RGBA32F layers (one 2D array texture, so any
// number of channel groups fits) and a framebuffer object that draws into up to
// GL_MAX_DRAW_BUFFERS consecutive layers at once. RGBA32F renders unclamped, which the
// spectral sums need (coefficients leave [0, 1]). Sizes beyond the context's limits, and a
// framebuffer GL calls incomplete, are svr::Error.

#include <map>
#include <string>
#include <utility>
#include <vector>

#include "renderers/gl/gl_context.h"
#include "renderers/gl/gl_objects.h"

namespace svr::gl {

// Throws svr::Error naming `what` and the status unless the framebuffer is complete.
void checkFramebufferComplete(const GlContext& context, GLuint framebuffer,
                              const std::string& what);

class LayeredTarget {
 public:
  // Needs `context` current (and for the whole life of the target).
  LayeredTarget(const GlContext& context, int width, int height, int layers, std::string name);

  int width() const { return width_; }
  int height() const { return height_; }
  int layers() const { return layers_; }
  GLuint texture() const { return texture_.id(); }

  // Binds a framebuffer with layers [first, first + count) as draw buffers 0..count-1 (one
  // framebuffer object per range, made and checked once, so passes that alternate between
  // ranges only rebind).
  void drawInto(int first, int count);
  // Sets every bound draw buffer to (rgb, rgb, rgb, alpha) (inside the scissor, if on).
  void clear(float rgb, float alpha);
  // The w×h pixels from (x, y) of layer `layer` as interleaved RGBA floats, row y first.
  void read(int layer, int x, int y, int w, int h, std::vector<float>& rgba) const;

 private:
  const GlContext& context_;
  int width_, height_, layers_;
  std::string name_;
  GlObject texture_;
  std::map<std::pair<int, int>, GlObject> framebuffers_;  // by (first, count)
  GLuint bound_ = 0;
  int bound_count_ = 0;
};

}  // namespace svr::gl
