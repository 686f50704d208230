#pragma once
// The ray-marching inner loop, templated on the channel count K (0 = dynamic), on whether
// transmittance is spectral (k channels) or scalar, and on where normals come from (the
// precomputed gradient volume, or central differences of the field on the fly when the
// gradients do not fit the memory budget). Included by one translation unit per instruction
// set (raycast_kernel_portable.cpp, raycast_kernel_avx2.cpp), each of which defines
// SVR_RAYCAST_ISA, the namespace its instantiations live in, so that the two compilations of
// the same templates never meet at link time. With AVX2 the eight corner weights of a
// trilinear cell are one vector, and a sample's value and gradient (kernels/gradient_volume.h)
// the four lanes of one multiply-add chain over its corners.
//
// Positions and steps are single precision inside the loop: sample positions are at most a
// few thousand voxels from the origin, where float keeps 1/4000 voxel; the ray set-up (box
// clipping, the first sample) stays in double so that the lattice does not depend on rounding.

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>

#include "renderers/classification/classification.h"
#include "renderers/classification/classified_sample.h"
#include "renderers/render/front_transmittance.h"
#include "renderers/kernels/gradient_volume.h"
#include "renderers/kernels/occupancy_pyramid.h"
#include "renderers/render/renderer.h"
#include "renderers/raycast/sample_table.h"

// SVR_RAYCAST_TARGET: the function attribute that compiles this namespace for the instruction
// set (target("avx2,fma")); the helpers below are always_inline, so they are compiled inside
// the kernels with it, and nothing compiled for AVX2 is ever shared with the portable path.
// SVR_RAYCAST_AVX2: 1 where the AVX2 intrinsics paths are used.
#if !defined(SVR_RAYCAST_ISA)
#error "define SVR_RAYCAST_ISA (the instruction set's namespace) before including raycast_kernel.h"
#endif
#if !defined(SVR_RAYCAST_TARGET)
#define SVR_RAYCAST_TARGET
#endif
#if SVR_RAYCAST_AVX2
#include <immintrin.h>
#endif

#include "renderers/simd/channel_widths.h"
#include "renderers/raycast/raycast_kernels.h"

namespace svr::raycast::SVR_RAYCAST_ISA {

#define SVR_RAYCAST_INLINE [[gnu::always_inline]] SVR_RAYCAST_TARGET inline

// The eight voxels around a sample: corner n is origin o + Grid::off[n], weight w[n].
struct Cell {
  std::size_t o;
  alignas(32) float w[8];
};

// Index arithmetic of the voxel grid, set up once per tile: a point (voxel coordinates) is
// clamped to the grid and its cell found with float operations only.
struct Grid {
  float hi[3];               // dims − 1
  int last_base[3];          // the largest cell origin: dims − 2 (0 for a one-voxel axis)
  std::size_t stride[3];     // index of a unit coordinate
  alignas(32) std::int32_t off[8];  // index offsets of the corners (0 along a one-voxel axis)

  SVR_RAYCAST_TARGET explicit Grid(const Dims& d) {
    const std::size_t s[3] = {1, static_cast<std::size_t>(d[0]),
                              static_cast<std::size_t>(d[0]) * d[1]};
    std::size_t step[3];
    for (int a = 0; a < 3; ++a) {
      hi[a] = static_cast<float>(d[a] - 1);
      last_base[a] = std::max(d[a] - 2, 0);
      stride[a] = s[a];
      step[a] = d[a] > 1 ? s[a] : 0;
    }
    for (int n = 0; n < 8; ++n)  // the renderer checks these fit (checkSliceSize)
      off[n] = static_cast<std::int32_t>(((n & 1) ? step[0] : 0) + ((n & 2) ? step[1] : 0) +
                                         ((n & 4) ? step[2] : 0));
  }

