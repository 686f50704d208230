#pragma once
// The one place that names every backend. Tests, harness and benches iterate it, so a new
// backend is compared and benchmarked without further edits.

#include <memory>
#include <string>
#include <vector>

#include "renderers/core/renderer.h"

namespace svr {

std::vector<std::string> rendererNames();
// Throws svr::Error for an unknown name, listing the registered ones.
std::unique_ptr<Renderer> makeRenderer(const std::string& name);

}  // namespace svr
