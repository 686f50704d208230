#pragma once
// The n-gon light mixer (Bergner et al. 2002 §3.3): n light nodes in the plane, a handle whose
// position gives each light a weight by normalised inverse distance, w_i ∝ 1/d_i^p. A handle
// on a node gives that light alone. Pure functions; the UI (or the CLI) owns the state.

#include <Eigen/Core>
#include <span>
#include <vector>

namespace svr {

struct MixerNode {
  double x = 0.0, y = 0.0;
  bool on = true;
};

struct LightMixer {
  std::vector<MixerNode> nodes;
  double power = 2.0;  // p in 1/d^p; larger makes the nearest light dominate sooner

  // n nodes on the unit circle, node 0 at the top, counter-clockwise.
  static LightMixer regularPolygon(int n, double power = 2.0);

  // Weights of the lights for a handle at (x, y): non-negative, zero for lights that are off,
  // summing to 1 (when any light is on). Throws svr::Error for impossible parameters.
  std::vector<double> weights(double x, double y) const;
};

// Σ w_i · light_i over coefficient vectors (or spectra) of equal size.
Eigen::VectorXd mixLights(std::span<const Eigen::VectorXd> lights, std::span<const double> weights);

// Scales weights so the mix has unit luminance, given each light's luminance Y_i:
// Σ w_i · Y_i = 1.
std::vector<double> normaliseIntensity(std::span<const double> weights,
                                       std::span<const double> luminances);

}  // namespace svr
