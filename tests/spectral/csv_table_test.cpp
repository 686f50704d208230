#include "spectral/csv_table.h"

#include <gtest/gtest.h>

#include "base/error.h"

namespace svr {
namespace {

std::string errorOf(const std::string& text) {
  try {
    parseCsvTable(text, "x.csv");
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(CsvTable, ParsesHeaderAndColumns) {
  const CsvTable t = parseCsvTable("wavelength_nm,a,b\n400,1,2\n410,3,4\n", "x.csv");
  ASSERT_EQ(t.names.size(), 2u);
  EXPECT_EQ(t.names[1], "b");
  EXPECT_EQ(t.columnIndex("b"), 1);
  EXPECT_EQ(t.columnIndex("c"), -1);
  EXPECT_EQ(t.wavelengths_nm[1], 410);
  EXPECT_EQ(t.columns[1][1], 4);
}

TEST(CsvTable, NamesTheRowAndColumnOfEveryDefect) {
  EXPECT_EQ(errorOf("wavelength_nm,a\n400,1\n400,2\n"), "x.csv: row 3 repeats wavelength 400 nm");
  EXPECT_EQ(errorOf("wavelength_nm,a\n410,1\n400,2\n"),
            "x.csv: row 3 is out of order: 400 nm after 410 nm");
  EXPECT_EQ(errorOf("wavelength_nm,a\n400,nan\n410,2\n"),
            "x.csv row 2 column 'a': value 'nan' is not finite");
  EXPECT_EQ(errorOf("wavelength_nm,a\n400,1,2\n"), "x.csv: row 2 has 3 fields, the header has 2");
  EXPECT_EQ(errorOf("wavelength_nm,a\n400,abc\n"), "x.csv row 2 column 'a': 'abc' is not a number");
  EXPECT_EQ(errorOf(""), "x.csv: empty file, expected a header row");
  EXPECT_EQ(errorOf("wavelength_nm,a,a\n400,1,1\n"), "x.csv: header names column 'a' twice");
  EXPECT_EQ(errorOf("wavelength_nm,a\n400,1\n"), "x.csv: 1 data row(s); a spectrum needs at least 2");
}

TEST(CsvTable, MissingFileNamesThePath) {
  try {
    loadCsvTable("/nonexistent/spectra.csv");
    FAIL();
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "/nonexistent/spectra.csv: cannot open spectrum table: no such file");
  }
}

TEST(CsvTable, ADeviceIsRefusedNotReadForever) {
  try {
    loadCsvTable("/dev/zero");
    FAIL();
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "/dev/zero: cannot open spectrum table: not a regular file");
  }
}

}  // namespace
}  // namespace svr
