#pragma once
// The light-independent image a renderer makes once (design.md §5): per pixel the k-channel
// scattered radiance S and, where a background or later compositing needs it, the
// transmittance T (k channels, or one scalar channel for achromatic absorbers). Planar: each
// channel is one contiguous width×height plane, row 0 at the top, so relighting streams
// through memory and vectorises across pixels. Samples are float, or half to halve the bytes.

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

namespace svr {

// A vector's allocator that leaves new floats unset (default-initialised), so that an image
// its renderer writes in full is not also zeroed first.
template <class T>
struct UnsetAllocator : std::allocator<T> {
  template <class U>
  struct rebind {
    using other = UnsetAllocator<U>;
  };
  UnsetAllocator() = default;
  template <class U>
  UnsetAllocator(const UnsetAllocator<U>&) {}
  template <class U>
  void construct(U* p) {
    ::new (static_cast<void*>(p)) U;
  }
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
};

enum class SampleStorage { kFloat, kHalf };

class LightIndependentImage {
 public:
  LightIndependentImage() = default;
  // Throws svr::Error for non-positive or absurd sizes.
  LightIndependentImage(int width, int height, int channels, int transmittance_channels,
                        SampleStorage storage = SampleStorage::kFloat);
  // Float planes whose samples are unset: for a renderer that writes every sample (shear-warp's
  // warp), which would otherwise pay for zeroing the image first.
  static LightIndependentImage unset(int width, int height, int channels,
                                     int transmittance_channels);
  // Bytes of such an image's planes as floats, for memory-budget checks before allocating.
  static std::uint64_t bytesFor(int width, int height, int channels, int transmittance_channels) {
    return std::uint64_t(width) * std::uint64_t(height) *
           std::uint64_t(channels + transmittance_channels) * sizeof(float);
  }

  int width() const { return width_; }
  int height() const { return height_; }
  size_t pixels() const { return static_cast<size_t>(width_) * height_; }
  int channels() const { return channels_; }
  int transmittanceChannels() const { return transmittance_channels_; }
  int planes() const { return channels_ + transmittance_channels_; }
  SampleStorage storage() const { return storage_; }

  // Plane p: 0..channels-1 are S, then the transmittance planes.
  std::span<float> planeFloat(int p);
  std::span<const float> planeFloat(int p) const;
  std::span<std::uint16_t> planeHalf(int p);
  std::span<const std::uint16_t> planeHalf(int p) const;
  const void* planeData(int p) const;

  // Sample access in float whatever the storage (slow path: tests, I/O, metrics).
  float scattered(int c, int x, int y) const { return sample(c, x, y); }
  float transmittance(int c, int x, int y) const { return sample(channels_ + c, x, y); }
  float sample(int plane, int x, int y) const;
  void setSample(int plane, int x, int y, float value);

  LightIndependentImage withStorage(SampleStorage storage) const;
  size_t bytes() const;

 private:
  struct Shape {};  // the size checked and set, no samples allocated
  LightIndependentImage(int width, int height, int channels, int transmittance_channels,
                        SampleStorage storage, Shape);

  int width_ = 0, height_ = 0, channels_ = 0, transmittance_channels_ = 0;
  SampleStorage storage_ = SampleStorage::kFloat;
  std::vector<float, UnsetAllocator<float>> float_samples_;
  std::vector<std::uint16_t> half_samples_;
};

// IEEE 754 binary16 conversions (round to nearest even), for the portable paths.
std::uint16_t floatToHalf(float value);
float halfToFloat(std::uint16_t bits);

}  // namespace svr
