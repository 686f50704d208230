// MetaImage headers (.mha with LOCAL voxels, or naming the scratch folder's data files), read
// through the whole loader: key parsing, the budget check and the raw/zlib payload reader.
#include "renderers/core/volume_io.h"
#include "spectral/error.h"
#include "tests/fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = svr::fuzz::writeInput("input.mha", data, size);
  svr::VolumeLoadOptions options;
  options.memory_budget = svr::fuzz::kMemoryBudget;
  try {
    svr::loadVolume(path, options);
  } catch (const svr::Error&) {
  }
  return 0;
}
