#include "renderers/gl/gl_platform.h"

#include <fmt/format.h>

#include "base/error.h"

namespace svr::gl {

const char* platformName(GlPlatformKind kind) {
  return kind == GlPlatformKind::kEgl ? "egl" : "osmesa";
}

GlPlatformKind platformOf(const std::string& name) {
  if (name == "auto") return defaultPlatform();
  if (name == "osmesa") return GlPlatformKind::kOsmesa;
  if (name == "egl") return GlPlatformKind::kEgl;
  throw Error(fmt::format("gl: platform '{}' is not one of auto, osmesa, egl", name));
}

std::unique_ptr<GlPlatform> makePlatform(GlPlatformKind kind) {
  return kind == GlPlatformKind::kEgl ? makeEglPlatform() : makeOsmesaPlatform();
}

}  // namespace svr::gl
