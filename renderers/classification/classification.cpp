#include "renderers/classification/classification.h"

#include "renderers/classification/classified_sample.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "base/error.h"

namespace svr {
namespace {

// Normalise an absorption shape to mean 1, so σ keeps its meaning as the mean extinction.
Eigen::VectorXd absorptionShape(const Material& m, int n) {
  if (!m.absorption) return Eigen::VectorXd::Ones(n);
  const double mean = m.absorption->values().mean();
  if (!(mean > 0) || !std::isfinite(mean))
    throw Error(fmt::format("material '{}': absorption spectrum has mean {}; it must be > 0",
                            m.name, mean));
  return m.absorption->values() / mean;
}

struct Entry {
  double alpha = 0.0, specular = 0.0;
  Eigen::VectorXd reflectance, transmission;
};

// One table entry from a blend of materials (weights sum to 1) at an opacity factor.
Entry blend(const std::vector<std::pair<int, double>>& weights, double opacity_factor,
            const TransferFunction& tf, const ColourModel& model, double step, bool spectral_t,
            const std::vector<Eigen::VectorXd>& refl_coeffs,
            const std::vector<Eigen::VectorXd>& shapes) {
  const int k = model.channels();
  const int n = model.grid().count;
  Entry e;
  e.reflectance = Eigen::VectorXd::Zero(k);
  Eigen::VectorXd depth = Eigen::VectorXd::Zero(n);  // occluding optical depth per wavelength
  double sigma = 0.0;
  for (const auto& [index, w] : weights) {
    const Material& m = tf.materials[index];
    const double s = w * m.extinction * opacity_factor;
    sigma += s;
    e.specular += w * m.specular;
    e.reflectance += w * refl_coeffs[index];
    if (!m.xray) depth += s * shapes[index];
  }
  e.alpha = 1.0 - std::exp(-step * sigma);
  if (spectral_t) {
    const Spectrum t(model.grid(), (-step * depth).array().exp().matrix());
    e.transmission = model.projectTransmittance(t);
  } else {
    e.transmission = Eigen::VectorXd::Constant(1, std::exp(-step * depth.mean()));
  }
  return e;
}

bool isIntegerType(ScalarType t) { return t != ScalarType::kFloat32 && t != ScalarType::kFloat64; }

// The blended entries as the float tables backends read; non-finite coefficients are refused.
void storeEntries(const std::vector<Entry>& entries, ClassifiedVolume& cv) {
  const int k = cv.k;
  cv.alpha.resize(cv.entries);
  cv.specular.resize(cv.entries);
  cv.reflectance.resize(static_cast<std::size_t>(cv.entries) * k);
  cv.transmission.resize(static_cast<std::size_t>(cv.entries) * cv.t_channels);
  for (int e = 0; e < cv.entries; ++e) {
    cv.alpha[e] = static_cast<float>(entries[e].alpha);
    cv.specular[e] = static_cast<float>(entries[e].specular);
    for (int c = 0; c < k; ++c) cv.reflectance[e * k + c] = static_cast<float>(entries[e].reflectance[c]);
    for (int c = 0; c < cv.t_channels; ++c)
      cv.transmission[e * cv.t_channels + c] = static_cast<float>(entries[e].transmission[c]);
  }
  for (float v : cv.reflectance)
    if (!std::isfinite(v)) throw Error("classification: non-finite reflectance coefficient");
  for (float v : cv.transmission)
    if (!std::isfinite(v)) throw Error("classification: non-finite transmission coefficient");
}

// Empty-space skipping: a block is occupied when any entry its voxels can reach (labels, or the
// bins between the block's value range) has non-zero opacity.
void markOccupiedBlocks(const Volume& volume, ClassifiedVolume& cv) {
  const int B = ClassifiedVolume::kBlock;
  for (int a = 0; a < 3; ++a) cv.blocks[a] = (cv.dims[a] + B - 1) / B;
  cv.block_occupied.assign(
      static_cast<std::size_t>(cv.blocks[0]) * cv.blocks[1] * cv.blocks[2], 0);
  const std::vector<int> nonzero_prefix = nonzeroOpacityPrefix(cv);
  const bool parallel = static_cast<std::int64_t>(cv.values.size()) >= kParallelVoxels;
#pragma omp parallel for collapse(2) schedule(dynamic) if (parallel)
  for (int bz = 0; bz < cv.blocks[2]; ++bz)
    for (int by = 0; by < cv.blocks[1]; ++by)
      for (int bx = 0; bx < cv.blocks[0]; ++bx) {
        float vmin = INFINITY, vmax = -INFINITY;
        bool occupied = false;
        for (int z = bz * B; z <= std::min(bz * B + B, cv.dims[2] - 1); ++z)
          for (int y = by * B; y <= std::min(by * B + B, cv.dims[1] - 1); ++y)
            for (int x = bx * B; x <= std::min(bx * B + B, cv.dims[0] - 1); ++x) {
              const std::size_t i = volume.index(x, y, z);
              if (cv.labels) {
                occupied = occupied || cv.alpha[cv.label[i]] > 0;
              } else {
                vmin = std::min(vmin, cv.values[i]);
                vmax = std::max(vmax, cv.values[i]);
              }
            }
        if (!cv.labels) {
          // In binCoordinate's arithmetic, as the samples' bins (monotone in the value, so
          // the block's range of bin coordinates is that of its extreme values).
          occupied = binRangeVisible(cv, nonzero_prefix, binCoordinate(cv, vmin),
                                     binCoordinate(cv, vmax));
        }
        cv.block_occupied[(static_cast<std::size_t>(bz) * cv.blocks[1] + by) * cv.blocks[0] + bx] =
            occupied;
      }
}

}  // namespace

namespace {

// The classification's tables for `model`: k, T's channels, white, and one entry per bin or
// label. What the volume gives (entries, value range) is already in cv.
void bakeTables(ClassifiedVolume& cv, const TransferFunction& tf, const ColourModel& model,
                const ClassificationOptions& options) {
  if (!model.componentwise())
    throw Error(fmt::format("model {} multiplies with k×k matrices; the renderers take "
                            "componentwise models only (rgb, factor:k, spectral:n)",
                            model.name()));
  const int k = model.channels();
  if (options.baked_light && options.baked_light->size() != k)
    throw Error(fmt::format("classification: baked light has {} coefficients, model {} has {}",
                            options.baked_light->size(), model.name(), k));
  const Eigen::VectorXd light =
      options.baked_light ? *options.baked_light : Eigen::VectorXd::Ones(k);
  cv.k = k;
  cv.t_channels = tf.achromatic() ? 1 : k;
  const Eigen::VectorXd white = model.white().cwiseProduct(light);
  cv.white.assign(white.data(), white.data() + k);

  std::vector<Eigen::VectorXd> refl_coeffs, shapes;
  for (const Material& m : tf.materials) {
    refl_coeffs.push_back(model.project(m.reflectance).cwiseProduct(light));
    shapes.push_back(absorptionShape(m, model.grid().count));
  }
  std::vector<Entry> entries;
  for (int e = 0; e < cv.entries; ++e) {
    if (cv.labels) {
      const int mat = e < static_cast<int>(tf.labels.size()) ? tf.labels[e] : -1;
      entries.push_back(blend(mat < 0 ? std::vector<std::pair<int, double>>{}
                                      : std::vector<std::pair<int, double>>{{mat, 1.0}},
                              1.0, tf, model, options.step_world, cv.t_channels > 1,
                              refl_coeffs, shapes));
    } else {
      const double v = cv.value_scale > 0 ? cv.value_lo + e / cv.value_scale : cv.value_lo;
      entries.push_back(blend(tf.materialWeights(v), tf.opacityFactor(v), tf, model,
                              options.step_world, cv.t_channels > 1, refl_coeffs, shapes));
    }
  }
  storeEntries(entries, cv);
  // What backends derived from the old tables is stale.
  cv.derived = std::make_shared<DerivedCache>();
}

}  // namespace

ClassifiedVolume classify(const Volume& volume, const TransferFunction& tf,
                          const ColourModel& model, const ClassificationOptions& options) {
  if (!(options.step_world > 0) || !std::isfinite(options.step_world))
    throw Error(fmt::format("classification: step {} must be > 0", options.step_world));
  if (options.bins < 2 || options.bins > (1 << 20))
    throw Error(fmt::format("classification: {} bins is outside 2..{}", options.bins, 1 << 20));

  ClassifiedVolume cv;
  cv.labels = tf.kind == TransferFunction::Kind::kLabels;
  cv.dims = volume.dims();
  cv.brick = volume.brick();
  cv.spacing = volume.spacing();
  cv.step_world = options.step_world;
  const auto [lo, hi] = volume.valueRange();
  if (cv.labels) {
    if (lo < 0 || hi > 65535)
      throw Error(fmt::format("{}: a label map needs integer labels in 0..65535, got {} values "
                              "in {}..{}", volume.source(), toString(volume.type()), lo, hi));
    cv.entries = std::max(static_cast<int>(hi) + 1, static_cast<int>(tf.labels.size()));
  } else {
    cv.entries = options.bins;
    cv.value_lo = lo;
    cv.value_scale = hi > lo ? (options.bins - 1) / (hi - lo) : 0.0;
  }
  bakeTables(cv, tf, model, options);
  cv.values = volume.toFloat();
  if (cv.labels) {
    if (!isIntegerType(volume.type()))  // float label maps are fine while every label is whole
      for (std::size_t i = 0; i < cv.values.size(); ++i)
        if (cv.values[i] != std::floor(cv.values[i])) {
          // Named in the whole grid's coordinates, also from a brick.
          const Dims& d = volume.dims();
          const Dims o = volume.brick() ? volume.brick()->stored.lo : Dims{0, 0, 0};
          const std::size_t x = i % d[0], y = i / d[0] % d[1], z = i / d[0] / d[1];
          throw Error(fmt::format("{}: voxel ({}, {}, {}) holds {}, not a whole label",
                                  volume.source(), x + o[0], y + o[1], z + o[2], cv.values[i]));
        }
    cv.label.resize(cv.values.size());
    const std::int64_t n = static_cast<std::int64_t>(cv.values.size());
#pragma omp parallel for schedule(static) if (n >= kParallelVoxels)
    for (std::int64_t i = 0; i < n; ++i) cv.label[i] = static_cast<std::uint16_t>(cv.values[i]);

    // Gradients of the per-voxel extinction (label numbers have no meaningful gradient); the
    // extinction, like the opacity, does not depend on the model.
    std::vector<float> extinction(cv.entries);  // per label, so the voxel loop is a lookup
    for (int e = 0; e < cv.entries; ++e)
      extinction[e] = -std::log1p(-std::min(cv.alpha[e], 0.999999f));
    cv.shading_field.resize(cv.values.size());
#pragma omp parallel for schedule(static) if (n >= kParallelVoxels)
    for (std::int64_t i = 0; i < n; ++i) cv.shading_field[i] = extinction[cv.label[i]];
  }

  markOccupiedBlocks(volume, cv);
  return cv;
}

void setModel(ClassifiedVolume& cv, const TransferFunction& tf, const ColourModel& model,
              const ClassificationOptions& options) {
  if (options.step_world != cv.step_world)
    throw Error(fmt::format("classification: a new model at step {} for a classification at "
                            "step {}; classify again", options.step_world, cv.step_world));
  bakeTables(cv, tf, model, options);
}

}  // namespace svr
