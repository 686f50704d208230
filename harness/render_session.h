#pragma once
// The one route from a scene to a frame (design.md §2): the scene with its overrides, the colour
// model (trained or cached), the classification, the backend, the light-independent image, and
// that image relit under any light. `svr render`, svr-mpi, `svr view`, the comparison harness,
// the public svr::Session (include/svr/svr.h) and the Python module all make frames through it.
// Its parts are reused: another view or size renders the same classification (renderView),
// another model classifies again (setModel).
//
// A distributed render (svr-mpi, FrameSettings::distribution) takes the same route, with what
// bricks add at each step (design.md §5b): the split before the volume is read, agreement on
// the whole volume's ranges and on auto's model, the transmittance in front, compositing. Every
// step is a phase on which the processes agree, so a process that fails never leaves the others
// waiting in a collective.

#include <atomic>
#include <cstdint>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "harness/brick_steps.h"
#include "renderers/classification/classification.h"
#include "renderers/model/scene_model.h"
#include "renderers/render/renderer.h"
#include "renderers/scene/scene.h"
#include "spectral/colorimetry.h"
#include "spectral/light_independent_image.h"
#include "spectral/post_illumination.h"
#include "spectral/spectrum_library.h"
#include "svr/svr.h"

namespace svr {

class RenderDistribution;

// The spectra of one data folder: its library and the CIE 1931 observer on the standard grid.
struct SessionSpectra {
  explicit SessionSpectra(const std::string& data_dir);
  std::string data_dir;
  WavelengthGrid grid = WavelengthGrid::standard();
  SpectrumLibrary library;
  Observer observer;
};

// What a frame is made with beyond the scene: each setting overrides the scene's own.
struct FrameSettings {
  std::string renderer = "raycast";
  std::string model;  // rgb, factor:k, spectral:n, auto; empty: the scene's
  std::optional<int> width, height;
  std::vector<std::string> options;  // BACKEND.KEY=VALUE over the scene's render.options
  std::optional<std::uint64_t> memory_budget;  // voxels and images; empty: the default
  // How errors name the settings: the command line's flags, or the API's fields.
  std::string model_flag = "--model", options_flag = "--option";
  // A distributed render: this process's part in it, and how its kd-split shares the volume
  // out: "work" (estimated, renderers/render/work_estimate.h) or "voxels".
  RenderDistribution* distribution = nullptr;
  std::string balance = "work";

  static FrameSettings of(const RenderSettings& api);  // the public API's settings
};

class RenderSession {
 public:
  // Reads the scene file and its volume (in a distributed render, this process's brick of it),
  // then sets up as the constructor does.
  static std::unique_ptr<RenderSession> load(std::shared_ptr<const SessionSpectra> spectra,
                                             const std::string& scene_file,
                                             const FrameSettings& settings);
  // `source` names the scene in errors ("engine.json", "scene JSON"). The model is made here
  // (trained, or read from the disk cache) and the volume classified, with the memory of the
  // image and its relit images checked before any is allocated.
  RenderSession(std::shared_ptr<const SessionSpectra> spectra, Scene scene,
                const FrameSettings& settings, const std::string& source);
  RenderSession(std::shared_ptr<const SessionSpectra> spectra, Scene scene,
                const RenderSettings& settings, const std::string& source);

  // Renders the scene's view and keeps the light-independent image (in a distributed render,
  // composited on the writer; empty elsewhere). `progress` is called on this thread; setting
  // *stop from anywhere ends the render early with svr::Cancelled. Returns its milliseconds.
  double render(const ProgressFn& progress = nullptr, const std::atomic<bool>* stop = nullptr);
  // Another view and size of the same classification, returned rather than kept (one process).
  LightIndependentImage renderView(const Camera& camera, int width, int height,
                                   const std::atomic<bool>* stop = nullptr) const;
  // Another colour model: made, and the volume classified again; the kept image is dropped.
  void setModel(const std::string& name);

  bool rendered() const { return image_.has_value(); }
  // Throws svr::Error when nothing was rendered yet.
  const LightIndependentImage& image() const;
  // What was noted while setting up and during the first render() of the current model (shown
  // after a progress bar): a later frame of the same view has nothing new to say.
  const std::vector<std::string>& notes() const { return notes_; }

  const Scene& scene() const { return scene_; }
  const std::string& source() const { return source_; }
  const SceneModel& model() const { return model_; }
  // Move the model and the kept image out, for a caller done with the session that keeps them
  // beyond it (the comparison's runs); nothing else may be asked of the session after.
  SceneModel takeModel() { return std::move(model_); }
  LightIndependentImage takeImage();
  const Renderer& renderer() const { return *renderer_; }
  const SessionSpectra& spectra() const { return *spectra_; }
  const ClassifiedVolume& classified() const { return classified_; }
  std::uint64_t memoryBudget() const { return memory_budget_; }
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

  // Milliseconds of the steps. load: the scene file and volume (load() only); setup: the whole
  // constructor (model and classification included); render: the last render().
  struct Timings {
    double load = 0, setup = 0, model = 0, classify = 0, render = 0;
  };
  const Timings& timings() const { return timings_; }

  // A distributed render's facts, every process's as one array on the writer (its brick,
  // times, memory; null on the others). Collective.
  nlohmann::json gatherBricks() const;

 private:
  void applySettings(const FrameSettings& settings);
  void chooseModel(const std::string& name);
  void classify();
  // One brick's frame, composited on the writer (distributed renders).
  LightIndependentImage renderBrick(RenderRequest request, const ProgressFn& progress);
  // The model's relighter with the scene's backdrop, set to `light`.
  PostIlluminator relighter(const Spectrum& light) const;

  std::shared_ptr<const SessionSpectra> spectra_;
  std::string source_;
  Scene scene_;
  SceneModel model_;
  std::unique_ptr<Renderer> renderer_;
  ClassifiedVolume classified_;
  std::optional<LightIndependentImage> image_;
  std::vector<std::string> notes_;
  bool noted_first_frame_ = false;
  std::vector<std::string> light_names_;
  std::vector<Spectrum> light_spectra_;  // paired with light_names_
  std::uint64_t memory_budget_ = 0;
  RenderDistribution* distribution_ = nullptr;
  BrickFacts brick_facts_;
  Timings timings_;
};

}  // namespace svr
