#pragma once
// Classification (design.md §2): the transfer function's materials baked into per-bin coefficient
// tables for one colour model and one sample step, plus what every backend samples: the volume
// as float, a scalar field for gradients, and min–max blocks for empty-space skipping. Built
// once per transfer function, model and step; backends only read it.

#include <Eigen/Core>
#include <memory>
#include <optional>
#include <vector>

#include "renderers/classification/derived_cache.h"
#include "renderers/scene/transfer_function.h"
#include "renderers/volume/volume.h"
#include "spectral/colour_model.h"

namespace svr {

struct ClassificationOptions {
  double step_world = 1.0;  // Δs: opacity and transmission are for this path length
  int bins = 1024;          // scalar transfer functions: table entries over the value range
  // A light folded into the scattering coefficients (ρ ⊙ l, white ⊙ l): renders "with the light
  // baked in", the reference post-illumination must reproduce.
  std::optional<Eigen::VectorXd> baked_light;
};

struct ClassifiedVolume {
  // Per-entry tables (bins for scalar volumes, one entry per label for label maps).
  int entries = 0;
  int k = 0;                  // channels of the model
  int t_channels = 1;         // 1 (achromatic absorbers) or k
  bool labels = false;
  double value_lo = 0.0, value_scale = 1.0;  // bin index = (value − lo) · scale
  std::vector<float> alpha;         // entries: 1 − exp(−Δs σ), x-ray materials included
  std::vector<float> reflectance;   // entries × k: ρ coefficients (⊙ baked light)
  std::vector<float> specular;      // entries: specular weight
  std::vector<float> transmission;  // entries × t_channels: per-step transmission (x-ray: 1)
  std::vector<float> white;         // k: coefficients of flat white (⊙ baked light)

  Dims dims{0, 0, 0};
  glm::dvec3 spacing{1.0};
  std::vector<float> values;         // the volume as float (labels as their numbers)
  std::vector<std::uint16_t> label;  // label maps: the label of every voxel
  // Label maps: the per-voxel extinction, whose gradient gives normals (label numbers have
  // none). Scalar volumes shade with the values themselves and leave this empty.
  std::vector<float> shading_field;
  const std::vector<float>& shadingField() const { return labels ? shading_field : values; }
  double step_world = 1.0;
  // A distributed render's brick (the volume's): dims and the fields above are the brick's
  // stored voxels; backends place them in the whole grid and take only the brick's own samples.
  std::optional<VolumeBrick> brick;

  // Empty-space skipping: the volume in blocks of kBlock³ voxels (4: on the engine at 512², 4³
  // blocks took 14 % less time per frame than 8³ and 9 % less than 2³); a block is empty when nothing
  // sampled inside it (trilinear from its voxels and its +1 border) can be non-transparent.
  static constexpr int kBlock = 4;
  Dims blocks{0, 0, 0};
  std::vector<std::uint8_t> block_occupied;
  bool blockOccupied(int bx, int by, int bz) const {
    return block_occupied[(static_cast<std::size_t>(bz) * blocks[1] + by) * blocks[0] + bx] != 0;
  }

  // What backends derive from this classification once (copies share it).
  std::shared_ptr<DerivedCache> derived = std::make_shared<DerivedCache>();
};

// Throws svr::Error when the model is not componentwise (linear:k has no per-sample product
// the backends can take) or a label exceeds the label table.
ClassifiedVolume classify(const Volume& volume, const TransferFunction& tf,
                          const ColourModel& model, const ClassificationOptions& options);

// The same classification for another model: the tables are baked again and what backends
// derived is dropped, while the volume's part (values, labels, occupied blocks: the opacity
// does not depend on the model) is kept. Equal to classify() with `model`; for renders of one
// scene under many models (the model probe). The step must be the classification's own.
void setModel(ClassifiedVolume& cv, const TransferFunction& tf, const ColourModel& model,
              const ClassificationOptions& options);

}  // namespace svr
