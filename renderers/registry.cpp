#include "renderers/registry.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>

#include "base/error.h"

// The list of backends. Each NAME is a folder renderers/NAME/ whose CMakeLists.txt adds its
// sources (or says why it cannot be built) and which defines svr::backends::NAME().
#define SVR_BACKENDS(X) \
  X(raycast)            \
  X(shearwarp)          \
  X(splat)              \
  X(gl)                 \
  /* one line per entry, each ending in a backslash */

namespace svr {
namespace backends {
#define SVR_DECLARE(NAME) BackendEntry NAME();
SVR_BACKENDS(SVR_DECLARE)
#undef SVR_DECLARE
}  // namespace backends

const std::vector<BackendEntry>& backendEntries() {
#define SVR_ENTRY(NAME) backends::NAME(),
  static const std::vector<BackendEntry> entries{SVR_BACKENDS(SVR_ENTRY)};
#undef SVR_ENTRY
  return entries;
}

std::vector<std::string> rendererNames() {
  std::vector<std::string> names;
  for (const auto& e : backendEntries())
    if (e.make) names.push_back(e.info.name);
  return names;
}

const BackendEntry& backendEntry(const std::string& name) {
  for (const auto& e : backendEntries()) {
    if (e.info.name != name) continue;
    if (!e.make) throw Error(fmt::format("renderer '{}' is not built: {}", name, e.unavailable));
    return e;
  }
  throw Error(fmt::format("unknown renderer '{}'; registered: {}", name,
                          fmt::join(rendererNames(), ", ")));
}

std::unique_ptr<Renderer> makeRenderer(const std::string& name) {
  return backendEntry(name).make();
}

const std::string& referenceRendererName() {
  for (const auto& e : backendEntries())
    if (e.make && e.info.supports.reference) return e.info.name;
  throw Error("no reference backend is built (BackendCapabilities::reference)");
}

std::unique_ptr<Relighter> makeRelighter(const std::string& name) {
  const BackendEntry& e = backendEntry(name);
  if (!e.relighter) {
    std::vector<std::string> with;
    for (const auto& other : backendEntries())
      if (other.relighter && other.make) with.push_back(other.info.name);
    throw Error(fmt::format("backend '{}' has no relighter of its own; backends with one: {}",
                            name, with.empty() ? "none" : fmt::format("{}", fmt::join(with, ", "))));
  }
  return e.relighter();
}

void checkRendererOptions(const nlohmann::json& options, const std::string& where) {
  if (!options.is_object())
    throw Error(fmt::format("{}: expected {{\"backend\": {{\"key\": value}}}}, got {}", where,
                            options.dump()));
  for (const auto& [backend, values] : options.items()) {
    const auto& entries = backendEntries();
    const auto it = std::find_if(entries.begin(), entries.end(),
                                 [&](const BackendEntry& e) { return e.info.name == backend; });
    if (it == entries.end())
      throw Error(fmt::format("{}: unknown backend '{}'; registered: {}", where, backend,
                              fmt::join(rendererNames(), ", ")));
    // A backend that is not built reads nothing here: its options are kept for builds that have
    // it, as a scene file is shared between machines.
    if (it->make) readBackendOptions(it->info.options, options, backend, where);
  }
}

void applyOptionAssignment(nlohmann::json& options, const std::string& text,
                           const std::string& flag) {
  const OptionAssignment a = parseOptionAssignment(text, flag);
  nlohmann::json updated = options;
  updated[a.backend][a.key] = a.value;
  checkRendererOptions(updated, fmt::format("{} '{}'", flag, text));
  options = std::move(updated);
}

std::string describeBackends(const std::string& only) {
  if (!only.empty()) backendEntry(only);  // unknown or unbuilt names fail
  std::string out;
  for (const auto& e : backendEntries()) {
    if (!only.empty() && e.info.name != only) continue;
    if (!e.make) {
      out += fmt::format("{}: not built: {}\n\n", e.info.name, e.unavailable);
      continue;
    }
    const BackendCapabilities& s = e.info.supports;
    out += fmt::format("{}: {}\n  supports: {} cameras, {} transmittance, k ≤ {}{}{}\n",
                       e.info.name, e.info.summary,
                       s.perspective ? "orthographic and perspective" : "orthographic",
                       s.spectral_transmittance ? "scalar and spectral" : "scalar",
                       s.max_channels, s.needs_gl ? ", needs an OpenGL context" : "",
                       e.relighter ? ", relights on its device (svr relight --on)" : "");
    if (e.info.options.empty()) out += "  options: none\n";
    for (const auto& o : e.info.options) out += fmt::format("  {}.{}\n", e.info.name, o.describe());
    out += "\n";
  }
  return out;
}

}  // namespace svr
