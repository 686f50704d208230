#pragma once
// factor:k for a scene (scene_model.h): the best of a few candidates on a small render of the
// scene itself (a ModelProbe, 48 pixels on the longer side, mean ΔE2000 over the scene's lights
// and mixes against spectral:81). The candidates are
//   the model trained for k on the scene's palette (from the one trained for k − 1);
//   k equal bands (stable under any absorption);
//   the scene's factor:(k − 1) with a channel split, whose image is factor:(k − 1)'s;
//   rgb in k channels (rgb's projection, its last channel split, projected light matrices),
//   whose image is rgb's.
// So on its probe factor:k never loses to factor:(k − 1), nor to rgb, and a training that does
// not converge costs accuracy, never a finite image. The palette alone is not the image (issue
// 40: absorbers behind absorbers, blends, how much of the image a product covers): it trains,
// the render chooses.
//
// A distributed brick holds part of the volume, so no probe sees the scene: bricks choose on
// the palette (trainingSetError), which every brick holds whole, and agree.
//
// Trained models and choices are cached on disk: the trained ones by the palette, the choices by
// the palette and everything the probe render reads (the volume's values included).

#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "renderers/model/scene_model.h"
#include "spectral/componentwise_model.h"
#include "spectral/factor_training.h"

namespace svr {

class FactorChoice {
 public:
  static constexpr int kProbeSide = 48;

  FactorChoice(const Scene& scene, const Observer& observer);
  // factor:k (name.kind must be kFactor).
  SceneModel make(const ModelName& name);
  // The probe's classification when a choice rendered one (null otherwise), for the caller
  // to reuse (SceneModel::classification); no further make() may follow.
  std::shared_ptr<ClassifiedVolume> releaseClassification();

 private:
  struct Candidate {
    std::string how;
    std::unique_ptr<ComponentwiseModel> model;
  };
  std::unique_ptr<ComponentwiseModel> trained(const ModelName& name, const TrainingSet& palette);
  SceneModel choose(const ModelName& name, const TrainingSet& palette);
  std::vector<Candidate> candidates(const ModelName& name, const TrainingSet& palette);
  // The probe (built on first use), or null in a brick.
  const ModelProbe* probe();
  std::optional<nlohmann::json> load(const std::string& kind, const nlohmann::json& key) const;
  void store(const std::string& kind, const nlohmann::json& key, const nlohmann::json& payload);

  const Scene& scene_;
  const Observer& observer_;
  const bool probing_;
  std::optional<ModelProbe> probe_;
  nlohmann::json probe_key_;  // what the probe render reads; null in a brick
  // This choice's entries, for a run with the disk cache off (auto asks for k = 3, 4, … and
  // each k for its k − 1).
  std::map<std::string, nlohmann::json> memo_;
};

}  // namespace svr
