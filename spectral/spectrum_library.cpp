#include "spectral/spectrum_library.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cctype>

#include "spectral/csv_table.h"
#include "base/error.h"

namespace svr {

int editDistance(const std::string& a, const std::string& b) {
  std::vector<int> prev(b.size() + 1), cur(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) prev[j] = static_cast<int>(j);
  for (size_t i = 1; i <= a.size(); ++i) {
    cur[0] = static_cast<int>(i);
    for (size_t j = 1; j <= b.size(); ++j) {
      const bool same = std::tolower(static_cast<unsigned char>(a[i - 1])) ==
                        std::tolower(static_cast<unsigned char>(b[j - 1]));
      cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + (same ? 0 : 1)});
    }
    std::swap(prev, cur);
  }
  return prev[b.size()];
}

SpectrumLibrary SpectrumLibrary::load(const std::string& data_dir, const WavelengthGrid& grid) {
  validate(grid);
  SpectrumLibrary lib;
  lib.grid_ = grid;
  const std::string dir = data_dir + "/spectra/";
  for (const char* file : {"cie_illuminants_A_D50_D65_5nm.csv", "cie_illuminants_F1-F12_5nm.csv",
                           "cie_illuminants_LED_5nm.csv"}) {
    const CsvTable t = loadCsvTable(dir + file);
    for (size_t j = 0; j < t.names.size(); ++j) {
      lib.add(t.names[j], t.spectrum(static_cast<int>(j), grid, OutsideRange::kError),
              SpectrumKind::kLight);
      lib.light_names_.push_back(t.names[j]);
    }
  }
  lib.add("E", Spectrum::constant(grid, 100.0), SpectrumKind::kLight);
  lib.light_names_.push_back("E");

  const CsvTable cc = loadCsvTable(dir + "colorchecker24_ohta1997_5nm.csv");
  for (size_t j = 0; j < cc.names.size(); ++j) {
    const std::string name = "ColorChecker/" + cc.names[j];
    lib.add(name, cc.spectrum(static_cast<int>(j), grid, OutsideRange::kError),
            SpectrumKind::kReflectance);
    lib.colorchecker_names_.push_back(name);
  }
  const CsvTable mu = loadCsvTable(dir + "munsell_matt_uef_1269_5nm.csv");
  for (size_t j = 0; j < mu.names.size(); ++j) {
    const std::string name = "Munsell/" + mu.names[j];
    lib.add(name, mu.spectrum(static_cast<int>(j), grid, OutsideRange::kError),
            SpectrumKind::kReflectance);
    lib.munsell_names_.push_back(name);
  }

  const CsvTable hb = loadCsvTable(dir + "hemoglobin_molar_extinction_prahl.csv");
  Spectrum oxy = hb.spectrum(hb.columnIndex("HbO2_cm-1_per_M"), grid, OutsideRange::kError);
  Spectrum deoxy = hb.spectrum(hb.columnIndex("Hb_cm-1_per_M"), grid, OutsideRange::kError);
  const double peak = oxy.values().maxCoeff();
  lib.add("HbO2", oxy * (1.0 / peak), SpectrumKind::kAbsorbance);
  lib.add("Hb", deoxy * (1.0 / peak), SpectrumKind::kAbsorbance);
  return lib;
}

void SpectrumLibrary::add(const std::string& name, Spectrum s, SpectrumKind kind) {
  entries_.insert_or_assign(name, Entry{std::move(s), kind});
}

std::vector<std::string> SpectrumLibrary::closestNames(const std::string& name, int count) const {
  // Library names are short; scoring only the first 64 characters of what was typed keeps a
  // long garbage name (a fuzzed scene, a pasted path) from costing |name| × |known| per entry.
  const std::string typed = name.substr(0, 64);
  std::vector<std::pair<int, const std::string*>> scored;
  scored.reserve(entries_.size());
  for (const auto& [known, entry] : entries_) {
    int d = editDistance(typed, known);
    // A name typed without its family prefix ("dark skin") should still find it.
    const auto slash = known.find('/');
    if (slash != std::string::npos)
      d = std::min(d, editDistance(typed, known.substr(slash + 1)) + 1);
    scored.emplace_back(d, &known);
  }
  const auto shown = std::min<std::size_t>(std::max(count, 0), scored.size());
  std::partial_sort(scored.begin(), scored.begin() + shown, scored.end(),
                    [](const auto& a, const auto& b) {
                      return a.first != b.first ? a.first < b.first : *a.second < *b.second;
                    });
  std::vector<std::string> out;
  for (std::size_t i = 0; i < shown; ++i) out.push_back(*scored[i].second);
  return out;
}

const Spectrum& SpectrumLibrary::get(const std::string& name) const {
  auto it = entries_.find(name);
  if (it == entries_.end())
    throw Error(fmt::format("unknown spectrum '{}'; closest known names: {}", name,
                            fmt::join(closestNames(name, 5), ", ")));
  return it->second.spectrum;
}

SpectrumKind SpectrumLibrary::kind(const std::string& name) const {
  get(name);
  return entries_.at(name).kind;
}

std::vector<std::string> SpectrumLibrary::names() const {
  std::vector<std::string> out;
  for (const auto& [name, entry] : entries_) out.push_back(name);
  return out;
}

std::vector<std::string> SpectrumLibrary::names(SpectrumKind kind) const {
  std::vector<std::string> out;
  for (const auto& [name, entry] : entries_)
    if (entry.kind == kind) out.push_back(name);
  return out;
}

}  // namespace svr
