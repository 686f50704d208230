#include "renderers/render/renderer.h"

#include <fmt/format.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <span>

#include "base/error.h"

namespace svr {
namespace {

// Whether no value is NaN or ±Inf (exponent bits all set), without a branch a value: the
// compiler vectorises this, where std::isfinite with an early exit took about nine
// instructions a value, a few per cent of a shear-warp frame. The rare failure is then looked
// for value by value.
// Split over the render's threads (a frame's last serial step otherwise: 2 % of a shear-warp
// frame at one thread, twice that share at two).
bool allFinite(std::span<const float> values) {
  std::uint32_t any = 0;
  const std::int64_t n = static_cast<std::int64_t>(values.size());
  const float* data = values.data();
#pragma omp parallel for simd reduction(| : any) schedule(static) if (n > (std::int64_t{1} << 18))
  for (std::int64_t i = 0; i < n; ++i) {
    std::uint32_t bits;
    std::memcpy(&bits, data + i, sizeof bits);
    any |= static_cast<std::uint32_t>((bits & 0x7f800000u) == 0x7f800000u);
  }
  return any == 0;
}

}  // namespace

std::optional<std::string> unsupportedBy(const BackendInfo& backend, const Camera& camera, int k,
                                         int t_channels) {
  const BackendCapabilities& s = backend.supports;
  if (!s.perspective && !camera.orthographic())
    return fmt::format("{} renders orthographic cameras only (the camera has fov {}°)",
                       backend.name, camera.fov_degrees);
  if (k > s.max_channels)
    return fmt::format("{}: {} channels exceed the supported {}", backend.name, k, s.max_channels);
  if (t_channels > 1 && !s.spectral_transmittance)
    return fmt::format("{} supports scalar transmittance only ({} channels asked)", backend.name,
                       t_channels);
  return std::nullopt;
}

LightIndependentImage Renderer::render(const RenderRequest& request,
                                       const ProgressFn& progress) const {
  const BackendInfo& backend = info();
  if (const auto why = unsupportedBy(backend, request.camera, request.volume.k,
                                     request.volume.t_channels))
    throw Error(*why);
  if (request.volume.brick && !backend.supports.bricks)
    throw Error(fmt::format("{} cannot render one brick of a distributed render", backend.name));
  const BackendOptions options = readBackendOptions(backend.options, request.options,
                                                    backend.name, request.options_source);
  const ClassifiedVolume& cv = request.volume;
  const std::uint64_t working = workingBytes(request, options);
  checkMemoryBudget(
      LightIndependentImage::bytesFor(request.width, request.height, cv.k, cv.t_channels) +
          working,
      request.memory_budget,
      fmt::format("{}: a {}×{} image of {} + {} channels{}", backend.name, request.width,
                  request.height, cv.k, cv.t_channels,
                  working > 0 ? " and its working memory" : ""));
  ProgressCounter counter(progress, request.stop);
  LightIndependentImage image = renderImpl(request, options, counter);
  if (counter.stopped()) throw Cancelled(fmt::format("{}: the render was stopped", backend.name));
  counter.set(1.0);
  requireFinite(image, request);  // numeric failure is reported, never written out
  return image;
}

void Renderer::requireFinite(const LightIndependentImage& image,
                             const RenderRequest& request) const {
  // The planes are one array.
  if (allFinite({image.planeFloat(0).data(), image.pixels() * image.planes()})) return;
  for (int p = 0; p < image.planes(); ++p) {
    const auto plane = image.planeFloat(p);
    if (allFinite(plane)) continue;
    for (std::size_t i = 0; i < plane.size(); ++i)
      if (!std::isfinite(plane[i]))
        throw Error(fmt::format("{}: non-finite value {} in {} channel {} at pixel ({}, {})",
                                name(), plane[i], p < request.volume.k ? "S" : "T",
                                p < request.volume.k ? p : p - request.volume.k,
                                i % image.width(), i / image.width()));
  }
}

}  // namespace svr
