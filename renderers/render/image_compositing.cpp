#include "renderers/render/image_compositing.h"

#include <fmt/format.h>

#include "base/error.h"

namespace svr {

void compositeOver(const LightIndependentImage& front, LightIndependentImage& back) {
  if (front.width() != back.width() || front.height() != back.height() ||
      front.channels() != back.channels() ||
      front.transmittanceChannels() != back.transmittanceChannels())
    throw Error(fmt::format("compositing: a {}×{} image of {} + {} channels over one of {}×{} "
                            "and {} + {}",
                            front.width(), front.height(), front.channels(),
                            front.transmittanceChannels(), back.width(), back.height(),
                            back.channels(), back.transmittanceChannels()));
  if (front.storage() != SampleStorage::kFloat || back.storage() != SampleStorage::kFloat)
    throw Error("compositing: images must hold float samples");
  const int k = front.channels(), kt = front.transmittanceChannels();
  const std::size_t n = front.pixels();
  for (int c = 0; c < k; ++c) {
    const float* sf = front.planeFloat(c).data();
    const float* tf = front.planeFloat(k + (kt > 1 ? c : 0)).data();
    float* sb = back.planeFloat(c).data();
    for (std::size_t i = 0; i < n; ++i) sb[i] = sf[i] + tf[i] * sb[i];
  }
  for (int c = 0; c < kt; ++c) {
    const float* tf = front.planeFloat(k + c).data();
    float* tb = back.planeFloat(k + c).data();
    for (std::size_t i = 0; i < n; ++i) tb[i] = tf[i] * tb[i];
  }
}

void compositeOverInterleaved(const float* front, float* back, std::size_t pixels, int k,
                              int t_channels) {
  const std::size_t stride = static_cast<std::size_t>(k + t_channels);
  for (std::size_t i = 0; i < pixels; ++i) {
    const float* f = front + i * stride;
    float* b = back + i * stride;
    for (int c = 0; c < k; ++c) b[c] = f[c] + f[k + (t_channels > 1 ? c : 0)] * b[c];
    for (int c = 0; c < t_channels; ++c) b[k + c] = f[k + c] * b[k + c];
  }
}

std::vector<float> interleavedSamples(const LightIndependentImage& image) {
  const int planes = image.planes();
  const std::size_t n = image.pixels();
  std::vector<float> out(n * planes);
  for (int p = 0; p < planes; ++p) {
    const LightIndependentImage& im = image;
    for (std::size_t i = 0; i < n; ++i)
      out[i * planes + p] = im.storage() == SampleStorage::kFloat
                                ? im.planeFloat(p)[i]
                                : halfToFloat(im.planeHalf(p)[i]);
  }
  return out;
}

LightIndependentImage fromInterleaved(std::span<const float> samples, int width, int height,
                                      int k, int t_channels) {
  LightIndependentImage image(width, height, k, t_channels);
  const int planes = k + t_channels;
  const std::size_t n = image.pixels();
  if (samples.size() != n * planes)
    throw Error(fmt::format("compositing: {} samples for a {}×{} image of {} planes",
                            samples.size(), width, height, planes));
  for (int p = 0; p < planes; ++p) {
    float* plane = image.planeFloat(p).data();
    for (std::size_t i = 0; i < n; ++i) plane[i] = samples[i * planes + p];
  }
  return image;
}

}  // namespace svr
