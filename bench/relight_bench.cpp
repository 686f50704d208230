// Post-illumination speed: Relight/<size>/<k>/<float|half> relights a size² k-channel
// light-independent image to 8-bit sRGB (RelightLinear: to linear float RGB, for a display
// that encodes sRGB itself); StreamRead/<size>/<k>/<float|half> reads the same
// bytes and does nothing else. Both report bytes/s and frames/s (items/s), so
// relight time / streaming-read time comes from one run (bench/ratios.py prints it).
// RelightOn/<backend>/<size>/<k> is the same 8-bit sRGB frame through every relighter a backend
// offers in the registry (gl: its fragment shader, on OSMesa's llvmpipe here): the image uploaded
// once, then per frame the 3×k matrix as uniforms, one draw and the read-back of the RGB bytes.
#include <benchmark/benchmark.h>
#include <fmt/format.h>

#include <cstdint>
#include <optional>
#include <random>
#include <vector>

#include "spectral/colorimetry.h"
#include "spectral/componentwise_model.h"
#include "base/data_dir.h"
#include "spectral/post_illumination.h"
#include "spectral/spectrum_library.h"
#include "renderers/registry.h"

namespace svr {
namespace {

LightIndependentImage makeImage(int size, int k, SampleStorage storage) {
  LightIndependentImage img(size, size, k, 0);
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> u(0.f, 0.5f);
  for (int c = 0; c < k; ++c)
    for (float& v : img.planeFloat(c)) v = u(rng);
  return img.withStorage(storage);
}

const Observer& observer() {
  static const Observer obs = Observer::cie1931(defaultDataDir(), WavelengthGrid::standard());
  return obs;
}

void relight(benchmark::State& state, int size, int k, SampleStorage storage, bool srgb8,
            std::optional<KernelIsa> isa) {
  const auto image = makeImage(size, k, storage);
  // The kernel depends only on the plane count; a k-band model gives any k.
  const auto model = makeSpectralModel(observer(), k);
  const auto lib = SpectrumLibrary::load(defaultDataDir(), WavelengthGrid::standard());
  PostIlluminator post(*model);
  post.forceKernel({.dynamic_width = false, .isa = isa});
  post.setLight(observer().unitLuminance(lib.get("D65")));
  std::vector<std::uint8_t> out(3 * image.pixels());
  std::vector<float> out_linear(srgb8 ? 0 : 3 * image.pixels());
  for (auto _ : state) {
    if (srgb8)
      post.relightSrgb8(image, out);
    else
      post.relightLinear(image, out_linear);
    benchmark::DoNotOptimize(out.data());
    benchmark::DoNotOptimize(out_linear.data());
    benchmark::ClobberMemory();
  }
  state.SetBytesProcessed(state.iterations() * image.bytes());
  state.SetItemsProcessed(state.iterations());
  state.SetLabel(post.kernelIsa(image));
}

template <typename T>
std::uint64_t sumRows(const LightIndependentImage& image, int k) {
  const int rows = image.height();
  const size_t width = image.width();
  std::uint64_t total = 0;
#pragma omp parallel for schedule(static) reduction(+ : total)
  for (int y = 0; y < rows; ++y) {
    std::uint32_t acc = 0;
    for (int c = 0; c < k; ++c) {
      const auto* plane = static_cast<const std::uint32_t*>(image.planeData(c));
      // Read the row as 32-bit words: a plain pass over the bytes, vectorised.
      const size_t words = width * sizeof(T) / 4;
      const std::uint32_t* row = plane + y * words;
      for (size_t i = 0; i < words; ++i) acc ^= row[i];
    }
    total += acc;
  }
  return total;
}

// A backend's own relighter (the registry's; gl: a fragment shader), same image and light.
void relightOn(benchmark::State& state, const std::string& backend, int size, int k) {
  const auto image = makeImage(size, k, SampleStorage::kFloat);
  const auto model = makeSpectralModel(observer(), k);
  const auto lib = SpectrumLibrary::load(defaultDataDir(), WavelengthGrid::standard());
  PostIlluminator post(*model);
  post.setLight(observer().unitLuminance(lib.get("D65")));
  const auto device = makeRelighter(backend);
  device->setImage(image);
  std::vector<std::uint8_t> out(3 * image.pixels());
  for (auto _ : state) {
    device->relightSrgb8(post.foldedMatrix(image, RelitSpace::kLinearSrgb), out);
    benchmark::DoNotOptimize(out.data());
  }
  state.SetBytesProcessed(state.iterations() * image.bytes());
  state.SetItemsProcessed(state.iterations());
}

void streamRead(benchmark::State& state, int size, int k, SampleStorage storage) {
  const auto image = makeImage(size, k, storage);
  for (auto _ : state) {
    const std::uint64_t s = storage == SampleStorage::kFloat ? sumRows<float>(image, k)
                                                             : sumRows<std::uint16_t>(image, k);
    benchmark::DoNotOptimize(s);
  }
  state.SetBytesProcessed(state.iterations() * image.bytes());
  state.SetItemsProcessed(state.iterations());
}

const bool registered = [] {
  // 256 … 1600 for the scaling curves (bench/scaling/run); 400 and 800 for bench/ratios.py.
  for (int size : {256, 400, 800, 1600})
    for (int k : {3, 4, 6, 8, 16})
      for (auto storage : {SampleStorage::kFloat, SampleStorage::kHalf}) {
        const char* type = storage == SampleStorage::kFloat ? "float" : "half";
        benchmark::RegisterBenchmark(fmt::format("Relight/{}/{}/{}", size, k, type).c_str(),
                                     relight, size, k, storage, true, std::nullopt)
            ->UseRealTime()
            ->Unit(benchmark::kMicrosecond);
        benchmark::RegisterBenchmark(fmt::format("RelightLinear/{}/{}/{}", size, k, type).c_str(),
                                     relight, size, k, storage, false, std::nullopt)
            ->UseRealTime()
            ->Unit(benchmark::kMicrosecond);
        benchmark::RegisterBenchmark(fmt::format("StreamRead/{}/{}/{}", size, k, type).c_str(),
                                     streamRead, size, k, storage)
            ->UseRealTime()
            ->Unit(benchmark::kMicrosecond);
      }
  for (const BackendEntry& entry : backendEntries())
    if (entry.make && entry.relighter)
      for (int size : {400, 800})
        for (int k : {3, 4, 6, 8, 16})
          benchmark::RegisterBenchmark(
              fmt::format("RelightOn/{}/{}/{}", entry.info.name, size, k).c_str(), relightOn,
              entry.info.name, size, k)
              ->UseRealTime()
              ->Unit(benchmark::kMicrosecond);
  // The same frame through every instruction set this CPU has, to choose between them.
  for (KernelIsa isa : availableKernelIsas())
    for (auto storage : {SampleStorage::kFloat, SampleStorage::kHalf})
      benchmark::RegisterBenchmark(
          fmt::format("RelightIsa/{}/800/6/{}", toString(isa),
                      storage == SampleStorage::kFloat ? "float" : "half")
              .c_str(),
          relight, 800, 6, storage, true, std::optional<KernelIsa>(isa))
          ->UseRealTime()
          ->Unit(benchmark::kMicrosecond);
  return true;
}();

}  // namespace
}  // namespace svr

BENCHMARK_MAIN();