  SVR_RAYCAST_INLINE void cell(const float p[3], Cell& c) const {
    float f[3];
    c.o = 0;
    for (int a = 0; a < 3; ++a) {
      const float x = std::clamp(p[a], 0.f, hi[a]);
      const int i0 = std::min(static_cast<int>(x), last_base[a]);
      f[a] = x - static_cast<float>(i0);
      c.o += static_cast<std::size_t>(i0) * stride[a];
    }
#if SVR_RAYCAST_AVX2
    // Lane n: x weight f or 1 − f by bit 0 of n, y by bit 1, z by bit 2.
    const __m256 wx = _mm256_fmadd_ps(_mm256_set1_ps(f[0]),
                                      _mm256_setr_ps(-1, 1, -1, 1, -1, 1, -1, 1),
                                      _mm256_setr_ps(1, 0, 1, 0, 1, 0, 1, 0));
    const __m256 wy = _mm256_fmadd_ps(_mm256_set1_ps(f[1]),
                                      _mm256_setr_ps(-1, -1, 1, 1, -1, -1, 1, 1),
                                      _mm256_setr_ps(1, 1, 0, 0, 1, 1, 0, 0));
    const __m256 wz = _mm256_fmadd_ps(_mm256_set1_ps(f[2]),
                                      _mm256_setr_ps(-1, -1, -1, -1, 1, 1, 1, 1),
                                      _mm256_setr_ps(1, 1, 1, 1, 0, 0, 0, 0));
    _mm256_store_ps(c.w, _mm256_mul_ps(_mm256_mul_ps(wx, wy), wz));
#else
    const float gx[2] = {1.f - f[0], f[0]}, gy[2] = {1.f - f[1], f[1]}, gz[2] = {1.f - f[2], f[2]};
    for (int n = 0; n < 8; ++n) c.w[n] = gx[n & 1] * gy[(n >> 1) & 1] * gz[n >> 2];
#endif
  }

  // The trilinear interpolation of a float field over a cell.
  SVR_RAYCAST_INLINE float interpolate(const float* field, const Cell& c) const {
#if SVR_RAYCAST_AVX2
    const __m256i offsets = _mm256_load_si256(reinterpret_cast<const __m256i*>(off));
    const __m256 v = _mm256_i32gather_ps(field + c.o, offsets, 4);
    return horizontalSum(_mm256_mul_ps(v, _mm256_load_ps(c.w)));
#else
    float v = 0.f;
    for (int n = 0; n < 8; ++n) v += c.w[n] * field[c.o + off[n]];
    return v;
#endif
  }

  SVR_RAYCAST_INLINE float sample(const float* field, const float p[3]) const {
    Cell c;
    cell(p, c);
    return interpolate(field, c);
  }

#if SVR_RAYCAST_AVX2
  SVR_RAYCAST_INLINE static float horizontalSum(__m256 v) {
    const __m128 h = _mm_add_ps(_mm256_castps256_ps128(v), _mm256_extractf128_ps(v, 1));
    const __m128 q = _mm_add_ps(h, _mm_movehl_ps(h, h));
    return _mm_cvtss_f32(_mm_add_ss(q, _mm_movehdup_ps(q)));
  }
#endif
};

// binOf's arithmetic in float, set up once per tile.
struct BinScale {
  float lo, scale, last;  // bin = clamp((v − lo) · scale, 0, last)
  int last_lower, last_entry;
  SVR_RAYCAST_TARGET explicit BinScale(const ClassifiedVolume& cv)
      : lo(static_cast<float>(cv.value_lo)),
        scale(static_cast<float>(cv.value_scale)),
        last(static_cast<float>(cv.entries - 1)),
        last_lower(std::max(cv.entries - 2, 0)),
        last_entry(cv.entries - 1) {}
};

#if SVR_RAYCAST_AVX2
// One voxel's four int16 as floats.
SVR_RAYCAST_INLINE __m128 corner16(const std::int16_t* v) {
  return _mm_cvtepi32_ps(_mm_cvtepi16_epi32(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(v))));
}
#endif

