// Spectrum CSV tables, and every column resampled onto the standard grid both ways a caller
// may ask (an error outside the measured range, or zero there).
#include <string>

#include "spectral/csv_table.h"
#include "base/error.h"
#include "spectral/wavelength_grid.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const svr::WavelengthGrid grid = svr::WavelengthGrid::standard();
  try {
    const svr::CsvTable table =
        svr::parseCsvTable(std::string(reinterpret_cast<const char*>(data), size), "input.csv");
    for (int c = 0; c < static_cast<int>(table.names.size()); ++c) {
      for (const auto outside : {svr::OutsideRange::kZero, svr::OutsideRange::kError}) {
        try {
          table.spectrum(c, grid, outside);
        } catch (const svr::Error&) {
        }
      }
    }
  } catch (const svr::Error&) {
  }
  return 0;
}
