#pragma once
// A design palette (Bergner, Drew & Möller, TOG 2009; paper §3.1, §5.2): rows are materials,
// columns are lights; every spectrum is given or free (to be designed), and cells hold what a
// material should look like under a light: a target colour, black (a metameric black), or a tie
// with other materials as metamers whose shared colour is itself unknown.
//
// JSON:
//   {"description": "…",
//    "lights":    [SPEC | {"name": N, "free": true, "init": SPEC?}, …],
//    "materials": [SPEC | {"name": N, "free": true, "init": SPEC?}, …],
//    "cells":    [{"material": M, "light": L, ("srgb": "#rrggbb" | "xyz": [x,y,z] |
//                  "lab": [L,a,b] | "like": SPEC | "black": true), "weight": w?}, …],
//    "metamers": [{"light": L, "materials": [M, …], "weight": w?}, …],
//    "options":  {"smoothness", "bounds": "physical"|"artificial", "projection_model":
//                 "none"|"factor:k", "projection_weight", "projection_de2000",
//                 "projection_rounds", "light_luminance", "max_iterations",
//                 "miss_de2000", "black_y", "ridge", "split_blocks"}}
// SPEC is a spectrum as in spectrum_spec.h. Target XYZ is relative to the white under that
// light (Y = 1); sRGB and Lab targets use the sRGB (D65) white: "#ffffff" is XYZ of D65, Y = 1.
// "like" takes the colour of a reflectance under that (given) light.

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "spectral/colorimetry.h"
#include "spectral/spectrum_library.h"

namespace svr {

struct DesignSpectrum {
  std::string name;
  bool free = false;
  Spectrum spectrum;  // the given spectrum, or the starting guess of a free one
};

enum class CellKind { kColour, kBlack, kMetamer };
std::string toString(CellKind kind);

struct DesignCell {
  int material = 0;
  int light = 0;
  CellKind kind = CellKind::kColour;  // kColour or kBlack (metamers are MetamerGroups)
  Xyz target = Xyz::Zero();           // relative to the white under the light, Y = 1
  double weight = 1.0;
};

struct MetamerGroup {
  int light = 0;
  std::vector<int> materials;  // at least two; their shared colour is an unknown
  double weight = 1.0;
};

enum class DesignBounds {
  kPhysical,    // reflectances in [0, 1], lights ≥ 0
  kArtificial,  // unbounded (paper §3.1: spectra that need not be physical)
};

struct DesignOptions {
  double smoothness = 1e-3;  // weight of the second-difference rows of every free spectrum
  DesignBounds bounds = DesignBounds::kPhysical;
  int projection_k = 0;  // 0: no projection-error term; else the factor:k model's subspace
  double projection_weight = 1.0;
  double projection_de2000 = 0.5;  // stop refreshing the subspace once every signal is within
  int projection_rounds = 8;       // at most this many refreshes
  double light_luminance = 1.0;  // Y of the white under every light (flat E = 1 has Y = 1)
  int max_iterations = 200;      // bilinear alternation rounds
  double miss_de2000 = 1.0;      // a colour or metamer cell further than this is a miss
  double black_y = 0.01;         // a black cell brighter than this (Y, white = 1) is a miss
  double ridge = 1e-4;           // tiny Tikhonov term: keeps every sub-problem well posed
  bool split_blocks = false;     // solve one free spectrum at a time (big palettes)
};

struct DesignPalette {
  std::string description;
  std::vector<DesignSpectrum> lights;
  std::vector<DesignSpectrum> materials;
  std::vector<DesignCell> cells;
  std::vector<MetamerGroup> metamers;
  DesignOptions options;
};

DesignPalette loadDesignPalette(const std::string& path, const SpectrumLibrary& library,
                                const Observer& observer);
// The same from JSON already in memory; `path` names it and anchors relative CSV paths.
DesignPalette parseDesignPalette(const nlohmann::json& json, const std::string& path,
                                 const SpectrumLibrary& library, const Observer& observer);

// The sRGB hex colour ("#rrggbb") as XYZ with the sRGB white at Y = 1.
Xyz srgbHexToXyz(const std::string& hex);
Xyz labToXyz(const Lab& lab, const Xyz& white);

}  // namespace svr
