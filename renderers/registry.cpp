#include "renderers/registry.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <functional>
#include <utility>

#include "renderers/raycast/raycast_renderer.h"
#include "renderers/shearwarp/shearwarp_renderer.h"
#include "renderers/splat/splat_renderer.h"
#include "spectral/error.h"

namespace svr {
namespace {

using Factory = std::function<std::unique_ptr<Renderer>()>;

const std::vector<std::pair<std::string, Factory>>& registry() {
  static const std::vector<std::pair<std::string, Factory>> entries{
      {"raycast", [] { return std::make_unique<RaycastRenderer>(); }},
      {"shearwarp", [] { return std::make_unique<ShearWarpRenderer>(); }},
      {"splat", [] { return std::make_unique<SplatRenderer>(); }},
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
  throw Error(fmt::format("unknown renderer '{}'; registered: {}", name,
                          fmt::join(rendererNames(), ", ")));
}

}  // namespace svr
