// NIfTI-1/-2 files (.nii) read through the whole loader: nifticlib's header parse, svr's checks,
// the axis map and scaling, the budget check and the payload reader.
#include "tests/fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return svr::fuzz::loadVolumeInput("input.nii", data, size);
}
