#include "renderers/registry.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <functional>
#include <utility>

#include "renderers/raycast/raycast_renderer.h"
#include "renderers/shearwarp/shearwarp_renderer.h"
#include "renderers/splat/splat_renderer.h"
#ifdef SVR_HAVE_GL
#include "renderers/gl/gl_splat_renderer.h"
#endif
#include "spectral/error.h"

namespace svr {
namespace {

using Factory = std::function<std::unique_ptr<Renderer>()>;

const std::vector<std::pair<std::string, Factory>>& registry() {
  static const std::vector<std::pair<std::string, Factory>> entries{
      {"raycast", [] { return std::make_unique<RaycastRenderer>(); }},
      {"shearwarp", [] { return std::make_unique<ShearWarpRenderer>(); }},
      {"splat", [] { return std::make_unique<SplatRenderer>(); }},
#ifdef SVR_HAVE_GL
      {"gl", [] { return std::make_unique<GlSplatRenderer>(); }},
#endif
  };
  return entries;
}

}  // namespace

std::vector<std::string> rendererNames() {
  std::vector<std::string> names;
  for (const auto& [name, factory] : registry()) names.push_back(name);
  return names;
}

std::unique_ptr<Renderer> makeRenderer(const std::string& name) {
  for (const auto& [n, factory] : registry())
    if (n == name) return factory();
#ifndef SVR_HAVE_GL
  if (name == "gl")
    throw Error("renderer 'gl' is not built: OSMesa was not found when svr was configured "
                "(install libosmesa6-dev and configure again)");
#endif
  throw Error(fmt::format("unknown renderer '{}'; registered: {}", name,
                          fmt::join(rendererNames(), ", ")));
}

void checkRendererOptions(const nlohmann::json& options, const std::string& where) {
  if (!options.is_object())
    throw Error(fmt::format("{}: expected {{\"backend\": {{\"key\": value}}}}", where));
  const std::vector<std::string> names = rendererNames();
  for (const auto& [backend, values] : options.items())
    if (std::find(names.begin(), names.end(), backend) == names.end())
      throw Error(fmt::format("{}: unknown backend '{}'; registered: {}", where, backend,
                              fmt::join(names, ", ")));
}

}  // namespace svr
