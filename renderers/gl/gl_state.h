#pragma once
// What the gl backend keeps between renders on one renderer instance: the context (on its
// platform), an empty vertex array, the compiled programs by name, and each mode's uploads of
// the classification last rendered. Both modes share it, so switching between gl.mode=raycast
// and gl.mode=splat on one instance keeps the context and the other mode's uploads.

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "renderers/gl/gl_context.h"
#include "renderers/gl/gl_objects.h"
#include "renderers/gl/gl_program.h"
#include "renderers/gl/gl_raycast_frame.h"
#include "renderers/gl/gl_splat_frame.h"
#include "base/error.h"

namespace svr::gl {

struct GlState {
  GlContext context;  // first: destroyed last, after every object below
  GlObject vao;
  std::map<std::string, std::unique_ptr<GlProgram>> programs;
  SplatUpload splat;
  RaycastUpload raycast;

  explicit GlState(GlPlatformKind platform) : context(platform) {
    const GlContext::Current current(context);
    vao = makeVertexArray(context.api());
  }
  ~GlState() {
    try {
      const GlContext::Current current(context);
      programs.clear();
      splat = {};
      raycast = {};
      vao.reset();
    } catch (const Error&) {
      // The context could not be made current: destroying it frees its objects all the same.
    }
  }
  GlState(const GlState&) = delete;
  GlState& operator=(const GlState&) = delete;

  // The program of this name, built from `stages` the first time it is asked for.
  const GlProgram& program(const std::string& key,
                           const std::function<std::vector<ShaderStage>()>& stages) {
    auto& p = programs[key];
    if (!p) p = std::make_unique<GlProgram>(context, key, stages());
    return *p;
  }
};

}  // namespace svr::gl
