#include "spectral/light_mixer.h"

#include <fmt/format.h>

#include <cmath>
#include <numbers>

#include "base/error.h"

namespace svr {

LightMixer LightMixer::regularPolygon(int n, double power) {
  if (n < 1 || n > 64) throw Error(fmt::format("light mixer: {} lights is outside 1..64", n));
  LightMixer mixer;
  mixer.power = power;
  for (int i = 0; i < n; ++i) {
    const double a = std::numbers::pi / 2 + 2 * std::numbers::pi * i / n;
    mixer.nodes.push_back({std::cos(a), std::sin(a), true});
  }
  return mixer;
}

std::vector<double> LightMixer::weights(double x, double y) const {
  if (!std::isfinite(x) || !std::isfinite(y))
    throw Error(fmt::format("light mixer: handle position ({}, {}) is not finite", x, y));
  if (!std::isfinite(power) || power <= 0)
    throw Error(fmt::format("light mixer: power must be > 0, got {}", power));
  if (nodes.empty()) throw Error("light mixer: no light nodes");
  std::vector<double> w(nodes.size(), 0.0);
  // A handle on (or within rounding of) a lit node selects that light alone.
  constexpr double kOnNode = 1e-9;
  for (size_t i = 0; i < nodes.size(); ++i) {
    if (!nodes[i].on) continue;
    if (std::hypot(nodes[i].x - x, nodes[i].y - y) < kOnNode) {
      w[i] = 1.0;
      return w;
    }
  }
  double sum = 0.0;
  for (size_t i = 0; i < nodes.size(); ++i) {
    if (!nodes[i].on) continue;
    w[i] = 1.0 / std::pow(std::hypot(nodes[i].x - x, nodes[i].y - y), power);
    sum += w[i];
  }
  if (sum == 0.0) return w;  // every light off: a dark mix
  for (double& v : w) v /= sum;
  return w;
}

Eigen::VectorXd mixLights(std::span<const Eigen::VectorXd> lights, std::span<const double> weights) {
  if (lights.size() != weights.size() || lights.empty())
    throw Error(fmt::format("light mix: {} lights but {} weights", lights.size(), weights.size()));
  Eigen::VectorXd mix = Eigen::VectorXd::Zero(lights.front().size());
  for (size_t i = 0; i < lights.size(); ++i) {
    if (lights[i].size() != mix.size())
      throw Error(fmt::format("light mix: light {} has {} coefficients, light 0 has {}", i,
                              lights[i].size(), mix.size()));
    if (!std::isfinite(weights[i]))
      throw Error(fmt::format("light mix: weight {} is not finite", i));
    mix += weights[i] * lights[i];
  }
  return mix;
}

std::vector<double> normaliseIntensity(std::span<const double> weights,
                                       std::span<const double> luminances) {
  if (weights.size() != luminances.size())
    throw Error(fmt::format("light mix: {} weights but {} luminances", weights.size(),
                            luminances.size()));
  double y = 0.0;
  for (size_t i = 0; i < weights.size(); ++i) y += weights[i] * luminances[i];
  if (!(y > 0) || !std::isfinite(y))
    throw Error(fmt::format("light mix: luminance {} cannot be normalised to 1", y));
  std::vector<double> out(weights.begin(), weights.end());
  for (double& w : out) w /= y;
  return out;
}

}  // namespace svr
