#pragma once
// A spectrum named in an input file (scene, palette): one general form everywhere.
//   "D65"                                               a library name
//   {"library": "D65"}                                  the same
//   {"csv": "file.csv", "column": "col"}                a CSV table column (path relative to the file)
//   {"wavelengths": [...], "values": [...]}             inline samples on any increasing grid
//   {"constant": 0.5}                                   a flat spectrum
// Objects may also carry "name" (the caller reads it) and "scale" (a factor applied).

#include <filesystem>

#include "base/json_reader.h"
#include "spectral/spectrum_library.h"

namespace svr {

Spectrum parseSpectrumSpec(const JsonReader& spec, const SpectrumLibrary& library,
                           const std::filesystem::path& base_dir);

}  // namespace svr
