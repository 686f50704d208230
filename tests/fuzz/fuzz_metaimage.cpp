// MetaImage headers (.mha with LOCAL voxels, or naming the scratch folder's data files), read
// through the whole loader: key parsing, the budget check and the raw/zlib payload reader.
#include "tests/fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return svr::fuzz::loadVolumeInput("input.mha", data, size);
}
