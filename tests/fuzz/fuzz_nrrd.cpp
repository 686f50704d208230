// NRRD headers (attached .nrrd or detached, pointing at the scratch folder's data files), read
// through the whole loader: pre-scan, teem, the budget check and the raw/gzip payload reader.
#include "tests/fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return svr::fuzz::loadVolumeInput("input.nrrd", data, size);
}
