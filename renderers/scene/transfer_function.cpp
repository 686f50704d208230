#include "renderers/scene/transfer_function.h"

#include <algorithm>

namespace svr {

std::vector<std::pair<int, double>> TransferFunction::materialWeights(double value) const {
  if (points.empty()) return {};
  if (value <= points.front().value) return {{points.front().material, 1.0}};
  if (value >= points.back().value) return {{points.back().material, 1.0}};
  const auto hi = std::upper_bound(points.begin(), points.end(), value,
                                   [](double v, const MaterialPoint& p) { return v < p.value; });
  const auto lo = hi - 1;
  const double t = (value - lo->value) / (hi->value - lo->value);
  if (lo->material == hi->material) return {{lo->material, 1.0}};
  return {{lo->material, 1.0 - t}, {hi->material, t}};
}

double TransferFunction::opacityFactor(double value) const {
  if (opacity.empty()) return 1.0;
  if (value <= opacity.front().first) return opacity.front().second;
  if (value >= opacity.back().first) return opacity.back().second;
  const auto hi = std::upper_bound(
      opacity.begin(), opacity.end(), value,
      [](double v, const std::pair<double, double>& p) { return v < p.first; });
  const auto lo = hi - 1;
  const double t = (value - lo->first) / (hi->first - lo->first);
  return (1.0 - t) * lo->second + t * hi->second;
}

bool TransferFunction::achromatic() const {
  return std::none_of(materials.begin(), materials.end(),
                      [](const Material& m) { return m.absorption.has_value(); });
}

}  // namespace svr
