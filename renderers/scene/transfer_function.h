#pragma once
// Spectral transfer functions: data value → material and opacity (design.md §5, paper §3).
//   1D: control points (value → material); between two neighbouring points the materials blend
//       linearly (smooth transitions), outside them the end material holds; an opacity curve
//       (piecewise linear, value → factor in [0, 1]) scales the materials' extinction.
//   Labels: label → material (or nothing); classification is per label and the classified
//       result is interpolated, never the label numbers.

#include <string>
#include <utility>
#include <vector>

#include "renderers/scene/material.h"

namespace svr {

struct MaterialPoint {
  double value;
  int material;  // index into TransferFunction::materials
};

struct TransferFunction {
  enum class Kind { kScalar, kLabels };
  Kind kind = Kind::kScalar;
  std::vector<Material> materials;
  // kScalar: control points sorted by value, and the opacity curve (value, factor) sorted.
  std::vector<MaterialPoint> points;
  std::vector<std::pair<double, double>> opacity;
  // kLabels: material index per label value (−1 = empty), label 0..labels.size()-1.
  std::vector<int> labels;

  // The blend of materials at a data value: up to two (index, weight) pairs.
  std::vector<std::pair<int, double>> materialWeights(double value) const;
  double opacityFactor(double value) const;
  // True when every material absorbs achromatically: the image then needs one T channel.
  bool achromatic() const;
};

}  // namespace svr
