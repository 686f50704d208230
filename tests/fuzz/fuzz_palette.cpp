// Palette JSON in both forms that read it: the plain palette (lights × materials, for
// "model no more than a scene needs") and the design palette (cells, metamers, options).
#include <string>

#include "spectral/design_palette.h"
#include "base/error.h"
#include "base/json_reader.h"
#include "spectral/palette.h"
#include "tests/fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string file = svr::fuzz::scratchDir() + "/palette.json";
  nlohmann::json json;
  try {
    json = svr::JsonReader::parse(std::string(reinterpret_cast<const char*>(data), size), file);
  } catch (const svr::Error&) {
    return 0;
  }
  try {
    svr::parsePalette(json, file, svr::fuzz::library());
  } catch (const svr::Error&) {
  }
  try {
    svr::parseDesignPalette(json, file, svr::fuzz::library(), svr::fuzz::observer());
  } catch (const svr::Error&) {
  }
  return 0;
}
