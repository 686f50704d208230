#pragma once
// A palette: the lights and materials a scene uses, each a spectrum (by library name, from a
// CSV file, or inline samples). "Model no more than a scene needs" trains the factor model on a
// palette's own colour signals. The design-tool issue extends this file with targets.
//
// JSON: {"lights": [SPEC, …], "materials": [SPEC, …]} where SPEC is a spectrum in the form of
// spectrum_spec.h; objects also give a "name" (a library name is its own name).

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "spectral/spectrum_library.h"

namespace svr {

struct NamedSpectrum {
  std::string name;
  Spectrum spectrum;
};

struct Palette {
  std::vector<NamedSpectrum> lights;
  std::vector<NamedSpectrum> materials;  // reflectances
};

Palette loadPalette(const std::string& path, const SpectrumLibrary& library);
// The same from JSON already in memory; `path` names it and anchors relative CSV paths.
Palette parsePalette(const nlohmann::json& json, const std::string& path,
                     const SpectrumLibrary& library);

}  // namespace svr
