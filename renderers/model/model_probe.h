#pragma once
// Renders of a scene, small, under candidate colour models, against spectral:81.

#include <memory>
#include <string>
#include <vector>

#include "renderers/classification/classification.h"
#include "renderers/scene/scene.h"
#include "spectral/colorimetry.h"
#include "spectral/colour_model.h"
#include "spectral/light_independent_image.h"

namespace svr {

// A model probe (issue 19): the scene itself rendered small by the registry's reference backend
// (the raycaster) with spectral:81, the exact product, and a candidate's relit image compared
// with it under every light and mix, the backdrop included. The probe and the candidates share
// step, termination and resolution, so what differs is the colour model alone. auto chooses its
// k on one (96 pixels), factor:k its candidate on another (48, renderers/model/factor_choice.h).
class ModelProbe {
 public:
  static constexpr int kLongerSide = 96;
  // The scene at the probe's size: longer_side pixels on its longer side (never enlarged).
  static Scene sized(Scene scene, int longer_side = kLongerSide);
  ModelProbe(const Scene& scene, const Observer& observer, int longer_side = kLongerSide);
  // The worst over lights and mixes of the mean ΔE2000 against spectral:81.
  double error(const ColourModel& model) const;
  // The mean over lights and mixes of the mean ΔE2000 against spectral:81 (infinite where an
  // image is not finite).
  double meanError(const ColourModel& model) const;
  // The mean ΔE2000 against spectral:81 under each light, then each mix (infinite where the
  // relit image is not finite).
  std::vector<double> errors(const ColourModel& model) const;
  std::string size() const;  // "96×96"
  const Scene& scene() const { return scene_; }
  // The probe's classification of the scene's volume (its tables the last model's), moved
  // out for a caller that classifies the same scene next (setModel); the probe is spent.
  ClassifiedVolume releaseClassification() { return std::move(classified_); }

 private:
  // Renders with `model`: the volume is classified once, and each model bakes its tables only
  // (setModel), so a probe of many models costs one classification. Not thread-safe.
  LightIndependentImage render(const ColourModel& model) const;

  Scene scene_;
  const Observer& observer_;
  std::vector<Spectrum> lights_;
  mutable ClassifiedVolume classified_;
  std::unique_ptr<ColourModel> reference_model_;
  LightIndependentImage reference_;
};

}  // namespace svr
