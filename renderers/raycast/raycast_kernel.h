#pragma once
// The ray-marching inner loop, templated on the channel count K (0 = dynamic) and on whether
// transmittance is spectral (k channels) or scalar. Included only by raycast_renderer.cpp.

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>

#include "renderers/core/classification.h"
#include "renderers/core/classified_sample.h"
#include "renderers/core/renderer.h"

namespace svr::raycast {

inline constexpr int kMaxChannels = 128;

struct TileJob {
  const ClassifiedVolume* volume;
  const RayGenerator* rays;
  const RenderRequest* request;
  LightIndependentImage* image;
  int x0, y0, x1, y1;
};

// Trilinear interpolation of a voxel field at p (voxel coordinates), clamped to the grid.
struct Trilinear {
  std::size_t i[8];
  float w[8];
};

inline void cellAt(const Dims& dims, const glm::dvec3& p, Trilinear& t) {
  int base[3];
  float f[3];
  for (int a = 0; a < 3; ++a) {
    const double c = std::clamp(p[a], 0.0, static_cast<double>(dims[a] - 1));
    int i0 = static_cast<int>(c);
    if (i0 >= dims[a] - 1) i0 = std::max(dims[a] - 2, 0);
    base[a] = i0;
    f[a] = dims[a] > 1 ? static_cast<float>(c - i0) : 0.0f;
  }
  const std::size_t sx = 1, sy = dims[0], sz = static_cast<std::size_t>(dims[0]) * dims[1];
  const std::size_t o = base[0] * sx + base[1] * sy + base[2] * sz;
  const std::size_t dx = dims[0] > 1 ? sx : 0, dy = dims[1] > 1 ? sy : 0, dz = dims[2] > 1 ? sz : 0;
  for (int c = 0; c < 8; ++c) {
    t.i[c] = o + ((c & 1) ? dx : 0) + ((c & 2) ? dy : 0) + ((c & 4) ? dz : 0);
    t.w[c] = ((c & 1) ? f[0] : 1 - f[0]) * ((c & 2) ? f[1] : 1 - f[1]) * ((c & 4) ? f[2] : 1 - f[2]);
  }
}

inline float sampleField(const std::vector<float>& field, const Dims& dims, const glm::dvec3& p) {
  Trilinear t;
  cellAt(dims, p, t);
  float v = 0.f;
  for (int c = 0; c < 8; ++c) v += t.w[c] * field[t.i[c]];
  return v;
}

template <int K, bool kSpectralT>
void traceTile(const TileJob& job) {
  const ClassifiedVolume& cv = *job.volume;
  const RenderRequest& req = *job.request;
  const int k = K > 0 ? K : cv.k;
  constexpr int kCap = K > 0 ? K : kMaxChannels;
  const int kt = kSpectralT ? k : 1;
  const Dims& dims = cv.dims;
  const glm::dvec3 inv_spacing = 1.0 / cv.spacing;
  const glm::dvec3 centre = 0.5 * glm::dvec3(dims[0] - 1, dims[1] - 1, dims[2] - 1);
  const double step = cv.step_world;
  const float threshold = static_cast<float>(req.termination);
  const int B = ClassifiedVolume::kBlock;
  const std::size_t pixels = job.image->pixels();
  float* out = job.image->planeFloat(0).data();

  for (int y = job.y0; y < job.y1; ++y)
    for (int x = job.x0; x < job.x1; ++x) {
      float S[kCap], T[kSpectralT ? kCap : 1];
      for (int c = 0; c < k; ++c) S[c] = 0.f;
      for (int c = 0; c < kt; ++c) T[c] = 1.f;

      const Ray ray = job.rays->ray(x + 0.5, y + 0.5);
      const glm::dvec3 o = ray.origin * inv_spacing + centre;
      const glm::dvec3 d = ray.direction * inv_spacing;  // voxels per world unit
      double t0 = 0.0, t1 = INFINITY;
      bool hit = true;
      for (int a = 0; a < 3 && hit; ++a) {
        const double lo = 0.0, hi = dims[a] - 1;
        if (std::abs(d[a]) < 1e-300) {
          hit = o[a] >= lo && o[a] <= hi;
        } else {
          double ta = (lo - o[a]) / d[a], tb = (hi - o[a]) / d[a];
          if (ta > tb) std::swap(ta, tb);
          t0 = std::max(t0, ta);
          t1 = std::min(t1, tb);
        }
      }
      if (hit && t1 > t0) {
        const glm::dvec3 view = -ray.direction;
        const glm::dvec3 light = req.light_direction ? *req.light_direction : view;
        const glm::dvec3 half = glm::normalize(light + view);
        const PhongSetup phong_setup(req.shading, light, half);
        const double first = t0 + 0.5 * step;
        for (double t = first; t < t1;) {
          const glm::dvec3 p = o + t * d;
          if (req.empty_space_skipping) {
            int b[3];
            for (int a = 0; a < 3; ++a)
              b[a] = std::clamp(static_cast<int>(p[a]) / B, 0, cv.blocks[a] - 1);
            if (!cv.blockOccupied(b[0], b[1], b[2])) {
              // Jump to the block's exit, staying on the same sample lattice.
              double exit = INFINITY;
              for (int a = 0; a < 3; ++a) {
                if (d[a] > 1e-300) exit = std::min(exit, ((b[a] + 1) * B - p[a]) / d[a]);
                else if (d[a] < -1e-300) exit = std::min(exit, (b[a] * B - p[a]) / d[a]);
              }
              const double target = t + std::max(exit, 0.0);
              t = first + std::max(std::ceil((target - first) / step), 1.0 + std::floor((t - first) / step)) * step;
              continue;
            }
          }
          // Classified sample: alpha, reflectance, specular weight, transmission.
          float alpha, spec_w, refl[kCap], trans[kSpectralT ? kCap : 1];
          Trilinear cell;
          cellAt(dims, p, cell);
          if (cv.labels) {
            // Classify each corner's label, then blend the classified entries.
            int entry[8];
            for (int n = 0; n < 8; ++n) entry[n] = cv.label[cell.i[n]];
            blendEntries(cv, cv.alpha.data(), cv.transmission.data(), entry, cell.w, 8, k, kt,
                         alpha, spec_w, refl, trans);
          } else {
            float v = 0.f;
            for (int n = 0; n < 8; ++n) v += cell.w[n] * cv.values[cell.i[n]];
            int entry[2];
            float frac;
            binOf(cv, v, entry[0], entry[1], frac);
            const float w[2] = {1.f - frac, frac};
            blendEntries(cv, cv.alpha.data(), cv.transmission.data(), entry, w, 2, k, kt, alpha,
                         spec_w, refl, trans);
          }
          if (alpha > 0.f) {
            // Phong with the gradient of the shading field (central differences, world units).
            float g[3];
            for (int a = 0; a < 3; ++a) {
              glm::dvec3 e(0.0);
              e[a] = 1.0;
              g[a] = static_cast<float>((sampleField(cv.shading_field, dims, p + e) -
                                         sampleField(cv.shading_field, dims, p - e)) *
                                        0.5 * inv_spacing[a]);
            }
            const auto [shade, highlight] = phong(phong_setup, g);
            const float hs = highlight * spec_w;
            if constexpr (kSpectralT) {
              for (int c = 0; c < k; ++c)
                S[c] += T[c] * alpha * (refl[c] * shade + cv.white[c] * hs);
            } else {
              for (int c = 0; c < k; ++c) S[c] += T[0] * alpha * (refl[c] * shade + cv.white[c] * hs);
            }
          }
          float tmax = 0.f;
          for (int c = 0; c < kt; ++c) {
            T[c] *= trans[c];
            tmax = std::max(tmax, T[c]);
          }
          if (tmax < threshold) break;
          t += step;
        }
      }
      const std::size_t px = static_cast<std::size_t>(y) * job.image->width() + x;
      for (int c = 0; c < k; ++c) out[c * pixels + px] = S[c];
      for (int c = 0; c < kt; ++c) out[(k + c) * pixels + px] = T[c];
    }
}

}  // namespace svr::raycast