// The precomputed (field, gradient) at a sample: the trilinear blend of the corners' four
// int16, in two chains of four multiply-adds, then decoded.
SVR_RAYCAST_INLINE void valueGradientAt(const GradientVolume& gv, const Grid& grid,
                                        const Cell& cell, float vg[4]) {
  const std::int16_t* base = gv.q.get() + 4 * cell.o;
#if SVR_RAYCAST_AVX2
  __m128 a = _mm_setzero_ps(), b = _mm_setzero_ps();
  for (int n = 0; n < 8; n += 2) {
    a = _mm_fmadd_ps(corner16(base + 4 * static_cast<std::ptrdiff_t>(grid.off[n])),
                     _mm_broadcast_ss(&cell.w[n]), a);
    b = _mm_fmadd_ps(corner16(base + 4 * static_cast<std::ptrdiff_t>(grid.off[n + 1])),
                     _mm_broadcast_ss(&cell.w[n + 1]), b);
  }
  _mm_storeu_ps(vg, _mm_fmadd_ps(_mm_add_ps(a, b), _mm_loadu_ps(gv.scale), _mm_loadu_ps(gv.offset)));
#else
  float s[4] = {0.f, 0.f, 0.f, 0.f};
  for (int n = 0; n < 8; ++n) {
    const std::int16_t* v = base + 4 * static_cast<std::ptrdiff_t>(grid.off[n]);
    for (int j = 0; j < 4; ++j) s[j] += cell.w[n] * static_cast<float>(v[j]);
  }
  for (int j = 0; j < 4; ++j) vg[j] = s[j] * gv.scale[j] + gv.offset[j];
#endif
}

// The gradient on the fly (the precomputed one did not fit): central differences of the
// interpolated shading field, world units.
SVR_RAYCAST_INLINE void gradientOnTheFly(const ClassifiedVolume& cv, const Grid& grid,
                                         const float p[3], const float half_inv_spacing[3],
                                         float g[3]) {
  const float* f = cv.shadingField().data();
  for (int a = 0; a < 3; ++a) {
    float hi[3] = {p[0], p[1], p[2]}, lo[3] = {p[0], p[1], p[2]};
    hi[a] += 1.f;
    lo[a] -= 1.f;
    g[a] = (grid.sample(f, hi) - grid.sample(f, lo)) * half_inv_spacing[a];
  }
}

// A sample's blended row of the sample table: acc = Σ w · row(e) over the entries around it
// (the two bins around a scalar volume's interpolated value v, or the eight corners' labels).
// kStride: the table's padded row length when k is fixed (the loops then have a compile-time
// count), else 0.
template <int kStride>
SVR_RAYCAST_INLINE void blendSample(const ClassifiedVolume& cv, const SampleTable& table,
                                    const Grid& grid, const Cell& cell, const BinScale& bins,
                                    float v, int width_, float* acc) {
  const int width = kStride > 0 ? kStride : width_;
  if (cv.labels) {
    for (int j = 0; j < width; ++j) acc[j] = 0.f;
    for (int n = 0; n < 8; ++n) {
      const float* row = table.row<kStride>(cv.label[cell.o + grid.off[n]]);
      for (int j = 0; j < width; ++j) acc[j] += cell.w[n] * row[j];
    }
  } else {
    const float bin = std::clamp((v - bins.lo) * bins.scale, 0.f, bins.last);
    const int e0 = std::min(static_cast<int>(bin), bins.last_lower);
    const int e1 = std::min(e0 + 1, bins.last_entry);
    const float f = bin - static_cast<float>(e0);
    const float* r0 = table.row<kStride>(e0);
    const float* r1 = table.row<kStride>(e1);
    for (int j = 0; j < width; ++j) acc[j] = r0[j] + f * (r1[j] - r0[j]);
  }
}

// The ray's parameter interval inside the grid's box [0, dims − 1] (voxel coordinates).
SVR_RAYCAST_INLINE bool clipToGrid(const Dims& dims, const glm::dvec3& o, const glm::dvec3& d,
                                   double& t0, double& t1) {
  t0 = 0.0, t1 = INFINITY;
  for (int a = 0; a < 3; ++a) {
    const double lo = 0.0, hi = dims[a] - 1;
    if (std::abs(d[a]) < 1e-300) {
      if (o[a] < lo || o[a] > hi) return false;
    } else {
      double ta = (lo - o[a]) / d[a], tb = (hi - o[a]) / d[a];
      if (ta > tb) std::swap(ta, tb);
      t0 = std::max(t0, ta);
      t1 = std::min(t1, tb);
    }
  }
  return t1 > t0;
}

