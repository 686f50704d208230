// TIFF stacks (a multi-page .tif) read through the whole loader: libtiff's directory and strip or
// tile decoding, svr's page checks, the budget check.
#include "tests/fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return svr::fuzz::loadVolumeInput("input.tif", data, size);
}
