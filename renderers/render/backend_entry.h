#pragma once
// What a backend hands the registry (renderers/registry.cpp's list): its description, how to
// make its renderer, and its relighter if it has one. A backend defines its entry from this
// header alone, so that only registry.* names the backends and no backend sits below it.

#include <functional>
#include <memory>
#include <string>
#include <utility>

#include "renderers/render/backend_info.h"
#include "renderers/render/relighter.h"
#include "renderers/render/renderer.h"

namespace svr {

struct BackendEntry {
  BackendInfo info;
  std::function<std::unique_ptr<Renderer>()> make;       // empty when not built
  std::function<std::unique_ptr<Relighter>()> relighter;  // empty: relights on the CPU only
  std::string unavailable;  // why the backend is not built (empty when it is)
};

// A backend whose folder was not built (cmake/SvrBackend.cmake: svr_backend_unavailable).
inline BackendEntry unavailableBackend(std::string name, std::string why) {
  BackendEntry entry;
  entry.info.name = std::move(name);
  entry.unavailable = std::move(why);
  return entry;
}

}  // namespace svr
