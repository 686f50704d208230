// Light-independent OpenEXR images (S.nn / T.nn channels, svr:* attributes) as `svr relight`
// reads them. OpenImageIO and OpenEXR are not instrumented, so coverage steers only through
// svr's checks; the sanitizers still catch what goes wrong in the libraries under our calls.
#include <map>
#include <string>

#include "harness/image_files.h"
#include "base/error.h"
#include "tests/fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = svr::fuzz::writeInput("input.exr", data, size);
  std::map<std::string, std::string> attributes;
  try {
    svr::readLightIndependentExr(path, &attributes);
  } catch (const svr::Error&) {
  }
  return 0;
}
