#include "renderers/shearwarp/shear_warp_factorization.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <glm/vec2.hpp>

#include "base/error.h"

namespace svr::shearwarp {

ShearWarpFactorization factorizeView(const Camera& camera, int width, int height,
                                     const Dims& dims, const glm::dvec3& spacing, int scale) {
  if (!camera.orthographic())
    throw Error(fmt::format("shearwarp: the camera has a field of view of {}°; only "
                            "orthographic cameras (fov 0) are supported — perspective "
                            "shear-warp is not implemented",
                            camera.fov_degrees));
  const RayGenerator rays(camera, width, height);
  const glm::dvec3 inv_spacing = 1.0 / spacing;
  const glm::dvec3 centre = 0.5 * glm::dvec3(dims[0] - 1, dims[1] - 1, dims[2] - 1);
  const glm::dvec3 d = rays.forward() * inv_spacing;  // voxels per world unit along the view

  ShearWarpFactorization f;
  f.scale = scale;
  f.axis = 0;
  for (int a = 1; a < 3; ++a)
    if (std::abs(d[a]) > std::abs(d[f.axis])) f.axis = a;
  f.axis_i = (f.axis + 1) % 3;
  f.axis_j = (f.axis + 2) % 3;
  if (f.axis == 1) std::swap(f.axis_i, f.axis_j);  // as AxisEncoding: rows along x
  const int c = f.axis, i = f.axis_i, j = f.axis_j;
  f.increasing = d[c] > 0;
  f.shear_i = d[i] / d[c];
  f.shear_j = d[j] / d[c];
  const glm::dvec3 per_slice = (d / d[c]) * spacing;  // world displacement from one slice on
  f.slice_spacing_world = glm::length(per_slice);

  // The crossings a of every ray that meets the volume, with one empty pixel of margin so the
  // warp's bilinear footprint at the rim reads empty space.
  const int last_k = dims[c] - 1;
  const double lo_i = std::min(0.0, -f.shear_i * last_k), lo_j = std::min(0.0, -f.shear_j * last_k);
  const double hi_i = std::max<double>(dims[i] - 1, dims[i] - 1 - f.shear_i * last_k);
  const double hi_j = std::max<double>(dims[j] - 1, dims[j] - 1 - f.shear_j * last_k);
  f.offset_i = lo_i - 1.0 / scale;
  f.offset_j = lo_j - 1.0 / scale;
  f.width = static_cast<int>(std::ceil((hi_i - f.offset_i) * scale)) + 2;
  f.height = static_cast<int>(std::ceil((hi_j - f.offset_j) * scale)) + 2;

  // The warp: where the ray of a final pixel crosses slice 0, as an affine map of (px, py).
  const auto crossing = [&](double px, double py) {
    const Ray r = rays.ray(px, py);
    const glm::dvec3 o = r.origin * inv_spacing + centre;
    const glm::dvec3 a = o + (-o[c] / d[c]) * d;
    return glm::dvec2((a[i] - f.offset_i) * scale, (a[j] - f.offset_j) * scale);
  };
  const glm::dvec2 p00 = crossing(0, 0), p10 = crossing(1, 0), p01 = crossing(0, 1);
  f.warp_u[0] = p00.x;
  f.warp_u[1] = p10.x - p00.x;
  f.warp_u[2] = p01.x - p00.x;
  f.warp_v[0] = p00.y;
  f.warp_v[1] = p10.y - p00.y;
  f.warp_v[2] = p01.y - p00.y;
  return f;
}

int supersampleForScreen(const ShearWarpFactorization& view, int max) {
  // J = [warp_u[1] warp_u[2]; warp_v[1] warp_v[2]], intermediate pixels per final pixel; the
  // eigenvalues of JᵀJ are its singular values squared.
  const double a = view.warp_u[1] * view.warp_u[1] + view.warp_v[1] * view.warp_v[1];
  const double c = view.warp_u[2] * view.warp_u[2] + view.warp_v[2] * view.warp_v[2];
  const double b = view.warp_u[1] * view.warp_u[2] + view.warp_v[1] * view.warp_v[2];
  const double smallest = std::sqrt(std::max(0.0, 0.5 * (a + c - std::hypot(a - c, 2.0 * b))));
  const double pixels_per_voxel = view.scale / std::max(smallest, 1e-12);
  // A relative slack, so that exactly one pixel a voxel (up to rounding) stays at 1.
  return static_cast<int>(std::clamp(std::ceil(pixels_per_voxel * (1.0 - 1e-9)), 1.0,
                                     static_cast<double>(max)));
}

void sampleBetweenSlices(ShearWarpFactorization& view, int m) {
  view.slice_spacing_world = view.slice_spacing_world * view.slice_samples / m;
  view.slice_samples = m;
}

int sliceSamplesForStep(const ShearWarpFactorization& view, double step_world, int max) {
  const double voxel_slice = view.slice_spacing_world * view.slice_samples;
  // A relative slack, so that a spacing equal to the step (up to rounding) takes no extra sample.
  const double needed = std::ceil(voxel_slice / step_world * (1.0 - 1e-9));
  return static_cast<int>(std::clamp(needed, 1.0, static_cast<double>(max)));
}

}  // namespace svr::shearwarp
