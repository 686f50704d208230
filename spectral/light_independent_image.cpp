#include "spectral/light_independent_image.h"

#include <fmt/format.h>

#include <bit>
#include <cstring>

#include "base/error.h"

namespace svr {

LightIndependentImage::LightIndependentImage(int width, int height, int channels,
                                             int transmittance_channels, SampleStorage storage)
    : LightIndependentImage(width, height, channels, transmittance_channels, storage, Shape{}) {
  const size_t n = pixels() * planes();
  if (storage == SampleStorage::kFloat)
    float_samples_.assign(n, 0.0f);
  else
    half_samples_.assign(n, 0);
}

LightIndependentImage::LightIndependentImage(int width, int height, int channels,
                                             int transmittance_channels, SampleStorage storage,
                                             Shape)
    : width_(width),
      height_(height),
      channels_(channels),
      transmittance_channels_(transmittance_channels),
      storage_(storage) {
  constexpr int kMaxSide = 1 << 15;
  if (width < 1 || height < 1 || width > kMaxSide || height > kMaxSide)
    throw Error(fmt::format("light-independent image: size {}×{} is outside 1..{}", width, height,
                            kMaxSide));
  if (channels < 1 || channels > 4096)
    throw Error(fmt::format("light-independent image: {} channels is outside 1..4096", channels));
  if (transmittance_channels != 0 && transmittance_channels != 1 &&
      transmittance_channels != channels)
    throw Error(fmt::format("light-independent image: {} transmittance channels; expected 0, 1 "
                            "or {}", transmittance_channels, channels));
}

LightIndependentImage LightIndependentImage::unset(int width, int height, int channels,
                                                  int transmittance_channels) {
  LightIndependentImage image(width, height, channels, transmittance_channels,
                              SampleStorage::kFloat, Shape{});
  image.float_samples_.resize(image.pixels() * image.planes());  // unset (UnsetAllocator)
  return image;
}

std::span<float> LightIndependentImage::planeFloat(int p) {
  return {float_samples_.data() + pixels() * p, pixels()};
}
std::span<const float> LightIndependentImage::planeFloat(int p) const {
  return {float_samples_.data() + pixels() * p, pixels()};
}
std::span<std::uint16_t> LightIndependentImage::planeHalf(int p) {
  return {half_samples_.data() + pixels() * p, pixels()};
}
std::span<const std::uint16_t> LightIndependentImage::planeHalf(int p) const {
  return {half_samples_.data() + pixels() * p, pixels()};
}
const void* LightIndependentImage::planeData(int p) const {
  return storage_ == SampleStorage::kFloat ? static_cast<const void*>(planeFloat(p).data())
                                           : static_cast<const void*>(planeHalf(p).data());
}

float LightIndependentImage::sample(int plane, int x, int y) const {
  const size_t i = pixels() * plane + static_cast<size_t>(y) * width_ + x;
  return storage_ == SampleStorage::kFloat ? float_samples_[i] : halfToFloat(half_samples_[i]);
}

void LightIndependentImage::setSample(int plane, int x, int y, float value) {
  const size_t i = pixels() * plane + static_cast<size_t>(y) * width_ + x;
  if (storage_ == SampleStorage::kFloat)
    float_samples_[i] = value;
  else
    half_samples_[i] = floatToHalf(value);
}

LightIndependentImage LightIndependentImage::withStorage(SampleStorage storage) const {
  LightIndependentImage out(width_, height_, channels_, transmittance_channels_, storage);
  const size_t n = pixels() * planes();
  for (size_t i = 0; i < n; ++i) {
    const float v = storage_ == SampleStorage::kFloat ? float_samples_[i]
                                                      : halfToFloat(half_samples_[i]);
    if (storage == SampleStorage::kFloat)
      out.float_samples_[i] = v;
    else
      out.half_samples_[i] = floatToHalf(v);
  }
  return out;
}

size_t LightIndependentImage::bytes() const {
  return pixels() * planes() * (storage_ == SampleStorage::kFloat ? 4 : 2);
}

std::uint16_t floatToHalf(float value) {
  const std::uint32_t f = std::bit_cast<std::uint32_t>(value);
  const std::uint32_t sign = (f >> 16) & 0x8000u;
  const std::uint32_t abs = f & 0x7fffffffu;
  if (abs >= 0x7f800000u)  // Inf or NaN (NaN keeps a payload bit)
    return static_cast<std::uint16_t>(sign | 0x7c00u | (abs > 0x7f800000u ? 0x200u : 0u));
  if (abs >= 0x477ff000u) return static_cast<std::uint16_t>(sign | 0x7c00u);  // overflow → Inf
  if (abs < 0x38800000u) {  // subnormal half or zero: scale into place and round to even
    const float scaled = std::bit_cast<float>(abs) * 16777216.0f;  // 2^24
    std::uint32_t m = static_cast<std::uint32_t>(scaled);
    const float rem = scaled - static_cast<float>(m);
    if (rem > 0.5f || (rem == 0.5f && (m & 1u))) ++m;
    return static_cast<std::uint16_t>(sign | m);
  }
  const std::uint32_t mantissa = abs & 0x7fffffu;
  std::uint32_t h = ((abs >> 23) - 112u) << 10 | (mantissa >> 13);
  const std::uint32_t rest = mantissa & 0x1fffu;
  if (rest > 0x1000u || (rest == 0x1000u && (h & 1u))) ++h;  // carries into the exponent correctly
  return static_cast<std::uint16_t>(sign | h);
}

float halfToFloat(std::uint16_t bits) {
  const std::uint32_t sign = static_cast<std::uint32_t>(bits & 0x8000u) << 16;
  const std::uint32_t exponent = (bits >> 10) & 0x1fu;
  const std::uint32_t mantissa = bits & 0x3ffu;
  if (exponent == 0) {  // zero or subnormal
    const float v = static_cast<float>(mantissa) * (1.0f / 16777216.0f);
    return sign ? -v : v;
  }
  if (exponent == 31)
    return std::bit_cast<float>(sign | 0x7f800000u | (mantissa << 13));
  return std::bit_cast<float>(sign | ((exponent + 112u) << 23) | (mantissa << 13));
}

}  // namespace svr
