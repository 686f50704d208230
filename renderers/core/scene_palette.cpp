#include "renderers/core/scene_palette.h"

#include <fmt/format.h>

#include "spectral/colorimetry.h"
#include "spectral/data_dir.h"
#include "spectral/design_palette.h"
#include "spectral/design_solver.h"
#include "spectral/error.h"
#include "spectral/palette.h"

namespace svr {

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

  Palette palette;
  if (design) {
    const std::string path = (base / design->string()).string();
    const Observer observer = Observer::cie1931(defaultDataDir(), library.grid());
    DesignResult result = designPalette(loadDesignPalette(path, library, observer), observer);
    palette.lights = std::move(result.lights);
    palette.materials = std::move(result.materials);
  } else {
    palette = loadPalette((base / designed->string()).string(), library);
  }

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
