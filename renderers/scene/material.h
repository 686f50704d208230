#pragma once
// A material of the spectral transfer function (paper §3.1, design.md §5): what it scatters
// (a reflectance spectrum, plus a flat-white specular weight) and how it absorbs (an absorption
// spectrum, or achromatic), with opacity given per unit world length so that every backend and
// every step size renders the same thing.

#include <optional>
#include <string>

#include "spectral/spectrum.h"

namespace svr {

struct Material {
  std::string name;
  Spectrum reflectance;
  // Relative spectral absorption A(λ), normalised to mean 1 over the grid; the transmission
  // over a step Δs is exp(−Δs·σ·A(λ)). Empty: achromatic, exp(−Δs·σ) at every wavelength.
  std::optional<Spectrum> absorption;
  double extinction = 0.0;  // σ per unit world length
  double specular = 0.0;    // weight of the flat-white specular term
  bool xray = false;        // scatters but does not occlude (paper §3.1)
};

}  // namespace svr
