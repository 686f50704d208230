#pragma once
// What the peer benchmarks (bench/peers/) share with the peers: the engine scene's views and its
// transfer function reduced to one entry per 8-bit voxel value, the form VolPack's classifier
// and lookup shader and VTK's piecewise functions take.

#include <array>
#include <cmath>
#include <glm/geometric.hpp>
#include <string>
#include <vector>

#include "bench/engine_scene.h"
#include "renderers/classification/classified_sample.h"
#include "renderers/render/renderer.h"

namespace svr::peers {

// The elevation of the engine scene's camera; the benches orbit at it and vary the azimuth.
inline constexpr double kElevation = 30.0;

// The scene's orthographic camera (its distance and zoom) at another azimuth.
inline Camera engineCamera(double azimuth_deg) {
  const Camera& c = engineBenchScene().scene.camera;
  return Camera::orbit(azimuth_deg, kElevation, glm::length(c.eye - c.target), 0.0,
                       c.ortho_height);
}

inline RenderRequest engineRequest(const ClassifiedVolume& cv, double azimuth_deg, int size) {
  RenderRequest request = engineRequest(cv, size);
  request.camera = engineCamera(azimuth_deg);
  return request;
}

// The transfer function at the 256 values of the 8-bit engine volume, from the rgb
// classification exactly as our backends sample it (binOf + blendEntries):
//   opacity:   per unit world length (= per voxel; spacing 1), 1 − (1 − α_step)^(1/Δs), the
//              convention of VolPack's classifier (corrected per view for the slice spacing)
//              and of VTK's ScalarOpacityUnitDistance = 1;
//   rgb:       linear sRGB reflectance (opacity-weighted between bins, as our samples are);
//   specular:  the specular weight that scales the flat-white highlight.
struct ValueTables {
  std::array<float, 256> opacity{};
  std::array<std::array<float, 3>, 256> rgb{};
  std::array<float, 256> specular{};
};

inline ValueTables engineValueTables() {
  const ClassifiedVolume& cv = engineClassified("rgb");
  ValueTables t;
  for (int v = 0; v < 256; ++v) {
    int entry[2];
    float frac;
    binOf(cv, static_cast<float>(v), entry[0], entry[1], frac);
    const float w[2] = {1.f - frac, frac};
    float alpha, spec, refl[3], trans[3];
    blendEntries(cv, cv.alpha.data(), cv.transmission.data(), entry, w, 2, 3, cv.t_channels,
                 alpha, spec, refl, trans);
    t.opacity[v] = static_cast<float>(1.0 - std::pow(1.0 - alpha, 1.0 / cv.step_world));
    for (int c = 0; c < 3; ++c) t.rgb[v][c] = refl[c];
    t.specular[v] = spec;
  }
  return t;
}

}  // namespace svr::peers
