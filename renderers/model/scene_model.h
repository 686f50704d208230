#pragma once
// The colour model a scene renders with — "model no more than a scene needs" (design.md §4):
//   rgb, spectral:n   fixed models;
//   factor:k          trained on the scene's own palette, what its image holds: its lights ×
//                     its materials' reflectances, the specular white and the backdrop, with
//                     deep products through every spectral absorber of the scene, at several
//                     strengths and depths (none where all absorb achromatically), for
//                     full-spectrum light matrices (factor:k/projected: for projected ones, the
//                     paper's, without the white); the best on that palette of the model
//                     trained for k, k equal bands and factor:(k−1) with a channel split, so it
//                     never loses to fewer channels there and its transmittances stay in [0, 1];
//   auto              the smallest factor k (3..16, full light matrices) whose relit image
//                     stays within the scene's model_target: a probe render of the scene
//                     itself (raycast, 96 pixels on the longer side) against spectral:81, the
//                     worst mean ΔE2000 over every light and mix, backdrop included; spectral:81
//                     when no k reaches it. (The palette alone misses what the image holds:
//                     absorbers deep in a volume, a backdrop seen through them.)

#include <cmath>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "renderers/scene/scene.h"
#include "spectral/colorimetry.h"
#include "spectral/colour_model.h"
#include "spectral/light_independent_image.h"
#include "spectral/wavelength_grid.h"

namespace svr {

struct SceneModel {
  std::unique_ptr<ColourModel> model;
  std::string description;  // how it was chosen, for render.json and the terminal
  std::string asked;        // the name it was made from ("auto", "factor:6", …)
  // Trained factor models: the error on the scene palette that justified the choice (worst of
  // the single-product and 256-step mean ΔE2000); auto also has its target. NaN otherwise.
  double palette_de2000 = NAN;
  double target = NAN;
  double probe_de2000 = NAN;  // auto: the chosen model's probe error (worst light's mean)
  // Trained models: read from the disk cache (base/disk_cache.h) rather than trained now.
  bool cached = false;

  // {"asked", "model", "k", "description", "palette_de2000"?, "target"?, "probe_de2000"?,
  // "cached"?} for render.json and report.json.
  nlohmann::json record() const;
};

// auto's probe (issue 19): the scene itself rendered small by the registry's reference backend
// (the raycaster) with spectral:81, the exact product, and a candidate's relit image compared
// with it under every light and mix, the backdrop included. The probe and the candidates share
// step, termination and resolution, so what differs is the colour model alone.
class ModelProbe {
 public:
  static constexpr int kLongerSide = 96;
  // The scene at the probe's size: kLongerSide pixels on its longer side (never enlarged).
  static Scene sized(Scene scene);
  ModelProbe(const Scene& scene, const Observer& observer);
  // The worst over lights and mixes of the mean ΔE2000 against spectral:81.
  double error(const ColourModel& model) const;
  // The mean ΔE2000 against spectral:81 under each light, then each mix (infinite where the
  // relit image is not finite).
  std::vector<double> errors(const ColourModel& model) const;
  std::string size() const;  // "96×96"

 private:
  LightIndependentImage render(const ColourModel& model) const;

  Scene scene_;
  const Observer& observer_;
  std::vector<Spectrum> lights_;
  std::unique_ptr<ColourModel> reference_model_;
  LightIndependentImage reference_;
};

// Throws svr::Error "FLAG 'NAME': why" unless NAME is auto or a model that can be made on `grid`
// (a known kind, k in range, spectral:n with n no more than the grid's samples): what a flag
// or key names is checked before anything renders.
void checkModelName(const std::string& name, const std::string& flag,
                    const WavelengthGrid& grid = WavelengthGrid::standard());

// Trained models are cached on disk, keyed by everything they depend on (DiskCache::process();
// off with --no-cache).
SceneModel makeSceneModel(const std::string& name, const Scene& scene, const Observer& observer);

}  // namespace svr
