#include "spectral/spectrum_spec.h"

#include <fmt/format.h>

#include "spectral/csv_table.h"
#include "base/error.h"

namespace svr {

Spectrum parseSpectrumSpec(const JsonReader& spec, const SpectrumLibrary& library,
                           const std::filesystem::path& base_dir) {
  auto named = [&](const std::string& name) {
    try {
      return library.get(name);
    } catch (const Error& e) {
      spec.fail(e.what());
    }
  };
  if (spec.isString()) return named(spec.string());
  if (!spec.isObject())
    spec.fail(fmt::format("expected a spectrum (a library name or an object), got {}",
                          spec.json().dump(-1, ' ', false, nlohmann::json::error_handler_t::replace)));
  for (const char* key : {"name", "scale", "library", "csv", "column", "wavelengths", "values",
                          "constant"})
    spec.find(key);  // "name" is the caller's; the rest are read below
  spec.rejectUnknownKeys();
  const double scale = spec.number("scale", 1.0, 0.0);
  std::optional<Spectrum> s;
  int forms = 0;
  if (auto lib = spec.find("library")) s = named(lib->string()), ++forms;
  if (auto csv = spec.find("csv")) {
    ++forms;
    // The table's own errors name the CSV file; add which input file and key named it.
    const CsvTable table = [&] {
      try {
        return loadCsvTable((base_dir / csv->string()).string());
      } catch (const Error& e) {
        csv->fail(e.what());
      }
    }();
    const std::string column = spec.at("column").string();
    const int c = table.columnIndex(column);
    if (c < 0)
      spec.at("column").fail(fmt::format("'{}' is not a column of {}", column, table.source));
    try {
      s = table.spectrum(c, library.grid(), OutsideRange::kError);
    } catch (const Error& e) {
      spec.fail(e.what());
    }
  }
  if (auto wl = spec.find("wavelengths")) {
    ++forms;
    const auto w = wl->numbers(0);
    const auto v = spec.at("values").numbers(0);
    // resample's errors already start with spec.where(): file and key.
    s = Spectrum::resample(library.grid(), w, v, OutsideRange::kError, spec.where());
  }
  if (auto c = spec.find("constant")) {
    ++forms;
    s = Spectrum::constant(library.grid(), c->number());
  }
  if (forms != 1)
    spec.fail("give exactly one of 'library', 'csv' (+ 'column'), 'wavelengths' (+ 'values') or "
              "'constant'");
  return *s * scale;
}

}  // namespace svr
