#pragma once
// The one place that names every backend (registry.cpp's list). Tests, harness and benches
// iterate it and read each entry's BackendInfo, so a new backend is compared, tested and
// benchmarked without further edits: adding one is its folder plus one line in that list.

#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "renderers/render/backend_entry.h"

namespace svr {

// Every backend in the list, built or not.
const std::vector<BackendEntry>& backendEntries();
// The built ones' names, in list order.
std::vector<std::string> rendererNames();
// The built backend of this name; svr::Error for an unknown name (listing the registered ones)
// or one that is not built (saying why).
const BackendEntry& backendEntry(const std::string& name);
std::unique_ptr<Renderer> makeRenderer(const std::string& name);
// The built backend whose capabilities say it is the reference (BackendCapabilities::reference);
// svr::Error when none is built.
const std::string& referenceRendererName();
std::unique_ptr<Relighter> makeRelighter(const std::string& name);

// Checks backend options ({"splat": {"mode": "sheet"}, …}) as the backends will read them: every
// key names a registered backend, and each backend's object holds only its own options, with
// values of the right type and range. Throws svr::Error naming `where`, backend, key and value.
void checkRendererOptions(const nlohmann::json& options, const std::string& where);
// Applies "BACKEND.KEY=VALUE" onto options and checks the result; `flag` names the source.
void applyOptionAssignment(nlohmann::json& options, const std::string& text,
                           const std::string& flag);

// Every built backend's summary, capabilities and options (`svr render --help-options`), or one
// backend's.
std::string describeBackends(const std::string& only = "");

}  // namespace svr
