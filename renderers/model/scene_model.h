#pragma once
// The colour model a scene renders with — "model no more than a scene needs" (design.md §4):
//   rgb, spectral:n   fixed models;
//   factor:k          trained on the scene's own palette, what its image holds: its lights ×
//                     its materials' reflectances, the specular white and the backdrop, with
//                     deep products through every spectral absorber of the scene, at several
//                     strengths and depths (none where all absorb achromatically), for
//                     full-spectrum light matrices (factor:k/projected: for projected ones, the
//                     paper's, without the white); then the best on a small render of the scene
//                     of the model trained for k, k equal bands, factor:(k−1) with a channel
//                     split and rgb in k channels, so it never loses to fewer channels or to rgb
//                     there and its transmittances stay in [0, 1] (renderers/model/
//                     factor_choice.h);
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

#include "renderers/model/model_probe.h"
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
  // factor:k: the chosen candidate's error on its probe (mean over lights and mixes); NaN in a
  // brick, which chooses on the palette (renderers/model/factor_choice.h).
  double choice_de2000 = NAN;
  // Trained models: read from the disk cache (base/disk_cache.h) rather than trained now.
  bool cached = false;
  // factor:k and auto, when choosing rendered a probe: its classification of the scene's
  // volume at the scene's step and bins, which the caller may take (setModel to `model`)
  // instead of classifying the volume again. Null otherwise.
  std::shared_ptr<ClassifiedVolume> classification;

  // {"asked", "model", "k", "description", "palette_de2000"?, "target"?, "probe_de2000"?,
  // "choice_de2000"?, "cached"?} for render.json and report.json.
  nlohmann::json record() const;
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
