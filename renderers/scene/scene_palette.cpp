#include "renderers/scene/scene_palette.h"

#include <fmt/format.h>

#include "spectral/colorimetry.h"
#include "base/data_dir.h"
#include "spectral/design_palette.h"
#include "spectral/design_solver.h"
#include "base/disk_cache.h"
#include "spectral/observer_key.h"
#include "base/error.h"
#include "spectral/palette.h"
#include "base/text_file.h"

namespace svr {
namespace {

// Bump when the design solver, its defaults or the palette format's reading change: palettes
// cached by an older version are then designed again.
constexpr int kDesignedPaletteVersion = 1;

nlohmann::json valuesOf(const std::vector<DesignSpectrum>& spectra) {
  nlohmann::json out = nlohmann::json::array();
  for (const auto& s : spectra)
    out.push_back({s.name, s.free, valuesJson(s.spectrum.values())});
  return out;
}

// Everything a design depends on: the palette file as read (cells, options, names), the values
// of every spectrum it names (library entries and CSV files it loaded), the observer, the grid.
nlohmann::json designKey(const std::string& text, const DesignPalette& design,
                         const Observer& observer) {
  return {{"version", kDesignedPaletteVersion},
          {"palette_file", text},
          {"lights", valuesOf(design.lights)},
          {"materials", valuesOf(design.materials)},
          {"observer", observerKey(observer)}};
}

nlohmann::json toJson(const std::vector<NamedSpectrum>& spectra) {
  nlohmann::json out = nlohmann::json::array();
  for (const auto& s : spectra)
    out.push_back({{"name", s.name}, {"values", valuesJson(s.spectrum.values())}});
  return out;
}

std::vector<NamedSpectrum> spectraFrom(const nlohmann::json& j, const WavelengthGrid& grid) {
  std::vector<NamedSpectrum> out;
  for (const auto& s : j) {
    const std::vector<double> v = s.at("values");
    if (static_cast<int>(v.size()) != grid.count) throw Error("cached palette: wrong grid");
    out.push_back({s.at("name"), Spectrum(grid, Eigen::Map<const Eigen::VectorXd>(
                                                    v.data(), static_cast<Eigen::Index>(v.size())))});
  }
  return out;
}

// The designed palette: from the disk cache when this exact design was made before.
Palette designedPalette(const std::string& path, const SpectrumLibrary& library) {
  const Observer observer = Observer::cie1931(defaultDataDir(), library.grid());
  const DesignPalette design = loadDesignPalette(path, library, observer);
  const DiskCache& cache = DiskCache::process();
  const nlohmann::json key = designKey(readTextFile(path, "design palette"), design, observer);
  if (const auto hit = cache.load("palette", key); hit.payload) {
    try {
      return {spectraFrom(hit.payload->at("lights"), library.grid()),
              spectraFrom(hit.payload->at("materials"), library.grid())};
    } catch (const std::exception&) {
      // A well-formed entry that does not read back is designed again, like a corrupt one.
    }
  }
  DesignResult result = designPalette(design, observer);
  Palette palette{std::move(result.lights), std::move(result.materials)};
  cache.store("palette", key,
              {{"lights", toJson(palette.lights)}, {"materials", toJson(palette.materials)}});
  return palette;
}

}  // namespace

SpectrumLibrary withScenePalette(const JsonReader& spec, const std::filesystem::path& base,
                                 const SpectrumLibrary& library) {
  if (!spec.isObject())
    spec.fail(R"(expected {"design": PALETTE.json} or {"designed": DIR/palette.json})");
  const auto design = spec.find("design");
  const auto designed = spec.find("designed");
  if (design.has_value() == designed.has_value())
    spec.fail("needs exactly one of \"design\" (a palette to design now) and \"designed\" "
              "(the palette.json svr design saved)");
  spec.rejectUnknownKeys();

  const Palette palette = design ? designedPalette((base / design->string()).string(), library)
                                 : loadPalette((base / designed->string()).string(), library);

  SpectrumLibrary out = library;
  const auto define = [&](const NamedSpectrum& s, SpectrumKind kind) {
    const std::string name = "palette/" + s.name;
    if (out.contains(name)) spec.fail(fmt::format("the palette names '{}' twice", s.name));
    out.define(name, s.spectrum, kind);
  };
  for (const auto& l : palette.lights) define(l, SpectrumKind::kLight);
  for (const auto& m : palette.materials) define(m, SpectrumKind::kReflectance);
  return out;
}

}  // namespace svr
