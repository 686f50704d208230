#pragma once
// Named spectra shipped in data/spectra: CIE illuminants (A, D50, D65, F1–F12, the LED series),
// equal-energy E, the 24 ColorChecker patches, the 1269 Munsell matte chips and haemoglobin
// absorbance. Names:
//   lights        "A", "D50", "D65", "E", "F1".."F12", "LED-B1".."LED-V2"
//   ColorChecker  "ColorChecker/dark skin" … "ColorChecker/black 2 (1.5 D)"
//   Munsell       "Munsell/2.5R 9/2" (the Munsell notation of the chip)
//   haemoglobin   "HbO2", "Hb": decadic molar extinction, both divided by the peak of HbO2 over
//                 380–780 nm, so their ratio is kept and the shape is an absorbance in [0, 1]

#include <map>
#include <string>
#include <vector>

#include "spectral/spectrum.h"

namespace svr {

enum class SpectrumKind { kLight, kReflectance, kAbsorbance };

class SpectrumLibrary {
 public:
  static SpectrumLibrary load(const std::string& data_dir, const WavelengthGrid& grid);

  // Throws svr::Error for an unknown name, listing the closest known names.
  const Spectrum& get(const std::string& name) const;
  bool contains(const std::string& name) const { return entries_.count(name) > 0; }
  SpectrumKind kind(const std::string& name) const;
  std::vector<std::string> closestNames(const std::string& name, int count) const;

  // Adds a spectrum under a new name (a scene's designed palette, say); it must be on grid().
  void define(const std::string& name, Spectrum s, SpectrumKind kind) {
    add(name, std::move(s), kind);
  }

  const WavelengthGrid& grid() const { return grid_; }
  const std::vector<std::string>& lightNames() const { return light_names_; }
  const std::vector<std::string>& colorCheckerNames() const { return colorchecker_names_; }
  const std::vector<std::string>& munsellNames() const { return munsell_names_; }
  // Every name, or those of one kind, sorted.
  std::vector<std::string> names() const;
  std::vector<std::string> names(SpectrumKind kind) const;

 private:
  struct Entry {
    Spectrum spectrum;
    SpectrumKind kind;
  };
  void add(const std::string& name, Spectrum s, SpectrumKind kind);

  WavelengthGrid grid_;
  std::map<std::string, Entry> entries_;
  std::vector<std::string> light_names_, colorchecker_names_, munsell_names_;
};

// Case-insensitive Levenshtein distance, for "did you mean" suggestions.
int editDistance(const std::string& a, const std::string& b);

}  // namespace svr
