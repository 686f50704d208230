#pragma once
// The route from a loaded scene to a frame and its relit images, behind the public svr::Session
// (include/svr/svr.h) and the Python module (python/): the settings' overrides, the colour
// model (trained or cached), the classification, the backend's light-independent image, and
// relighting it under any light. Internal: the public API exposes none of these types.

#include <atomic>
#include <memory>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "renderers/core/classification.h"
#include "renderers/core/renderer.h"
#include "renderers/core/scene.h"
#include "renderers/scene_model.h"
#include "spectral/colorimetry.h"
#include "spectral/light_independent_image.h"
#include "spectral/post_illumination.h"
#include "spectral/spectrum_library.h"
#include "svr/svr.h"

namespace svr {

// The spectra of one data folder: its library and the CIE 1931 observer on the standard grid.
struct SessionSpectra {
  explicit SessionSpectra(const std::string& data_dir);
  std::string data_dir;
  WavelengthGrid grid = WavelengthGrid::standard();
  SpectrumLibrary library;
  Observer observer;
};

class RenderSession {
 public:
  // `source` names the scene in errors ("engine.json", "scene JSON"). The model is made here
  // (trained, or read from the disk cache) and the volume classified. settings.data_dir is not
  // read: the spectra come loaded.
  RenderSession(std::shared_ptr<const SessionSpectra> spectra, Scene scene,
                const RenderSettings& settings, const std::string& source);

  // Renders the light-independent image. `progress` is called on this thread; setting *stop
  // from anywhere ends the render early with svr::Cancelled.
  void render(const ProgressFn& progress = nullptr, const std::atomic<bool>* stop = nullptr);
  bool rendered() const { return image_.has_value(); }
  // Throws svr::Error when nothing was rendered yet.
  const LightIndependentImage& image() const;

  const Scene& scene() const { return scene_; }
  const SceneModel& model() const { return model_; }
  const Renderer& renderer() const { return *renderer_; }
  const SessionSpectra& spectra() const { return *spectra_; }
  const ClassifiedVolume& classified() const { return classified_; }
  // The scene's lights, then its mixes, by name.
  const std::vector<std::string>& lightNames() const { return light_names_; }

  // A scene light or mix by name, else a library spectrum, at unit luminance.
  Spectrum light(const std::string& name) const;
  // Light name → weight, each light at unit luminance; weights finite and ≥ 0.
  Spectrum mix(const std::vector<std::pair<std::string, double>>& weights) const;
  // Any spectrum on the grid (a user's own), at unit luminance; its values finite and ≥ 0.
  Spectrum ownLight(const Spectrum& spectrum, const std::string& what) const;

  // The image relit under `light` with the scene's backdrop: 8-bit sRGB or linear sRGB floats,
  // 3 per pixel, row 0 at the top (out holds exactly that many).
  void relightSrgb8(const Spectrum& light, std::span<std::uint8_t> out) const;
  void relightLinear(const Spectrum& light, std::span<float> out) const;
  // What `svr render` writes for this frame into `dir` (EXR, model, PNGs, render.json).
  void save(const std::string& dir, bool quiet = true) const;

  // Milliseconds of the steps, for the record and the Python module's overhead bench.
  // setup: the whole constructor (model and classification included).
  struct Timings {
    double setup = 0, model = 0, classify = 0, render = 0;
  };
  const Timings& timings() const { return timings_; }

 private:
  // The model's relighter with the scene's backdrop, set to `light`.
  PostIlluminator relighter(const Spectrum& light) const;

  std::shared_ptr<const SessionSpectra> spectra_;
  std::string source_;
  Scene scene_;
  SceneModel model_;
  std::unique_ptr<Renderer> renderer_;
  ClassifiedVolume classified_;
  std::optional<LightIndependentImage> image_;
  std::vector<std::string> light_names_;
  std::vector<Spectrum> light_spectra_;  // paired with light_names_
  Timings timings_;
};

}  // namespace svr
