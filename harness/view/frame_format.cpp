#include "harness/view/frame_format.h"

#include <bit>
#include <cstdint>

namespace svr {

std::string encodeFrame(const LightIndependentImage& image, nlohmann::json header) {
  const bool half = image.storage() == SampleStorage::kHalf;
  header["samples"] = half ? "half" : "float";
  std::string json = header.dump();
  while ((8 + json.size()) % 4 != 0) json += ' ';
  const size_t plane_bytes = image.pixels() * (half ? 2 : 4);
  std::string out;
  out.reserve(8 + json.size() + plane_bytes * image.planes());
  out += "SVRI";
  const std::uint32_t n = static_cast<std::uint32_t>(json.size());
  for (int b = 0; b < 4; ++b) out += static_cast<char>((n >> (8 * b)) & 0xff);
  out += json;
  // The format is little-endian, as are the hosts svr builds on and every browser's typed
  // arrays: the planes go out as stored.
  static_assert(std::endian::native == std::endian::little);
  for (int p = 0; p < image.planes(); ++p)
    out.append(static_cast<const char*>(image.planeData(p)), plane_bytes);
  return out;
}

}  // namespace svr
