#pragma once
// A scene's designed palette (issue 8): the lights and materials `svr design` makes, named in
// the scene as "palette/NAME". Either designed when the scene loads, from the palette itself —
//   "palette": {"design": "../palettes/engine.json"}
// — or read from what `svr design --out DIR` saved, for palettes that take long to design:
//   "palette": {"designed": "designed/frog/palette.json"}
// Paths are relative to the scene file.

#include <filesystem>

#include "base/json_reader.h"
#include "spectral/spectrum_library.h"

namespace svr {

// The library with the palette's spectra added as "palette/NAME" (lights as lights, materials
// as reflectances).
SpectrumLibrary withScenePalette(const JsonReader& palette, const std::filesystem::path& base,
                                 const SpectrumLibrary& library);

}  // namespace svr
