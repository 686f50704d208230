#pragma once
// The one place that names every backend. Tests, harness and benches iterate it, so a new
// backend is compared and benchmarked without further edits.

#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "renderers/core/renderer.h"

namespace svr {

std::vector<std::string> rendererNames();
// Throws svr::Error for an unknown name, listing the registered ones.
std::unique_ptr<Renderer> makeRenderer(const std::string& name);

// Backend options ({"splat": {"mode": "sheet"}, …}) name only registered backends. Each backend
// rejects its own unknown keys, but a key for a backend that does not exist would be read by
// none and silently ignored. Throws svr::Error "WHERE: unknown backend 'NAME' …".
void checkRendererOptions(const nlohmann::json& options, const std::string& where);

}  // namespace svr
