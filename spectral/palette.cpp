#include "spectral/palette.h"

#include <fmt/format.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "spectral/csv_table.h"
#include "spectral/error.h"

namespace svr {
namespace {

NamedSpectrum parseSpectrum(const nlohmann::json& j, const std::string& where,
                            const std::filesystem::path& base, const SpectrumLibrary& library) {
  if (j.is_string()) return {j.get<std::string>(), library.get(j.get<std::string>())};
  if (!j.is_object())
    throw Error(fmt::format("{}: expected a library name or an object, got {}", where, j.dump()));
  for (const auto& [key, value] : j.items())
    if (key != "name" && key != "library" && key != "csv" && key != "column" &&
        key != "wavelengths" && key != "values")
      throw Error(fmt::format("{}: unknown key '{}'", where, key));
  if (!j.contains("name") || !j["name"].is_string())
    throw Error(fmt::format("{}.name: missing or not a string", where));
  const std::string name = j["name"].get<std::string>();
  if (j.contains("library")) {
    if (!j["library"].is_string())
      throw Error(fmt::format("{}.library: expected a string, got {}", where, j["library"].dump()));
    return {name, library.get(j["library"].get<std::string>())};
  }
  if (j.contains("csv")) {
    if (!j["csv"].is_string() || !j.contains("column") || !j["column"].is_string())
      throw Error(fmt::format("{}: 'csv' needs a file name and a 'column' name", where));
    const CsvTable table = loadCsvTable((base / j["csv"].get<std::string>()).string());
    const std::string column = j["column"].get<std::string>();
    const int c = table.columnIndex(column);
    if (c < 0)
      throw Error(fmt::format("{}.column: '{}' is not a column of {}", where, column, table.source));
    return {name, table.spectrum(c, library.grid(), OutsideRange::kError)};
  }
  if (j.contains("wavelengths") && j.contains("values")) {
    std::vector<double> wl, v;
    try {
      wl = j["wavelengths"].get<std::vector<double>>();
      v = j["values"].get<std::vector<double>>();
    } catch (const nlohmann::json::exception&) {
      throw Error(fmt::format("{}: wavelengths and values must be arrays of numbers", where));
    }
    return {name, Spectrum::resample(library.grid(), wl, v, OutsideRange::kError, where)};
  }
  throw Error(fmt::format("{}: give 'library', 'csv' or 'wavelengths'+'values'", where));
}

}  // namespace

Palette loadPalette(const std::string& path, const SpectrumLibrary& library) {
  std::ifstream in(path);
  if (!in) throw Error(fmt::format("{}: cannot open palette", path));
  nlohmann::json j;
  try {
    in >> j;
  } catch (const nlohmann::json::exception& e) {
    throw Error(fmt::format("{}: invalid JSON: {}", path, e.what()));
  }
  if (!j.is_object()) throw Error(fmt::format("{}: expected a JSON object", path));
  const auto base = std::filesystem::path(path).parent_path();
  Palette palette;
  for (const auto& [key, value] : j.items()) {
    if (key != "lights" && key != "materials" && key != "description" && key != "name")
      throw Error(fmt::format("{}: unknown key '{}'", path, key));
  }
  for (const char* key : {"lights", "materials"}) {
    if (!j.contains(key) || !j[key].is_array() || j[key].empty())
      throw Error(fmt::format("{}: '{}' must be a non-empty array", path, key));
    auto& out = std::string(key) == "lights" ? palette.lights : palette.materials;
    for (size_t i = 0; i < j[key].size(); ++i)
      out.push_back(
          parseSpectrum(j[key][i], fmt::format("{}: {}[{}]", path, key, i), base, library));
  }
  return palette;
}

}  // namespace svr
