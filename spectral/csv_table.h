#pragma once
// Spectral tables in CSV: a header row, wavelength_nm in column 1, one spectrum per further
// column (the format of data/spectra, see its README).

#include <string>
#include <vector>

#include "spectral/spectrum.h"

namespace svr {

struct CsvTable {
  std::string source;                       // file name, for error messages
  std::vector<std::string> names;           // column headers after the wavelength column
  std::vector<double> wavelengths_nm;       // strictly increasing
  std::vector<std::vector<double>> columns; // columns[j][i] = value of names[j] at row i

  int columnIndex(const std::string& name) const;  // -1 when absent
  Spectrum spectrum(int column, const WavelengthGrid& grid, OutsideRange outside) const;
};

// Parses CSV text; `source` names it in errors. Throws svr::Error naming the row and column of
// any malformed, non-finite, duplicated or out-of-order entry.
CsvTable parseCsvTable(const std::string& text, const std::string& source);
CsvTable loadCsvTable(const std::string& path);

}  // namespace svr
