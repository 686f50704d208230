// DICOM series: the input is one file of a series folder, read through the whole loader (GDCM's
// parse and pixel decoding, svr's series checks, the axis map and rescaling). A fixed good slice
// beside it (fuzz_support.h) makes the series checks (position, spacing, series UID) run.
#include "tests/fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return svr::fuzz::loadFolderInput("series/IM0002.dcm", data, size);
}
