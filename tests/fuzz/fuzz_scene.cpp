// Scene JSON, parsed strictly (duplicate keys, depth) and then read key by key: volumes
// (procedural or the scratch folder's files, under a small memory budget), materials, transfer
// functions, lights, mixes, camera, image, render options, shading and the colour model's name.
#include <string>

#include "renderers/scene/scene.h"
#include "base/error.h"
#include "base/json_reader.h"
#include "tests/fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string file = svr::fuzz::scratchDir() + "/scene.json";
  svr::VolumeLoadOptions options;
  options.memory_budget = svr::fuzz::kMemoryBudget;
  try {
    const nlohmann::json json =
        svr::JsonReader::parse(std::string(reinterpret_cast<const char*>(data), size), file);
    svr::parseScene(json, file, svr::fuzz::library(), options);
  } catch (const svr::Error&) {
  }
  return 0;
}
