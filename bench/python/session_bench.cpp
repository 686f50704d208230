// The C++ side of bench/python/run: the same scene, size and model as the Python side, timed
// through the library's RenderSession (what svr.Scene.render and svr.Image.relight call).
//   render:         median ms of a session made and rendered (model from the cache, classify,
//                   render), the work scene.render does below Python;
//   relight_call:   frames/s of RenderSession::relightSrgb8 (light matrix, then the kernel),
//                   what image.relight does below Python;
//   relight_kernel: frames/s of the kernel alone, the light set once (svr_relight_bench's).
// Usage: svr_session_bench SCENE MODEL RENDER_SIZE RELIGHT_SIZE; prints one JSON object.

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <vector>

#include "harness/render_session.h"
#include "base/data_dir.h"
#include "base/elapsed.h"
#include "spectral/post_illumination.h"

namespace {

template <class Fn>
double medianMs(int runs, Fn&& fn) {
  std::vector<double> ms;
  for (int i = 0; i < runs; ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    fn();
    ms.push_back(svr::msSince(t0));
  }
  std::nth_element(ms.begin(), ms.begin() + ms.size() / 2, ms.end());
  return ms[ms.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  using namespace svr;
  if (argc != 5) {
    fmt::print(stderr, "usage: svr_session_bench SCENE MODEL RENDER_SIZE RELIGHT_SIZE\n");
    return 2;
  }
  const std::string scene_file = argv[1], model = argv[2];
  const int render_size = std::atoi(argv[3]), relight_size = std::atoi(argv[4]);
  auto spectra = std::make_shared<const SessionSpectra>(defaultDataDir());
  const Scene scene = loadScene(scene_file, spectra->library);
  RenderSettings settings;
  settings.model = model;
  settings.width = settings.height = render_size;
  auto once = [&] {
    RenderSession session(spectra, scene, settings, scene_file);
    session.render();
  };
  once();  // the model into the cache, the pages warm
  const double render_ms = medianMs(15, once);

  settings.width = settings.height = relight_size;
  RenderSession big(spectra, scene, settings, scene_file);
  big.render();
  const Spectrum d65 = big.light("D65");
  std::vector<std::uint8_t> out(3 * big.image().pixels());
  const int frames = 200;
  const double call_ms = medianMs(5, [&] {
    for (int f = 0; f < frames; ++f) big.relightSrgb8(d65, out);
  });
  PostIlluminator post(*big.model().model);
  post.setLight(d65);
  const double kernel_ms = medianMs(5, [&] {
    for (int f = 0; f < frames; ++f) post.relightSrgb8(big.image(), out);
  });
  fmt::print("{{\"render_ms\": {:.3f}, \"relight_call_fps\": {:.1f}, \"relight_kernel_fps\": {:.1f}, "
             "\"planes\": {}}}\n",
             render_ms, frames * 1000.0 / call_ms, frames * 1000.0 / kernel_ms,
             big.image().planes());
  return 0;
}
