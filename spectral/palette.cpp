#include "spectral/palette.h"

#include <fmt/format.h>

#include "base/json_reader.h"
#include "spectral/spectrum_spec.h"

namespace svr {

Palette loadPalette(const std::string& path, const SpectrumLibrary& library) {
  return parsePalette(JsonReader::parseFile(path), path, library);
}

Palette parsePalette(const nlohmann::json& json, const std::string& path,
                     const SpectrumLibrary& library) {
  const JsonReader root(json, path);
  if (!root.isObject()) root.fail("expected a JSON object");
  const auto base = std::filesystem::path(path).parent_path();
  for (const char* key : {"description", "name", "lights", "materials"}) root.find(key);
  root.rejectUnknownKeys();  // a misspelt key is reported as such, not as a missing one
  Palette palette;
  for (const char* key : {"lights", "materials"}) {
    const JsonReader list = root.at(key);
    if (!list.isArray() || list.size() == 0) list.fail("must be a non-empty array");
    auto& out = std::string(key) == "lights" ? palette.lights : palette.materials;
    for (std::size_t i = 0; i < list.size(); ++i) {
      const JsonReader item = list.at(i);
      const std::string name = item.isString() ? item.string() : item.at("name").string();
      out.push_back({name, parseSpectrumSpec(item, library, base)});
    }
  }
  return palette;
}

}  // namespace svr