// The index of the first lattice sample past the exit of the block of 2^shift voxels holding p
// (sample i, at t); inv_d = 1 / d per axis (inf on an axis the ray runs parallel to).
SVR_RAYCAST_INLINE long firstSamplePast(int shift, const float p[3], const float inv_d[3], long i,
                                       double t, double first, double step) {
  const float size = static_cast<float>(1 << shift);
  float exit = INFINITY;
  for (int a = 0; a < 3; ++a) {
    const float lo = static_cast<float>(static_cast<int>(std::max(p[a], 0.f)) >> shift) * size;
    const float bound = inv_d[a] > 0.f ? lo + size : lo;
    if (std::isfinite(inv_d[a])) exit = std::min(exit, (bound - p[a]) * inv_d[a]);
  }
  const double target = t + std::max(static_cast<double>(exit), 0.0);
  return std::max(static_cast<long>(std::ceil((target - first) / step)), i + 1);
}

// What a brick changes in the ray loop: the lattice of the whole grid, the range of sample
// indices that can lie in its own box, the ownership test, and the local origin. For a whole
// volume it is the identity (owns everything, origin 0).
struct BrickClip {
  bool bricked;
  Dims whole;
  float origin[3] = {0.f, 0.f, 0.f};
  // Own box in whole-grid voxel coordinates; open to ±∞ at the grid's faces, so that samples a
  // whole render clamps into the grid are owned too.
  float lo[3], hi[3];

  SVR_RAYCAST_TARGET explicit BrickClip(const ClassifiedVolume& cv)
      : bricked(cv.brick.has_value()), whole(bricked ? cv.brick->whole : cv.dims) {
    for (int a = 0; a < 3; ++a) {
      lo[a] = -INFINITY, hi[a] = INFINITY;
      if (!bricked) continue;
      const VolumeBrick& b = *cv.brick;
      origin[a] = static_cast<float>(b.stored.lo[a]);
      if (b.own.lo[a] > 0) lo[a] = static_cast<float>(b.own.lo[a]);
      if (b.own.hi[a] < whole[a]) hi[a] = static_cast<float>(b.own.hi[a]);
    }
  }

  SVR_RAYCAST_INLINE bool owns(const float p[3]) const {
    return p[0] >= lo[0] && p[0] < hi[0] && p[1] >= lo[1] && p[1] < hi[1] && p[2] >= lo[2] &&
           p[2] < hi[2];
  }

  // The sample indices [begin, end) of the ray (in the grid over [t0, t1], first sample at
  // t0 + step/2) that may be owned: all of them for a whole volume; for a brick, those within a
  // sample of the ray's interval in the own box (owns() decides at the edges). False: none.
  SVR_RAYCAST_TARGET bool range(const glm::dvec3& o, const glm::dvec3& d, double t0, double t1,
                                double step, long& begin, long& end) const {
    const double first = t0 + 0.5 * step;
    begin = 0, end = static_cast<long>(std::ceil((t1 - first) / step));
    if (!bricked) return end > 0;
    double ta = t0, tb = t1;
    for (int a = 0; a < 3; ++a) {
      const double l = std::isfinite(lo[a]) ? lo[a] : -1e300, h = std::isfinite(hi[a]) ? hi[a] : 1e300;
      if (std::abs(d[a]) < 1e-300) {
        if (o[a] < l - 1.0 || o[a] > h + 1.0) return false;
        continue;
      }
      double u = (l - o[a]) / d[a], v = (h - o[a]) / d[a];
      if (u > v) std::swap(u, v);
      ta = std::max(ta, u), tb = std::min(tb, v);
    }
    if (tb < ta) return false;
    begin = std::max(begin, static_cast<long>(std::floor((ta - first) / step)) - 1);
    end = std::min(end, static_cast<long>(std::ceil((tb - first) / step)) + 2);
    return end > begin;
  }
};

