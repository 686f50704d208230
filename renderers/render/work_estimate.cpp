#include "renderers/render/work_estimate.h"

#include <algorithm>
#include <cmath>

namespace svr {
namespace {

// The ray's parameter interval inside the grid's voxel box [0, dims − 1]; false: it misses.
bool clip(const Dims& dims, const glm::dvec3& o, const glm::dvec3& d, double& t0, double& t1) {
  t0 = 0.0, t1 = INFINITY;
  for (int a = 0; a < 3; ++a) {
    if (std::abs(d[a]) < 1e-300) {
      if (o[a] < 0.0 || o[a] > dims[a] - 1) return false;
      continue;
    }
    double u = -o[a] / d[a], v = (dims[a] - 1 - o[a]) / d[a];
    if (u > v) std::swap(u, v);
    t0 = std::max(t0, u), t1 = std::min(t1, v);
  }
  return t1 > t0;
}

}  // namespace

WorkGrid estimateWork(const ClassifiedVolume& coarse, const Camera& camera, int width, int height,
                      double termination, int rays_across) {
  WorkGrid work{coarse.dims, {}};
  const Dims& n = coarse.dims;
  work.cost.assign(static_cast<std::size_t>(n[0]) * n[1] * n[2], 0.f);
  const double scale = static_cast<double>(rays_across) / std::max(width, height);
  const int rw = std::max(1, static_cast<int>(std::lround(width * scale)));
  const int rh = std::max(1, static_cast<int>(std::lround(height * scale)));
  const RayGenerator rays(camera, rw, rh);
  const glm::dvec3 centre = 0.5 * glm::dvec3(n[0] - 1, n[1] - 1, n[2] - 1);
  const int kt = coarse.t_channels;
  const double step = coarse.step_world;
  std::vector<double> T(kt);
  for (int y = 0; y < rh; ++y)
    for (int x = 0; x < rw; ++x) {
      const Ray ray = rays.ray(x + 0.5, y + 0.5);
      const glm::dvec3 o = ray.origin / coarse.spacing + centre;
      const glm::dvec3 d = ray.direction / coarse.spacing;
      double t0, t1;
      if (!clip(n, o, d, t0, t1)) continue;
      std::fill(T.begin(), T.end(), 1.0);
      for (double t = t0 + 0.5 * step; t < t1; t += step) {
        const glm::dvec3 p = o + t * d;
        std::size_t cell = 0;
        for (int a = 2; a >= 0; --a)
          cell = cell * n[a] + static_cast<std::size_t>(std::clamp(
                                   static_cast<int>(std::lround(p[a])), 0, n[a] - 1));
        const float value = coarse.values[cell];
        const int entry =
            coarse.labels ? static_cast<int>(value)
                          : static_cast<int>((value - coarse.value_lo) * coarse.value_scale);
        const int e = std::clamp(entry, 0, coarse.entries - 1);
        if (coarse.alpha[e] > 0.f) work.cost[cell] += 1.f;
        double largest = 0.0;
        for (int c = 0; c < kt; ++c)
          largest = std::max(largest, T[c] *= coarse.transmission[static_cast<std::size_t>(e) * kt + c]);
        if (largest < termination) break;
      }
    }
  return work;
}

}  // namespace svr
