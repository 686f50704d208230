#include "spectral/csv_table.h"

#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <sstream>

#include "base/error.h"
#include "base/text_file.h"

namespace svr {
namespace {

std::vector<std::string> splitFields(const std::string& line) {
  std::vector<std::string> fields;
  std::string field;
  std::istringstream in(line);
  while (std::getline(in, field, ',')) fields.push_back(field);
  if (!line.empty() && line.back() == ',') fields.emplace_back();
  return fields;
}

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return {};
  const auto e = s.find_last_not_of(" \t\r");
  return s.substr(b, e - b + 1);
}

double parseNumber(const std::string& text, const std::string& where) {
  const std::string t = trim(text);
  double value = 0.0;
  const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), value);
  if (t.empty() || ec != std::errc() || end != t.data() + t.size())
    throw Error(fmt::format("{}: '{}' is not a number", where, t));
  if (!std::isfinite(value)) throw Error(fmt::format("{}: value '{}' is not finite", where, t));
  return value;
}

}  // namespace

int CsvTable::columnIndex(const std::string& name) const {
  for (size_t j = 0; j < names.size(); ++j)
    if (names[j] == name) return static_cast<int>(j);
  return -1;
}

Spectrum CsvTable::spectrum(int column, const WavelengthGrid& grid, OutsideRange outside) const {
  return Spectrum::resample(grid, wavelengths_nm, columns.at(column), outside,
                            fmt::format("{} column '{}'", source, names.at(column)));
}

CsvTable parseCsvTable(const std::string& text, const std::string& source) {
  CsvTable table;
  table.source = source;
  std::istringstream in(text);
  std::string line;
  int row = 0;
  size_t width = 0;
  while (std::getline(in, line)) {
    ++row;
    if (trim(line).empty()) continue;
    auto fields = splitFields(line);
    if (table.names.empty() && width == 0) {
      width = fields.size();
      if (width < 2)
        throw Error(fmt::format("{}: header row has {} column(s); need wavelength_nm and at least "
                                "one spectrum", source, width));
      for (size_t j = 1; j < width; ++j) {
        std::string name = trim(fields[j]);
        if (name.empty()) throw Error(fmt::format("{}: header column {} is empty", source, j + 1));
        if (table.columnIndex(name) >= 0)
          throw Error(fmt::format("{}: header names column '{}' twice", source, name));
        table.names.push_back(name);
      }
      table.columns.resize(width - 1);
      continue;
    }
    if (fields.size() != width)
      throw Error(fmt::format("{}: row {} has {} fields, the header has {}", source, row,
                              fields.size(), width));
    const double wl = parseNumber(fields[0], fmt::format("{} row {} column 1", source, row));
    if (!table.wavelengths_nm.empty()) {
      const double prev = table.wavelengths_nm.back();
      if (wl == prev)
        throw Error(fmt::format("{}: row {} repeats wavelength {} nm", source, row, wl));
      if (wl < prev)
        throw Error(fmt::format("{}: row {} is out of order: {} nm after {} nm", source, row, wl,
                                prev));
    }
    table.wavelengths_nm.push_back(wl);
    for (size_t j = 1; j < width; ++j)
      table.columns[j - 1].push_back(parseNumber(
          fields[j], fmt::format("{} row {} column '{}'", source, row, table.names[j - 1])));
  }
  if (width == 0) throw Error(fmt::format("{}: empty file, expected a header row", source));
  if (table.wavelengths_nm.size() < 2)
    throw Error(fmt::format("{}: {} data row(s); a spectrum needs at least 2", source,
                            table.wavelengths_nm.size()));
  return table;
}

CsvTable loadCsvTable(const std::string& path) {
  return parseCsvTable(readTextFile(path, "spectrum table"), path);
}

}  // namespace svr