// The transmittance in front of a brick at pixel (x, y), channel by channel into front[0, kt),
// and its largest channel: a brick's rays stop where the whole render's do. 1 without a front.
SVR_RAYCAST_INLINE float frontTransmittance(const TileJob& job, int x, int y, int kt, float* front) {
  if (!job.front) {
    for (int c = 0; c < kt; ++c) front[c] = 1.f;
    return 1.f;
  }
  constexpr int n = FrontTransmittance::kBlock;
  const std::size_t at = static_cast<std::size_t>(y - job.front_y0) * n + (x - job.front_x0);
  float front_max = 0.f;
  for (int c = 0; c < kt; ++c) {
    front[c] = job.front[c * n * n + at];
    front_max = std::max(front_max, front[c]);
  }
  return front_max;
}

template <int K, bool kSpectralT, bool kPrecomputedGradients>
SVR_RAYCAST_TARGET void traceTile(const TileJob& job) {
  const ClassifiedVolume& cv = *job.volume;
  const RenderRequest& req = *job.request;
  const SampleTable& table = *job.table;
  const int k = K > 0 ? K : cv.k;
  constexpr int kCap = K > 0 ? K : kMaxChannels;
  const int kt = kSpectralT ? k : 1;
  const int width = 2 + k + kt;  // a sample-table row
  if (width < 3) __builtin_unreachable();  // k ≥ 1: tells the compiler acc[0] is always set
  constexpr int kStride = K > 0 ? SampleTable::strideFor(2 + K + (kSpectralT ? K : 1)) : 0;
  constexpr int kWidthCap = SampleTable::strideFor(2 + kCap + (kSpectralT ? kCap : 1));
  const Dims& dims = cv.dims;
  const Grid grid(dims);
  const BinScale bins(cv);
  const glm::dvec3 inv_spacing = 1.0 / cv.spacing;
  const float half_inv_spacing[3] = {static_cast<float>(0.5 * inv_spacing.x),
                                     static_cast<float>(0.5 * inv_spacing.y),
                                     static_cast<float>(0.5 * inv_spacing.z)};
  // A brick samples the whole grid's lattice and takes only its own samples (volume/brick_box.h),
  // at local positions p − origin (exact: p ≥ origin ≥ 0 and both are on float's grid there).
  const BrickClip brick(cv);
  const Dims& whole = brick.whole;
  const glm::dvec3 centre = 0.5 * glm::dvec3(whole[0] - 1, whole[1] - 1, whole[2] - 1);
  const double step = cv.step_world;
  const float threshold = static_cast<float>(req.termination);
  const std::size_t pixels = job.image->pixels();
  float* out = job.image->planeFloat(0).data();

  // The shading set up once (its highlight floor takes a pow); directions change per ray.
  PhongSetup phong_setup(req.shading, glm::dvec3(0.0, 0.0, 1.0), glm::dvec3(0.0, 0.0, 1.0));
  for (int y = job.y0; y < job.y1; ++y)
    for (int x = job.x0; x < job.x1; ++x) {
      float S[kCap], T[kSpectralT ? kCap : 1];
      for (int c = 0; c < k; ++c) S[c] = 0.f;
      for (int c = 0; c < kt; ++c) T[c] = 1.f;
      float front[kSpectralT ? kCap : 1];
      const float front_max = frontTransmittance(job, x, y, kt, front);

      const Ray ray = job.rays->ray(x + 0.5, y + 0.5);
      const glm::dvec3 o = ray.origin * inv_spacing + centre;
      const glm::dvec3 d = ray.direction * inv_spacing;  // voxels per world unit
      double t0, t1;
      long i_begin = 0, i_end = 0;
      if (!(front_max < threshold) && clipToGrid(whole, o, d, t0, t1) &&
          brick.range(o, d, t0, t1, step, i_begin, i_end)) {
        const glm::dvec3 view = -ray.direction;
        const glm::dvec3 light = req.light_direction ? *req.light_direction : view;
        phong_setup.setDirections(light, glm::normalize(light + view));
        const double first = t0 + 0.5 * step;
        float of[3], df[3], inv_d[3];
        for (int a = 0; a < 3; ++a) {
          of[a] = static_cast<float>(o[a]);
          df[a] = static_cast<float>(d[a]);
          inv_d[a] = std::abs(df[a]) > 1e-30f ? 1.f / df[a] : INFINITY;
        }
        const float first_f = static_cast<float>(first), step_f = static_cast<float>(step);
        long occupied_until = 0;
        for (long i = i_begin; i < i_end;) {
          const float t = first_f + static_cast<float>(i) * step_f;
          float p[3] = {of[0] + t * df[0], of[1] + t * df[1], of[2] + t * df[2]};
          if (brick.bricked) {
            if (!brick.owns(p)) {
              ++i;
              continue;
            }
            for (int a = 0; a < 3; ++a) p[a] -= brick.origin[a];
          }
          // Empty space: jump past the largest empty block; in an occupied block, look again
          // only once the ray has left it.
          if (req.empty_space_skipping && i >= occupied_until) {
            int c[3];
            for (int a = 0; a < 3; ++a)
              c[a] = static_cast<int>(std::clamp(p[a], 0.f, grid.hi[a]));
            const int level = job.occupancy->emptyLevel(c[0], c[1], c[2]);
            if (level >= 0) {
              i = firstSamplePast(job.occupancy->shift(level), p, inv_d, i, t, first, step);
              continue;
            }
            occupied_until = firstSamplePast(job.occupancy->shift(0), p, inv_d, i, t, first, step);
          }
          Cell cell;
          grid.cell(p, cell);
          float vg[4];  // the value and gradient, when precomputed
          float v = 0.f;
          if constexpr (kPrecomputedGradients) {
            valueGradientAt(*job.gradients, grid, cell, vg);
            v = vg[0];
          } else if (!cv.labels) {
            v = grid.interpolate(cv.values.data(), cell);
          }
          float acc[kWidthCap];
          blendSample<kStride>(cv, table, grid, cell, bins, v, width, acc);
          if (acc[0] > 0.f) {  // α
            float g[3];
            if constexpr (kPrecomputedGradients)
              g[0] = vg[1], g[1] = vg[2], g[2] = vg[3];
            else
              gradientOnTheFly(cv, grid, p, half_inv_spacing, g);
            const auto [shade, highlight] = phong(phong_setup, g);
            const float hs = highlight * acc[1];
            for (int c = 0; c < k; ++c)
              S[c] += T[kSpectralT ? c : 0] * (acc[2 + c] * shade + cv.white[c] * hs);
          }
          float tmax = 0.f;
          for (int c = 0; c < kt; ++c) {
            T[c] *= acc[2 + k + c];
            tmax = std::max(tmax, front[c] * T[c]);
          }
          if (tmax < threshold) break;
          ++i;
        }
      }
      const std::size_t px = static_cast<std::size_t>(y) * job.image->width() + x;
      for (int c = 0; c < k; ++c) out[c * pixels + px] = S[c];
      for (int c = 0; c < kt; ++c) out[(k + c) * pixels + px] = T[c];
    }
}

#undef SVR_RAYCAST_INLINE

// The kernel for a key: pickWidth's compiled widths, else the dynamic path.
template <bool kSpectralT, bool kPrecomputed>
TileFn pickFor(const KernelKey& key) {
  return pickWidth(key.k, key.dynamic_width, []<int N>() -> TileFn {
    return &traceTile<N, kSpectralT, kPrecomputed>;
  });
}

inline TileFn pickKernel(const KernelKey& key) {
  if (key.t_channels > 1)
    return key.precomputed_gradients ? pickFor<true, true>(key) : pickFor<true, false>(key);
  return key.precomputed_gradients ? pickFor<false, true>(key) : pickFor<false, false>(key);
}

}  // namespace svr::raycast::SVR_RAYCAST_ISA
