#include "renderers/render/front_transmittance.h"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>

#include "spectral/light_independent_image.h"

namespace svr {

std::vector<int> footprintBlocks(const VoxelBox& own, const Dims& whole,
                                 const glm::dvec3& spacing, const Camera& camera, int width,
                                 int height) {
  const RayGenerator rays(camera, width, height);
  const int bx = FrontTransmittance::blocksAcross(width);
  const int by = FrontTransmittance::blocksAcross(height);
  double x_lo = INFINITY, x_hi = -INFINITY, y_lo = INFINITY, y_hi = -INFINITY;
  bool everywhere = false;
  for (int corner = 0; corner < 8 && !everywhere; ++corner) {
    glm::dvec3 world;
    for (int a = 0; a < 3; ++a) {
      // A voxel beyond the own box: the samples owned at its faces, with room for rounding.
      const double v = (corner >> a & 1) ? own.hi[a] + 1.0 : own.lo[a] - 1.0;
      world[a] = (v - 0.5 * (whole[a] - 1)) * spacing[a];  // design.md §7
    }
    const glm::dvec3 q = world - camera.eye;
    double u = glm::dot(q, rays.right()), v = glm::dot(q, rays.up());
    if (!camera.orthographic()) {
      const double depth = glm::dot(q, rays.forward());
      if (!(depth > 1e-9)) {  // a corner at or behind the eye: the box may fill the view
        everywhere = true;
        break;
      }
      u /= depth, v /= depth;
    }
    // Inverse of RayGenerator::ray: u = (2px/width − 1)·halfWidth,
    // v = (1 − 2py/height)·halfHeight.
    const double px = 0.5 * width * (u / rays.halfWidth() + 1.0);
    const double py = 0.5 * height * (1.0 - v / rays.halfHeight());
    x_lo = std::min(x_lo, px), x_hi = std::max(x_hi, px);
    y_lo = std::min(y_lo, py), y_hi = std::max(y_hi, py);
  }
  std::vector<int> blocks;
  // The blocks of the rectangle a pixel wider on each side.
  const auto blockOf = [](double p) {
    return static_cast<int>(std::floor(p / FrontTransmittance::kBlock));
  };
  const auto first = [&](double p) { return blockOf(p - 1.0); };
  const auto last = [&](double p) { return blockOf(p + 1.0); };
  const int x0 = everywhere ? 0 : std::max(first(x_lo), 0);
  const int x1 = everywhere ? bx - 1 : std::min(last(x_hi), bx - 1);
  const int y0 = everywhere ? 0 : std::max(first(y_lo), 0);
  const int y1 = everywhere ? by - 1 : std::min(last(y_hi), by - 1);
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x) blocks.push_back(y * bx + x);
  return blocks;
}

void copyBlockTransmittance(const LightIndependentImage& image, int block, float* out) {
  constexpr int n = FrontTransmittance::kBlock;
  const int bx = FrontTransmittance::blocksAcross(image.width());
  const int x0 = block % bx * n, y0 = block / bx * n;
  const int k = image.channels();
  for (int c = 0; c < image.transmittanceChannels(); ++c) {
    const auto plane = image.planeFloat(k + c);
    float* dest = out + static_cast<std::size_t>(c) * n * n;
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        const int ix = x0 + x, iy = y0 + y;
        dest[y * n + x] = ix < image.width() && iy < image.height()
                              ? plane[static_cast<std::size_t>(iy) * image.width() + ix]
                              : 1.f;
      }
  }
}

}  // namespace svr
