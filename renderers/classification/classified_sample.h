#pragma once
// One classified, shaded sample — the part every backend shares (design.md §5): the classification
// entries around a sample blended into α, reflectance, specular weight and transmission, and the
// Phong terms from a gradient. Backends differ in where samples lie and how they composite, not
// in what a sample is, so this lives here once.

#include <algorithm>
#include <cmath>
#include <span>
#include <vector>
#include <glm/vec3.hpp>

#include "renderers/classification/classification.h"
#include "renderers/simd/float4.h"
#include "renderers/scene/scene.h"
#include "renderers/simd/unit_power.h"

namespace svr {

// Blends n classification entries with weights w (summing to 1) into one sample. α and the
// transmission interpolate as they are; reflectance and the specular weight are opacity-weighted
// (Wittenbrink, Malzbender & Goss 1998), so at a material's edge against empty space the
// sample fades in opacity rather than in colour — interpolating colour alone would blend in the
// empty entry's black and darken every boundary. `alpha` and `transmission` are the per-sample
// tables (the classification's, or a backend's copy corrected for its own sample spacing).
inline void blendEntries(const ClassifiedVolume& cv, const float* alpha_table,
                         const float* transmission_table, const int* entry, const float* w, int n,
                         int k, int kt, float& alpha, float& spec_w, float* refl, float* trans) {
  alpha = spec_w = 0.f;
  for (int c = 0; c < k; ++c) refl[c] = 0.f;
  for (int c = 0; c < kt; ++c) trans[c] = 0.f;
  for (int i = 0; i < n; ++i) {
    const int e = entry[i];
    const float a = w[i] * alpha_table[e];
    alpha += a;
    spec_w += a * cv.specular[e];
    const float* r = &cv.reflectance[static_cast<std::size_t>(e) * k];
    for (int c = 0; c < k; ++c) refl[c] += a * r[c];
    const float* t = &transmission_table[static_cast<std::size_t>(e) * kt];
    for (int c = 0; c < kt; ++c) trans[c] += w[i] * t[c];
  }
  if (alpha > 0.f) {
    const float inv = 1.f / alpha;
    spec_w *= inv;
    for (int c = 0; c < k; ++c) refl[c] *= inv;
  }
}

// Every entry as one row of a blend table, [α, α·specular, α·ρ_0 … α·ρ_{k−1}, t_0 … t_{kt−1}]
// (2 + k + kt floats, padded with zeros to `stride`), so that blending entries is a lerp of
// rows and the opacity weighting needs no division until the end. `alpha` and `transmission`
// are per-entry tables: the classification's (the raycaster's sample table, the pre-classified
// shear-warp records), shear-warp's corrected for its slice spacing, or the splats' per unit
// length.
inline std::vector<float> blendRows(const ClassifiedVolume& cv, const float* alpha,
                                    const float* transmission, int stride) {
  const int k = cv.k, kt = cv.t_channels;
  std::vector<float> rows(static_cast<std::size_t>(cv.entries) * stride, 0.f);
  for (int e = 0; e < cv.entries; ++e) {
    float* row = &rows[static_cast<std::size_t>(e) * stride];
    const float a = alpha[e];
    row[0] = a;
    row[1] = a * cv.specular[e];
    for (int c = 0; c < k; ++c)
      row[2 + c] = a * cv.reflectance[static_cast<std::size_t>(e) * k + c];
    for (int c = 0; c < kt; ++c) row[2 + k + c] = transmission[static_cast<std::size_t>(e) * kt + c];
  }
  return rows;
}

// A scalar value's bin coordinate in the classification table (entry + fraction, not yet
// clamped to the table). It is linear in the value, so backends that interpolate may store and
// interpolate bin coordinates instead of values. In float, as the raycaster's BinScale: a
// loop over voxels takes four at a time where double arithmetic would take two and convert
// twice.
inline float binCoordinate(const ClassifiedVolume& cv, float value) {
  return (value - static_cast<float>(cv.value_lo)) * static_cast<float>(cv.value_scale);
}

// The two classification entries a bin coordinate falls between (clamped to the table), and
// the weight of the upper.
inline void entriesOfBin(const ClassifiedVolume& cv, float bin, int& e0, int& e1, float& frac) {
  bin = std::clamp(bin, 0.f, static_cast<float>(cv.entries - 1));
  e0 = std::min(static_cast<int>(bin), std::max(cv.entries - 2, 0));
  e1 = std::min(e0 + 1, cv.entries - 1);
  frac = bin - e0;
}

// entriesOfBin for four bin coordinates at once (finite ones: a NaN has no entry), each lane
// with the scalar's operations: the same entries and the same weight.
inline void entriesOfBins(const ClassifiedVolume& cv, Float4 bins, Int4& e0, Int4& e1,
                          Float4& frac) {
  const Float4 last = splat4(static_cast<float>(cv.entries - 1));
  const int l = cv.entries - 1, t = std::max(cv.entries - 2, 0);
  const Int4 last_entry{l, l, l, l}, top{t, t, t, t};
  Float4 b = bins < splat4(0.f) ? splat4(0.f) : bins;
  b = last < b ? last : b;
  e0 = __builtin_convertvector(b, Int4);
  e0 = e0 < top ? e0 : top;
  e1 = e0 + 1 < last_entry ? e0 + 1 : last_entry;
  frac = b - __builtin_convertvector(e0, Float4);
}

// prefix[e]: how many entries below e have non-zero opacity (entries + 1 values), so that
// whether a range of entries holds a visible one is one subtraction.
inline std::vector<int> nonzeroOpacityPrefix(const ClassifiedVolume& cv) {
  std::vector<int> prefix(cv.entries + 1, 0);
  for (int e = 0; e < cv.entries; ++e) prefix[e + 1] = prefix[e] + (cv.alpha[e] > 0.f);
  return prefix;
}

// Whether a sample whose bin coordinate lies in [lo, hi] can have non-zero opacity: its table
// lookup blends the entries floor(lo) .. ceil(hi), clamped to the table (a bin hit exactly
// takes its upper neighbour with weight 0). `prefix`: nonzeroOpacityPrefix(cv).
inline bool binRangeVisible(const ClassifiedVolume& cv, std::span<const int> prefix, float lo,
                            float hi) {
  const int last = cv.entries - 1;
  const int b0 = std::clamp(static_cast<int>(std::floor(lo)), 0, last);
  const int b1 = std::clamp(static_cast<int>(std::ceil(hi)), 0, last);
  return prefix[b1 + 1] - prefix[b0] > 0;
}

// The two classification entries a scalar value falls between, and the weight of the upper.
inline void binOf(const ClassifiedVolume& cv, float value, int& e0, int& e1, float& frac) {
  entriesOfBin(cv, binCoordinate(cv, value), e0, e1, frac);
}

// The Phong model of every backend, two-sided (|n·l|, as volume boundaries have no outside):
// `shade` multiplies the reflectance, `highlight` the white (times the specular weight).
struct PhongTerms {
  float shade, highlight;
};

// Light and half vectors of one view, as floats, with the shading coefficients.
struct PhongSetup {
  float light[3], half[3];
  float ambient, diffuse, specular, shininess;
  // Below this |n·h| the highlight |n·h|^shininess is under 2⁻²⁴ — less than float rounding of
  // the lit colour it is added to — and is taken as 0 without evaluating the power.
  float highlight_floor;
  // The shininess when it is a whole number from 1 to 1024 (scenes' usual 24, 64, …), else 0:
  // the highlight is then a few multiplications (square and multiply), exact to float rounding,
  // instead of unitPower's logarithm and exponential, a third of a shear-warp sample's work.
  int whole_shininess;
  PhongSetup(const Shading& s, const glm::dvec3& light_dir, const glm::dvec3& half_dir)
      : ambient(static_cast<float>(s.ambient)),
        diffuse(static_cast<float>(s.diffuse)),
        specular(static_cast<float>(s.specular)),
        shininess(static_cast<float>(s.shininess)),
        highlight_floor(s.shininess > 0 ? static_cast<float>(std::pow(0x1p-24, 1.0 / s.shininess))
                                        : 0.f),
        whole_shininess(s.shininess >= 1 && s.shininess <= 1024 &&
                                s.shininess == std::floor(s.shininess)
                            ? static_cast<int>(s.shininess)
                            : 0) {
    setDirections(light_dir, half_dir);
  }
  // Another view direction (a perspective camera's next ray), the same shading.
  void setDirections(const glm::dvec3& light_dir, const glm::dvec3& half_dir) {
    for (int a = 0; a < 3; ++a) {
      light[a] = static_cast<float>(light_dir[a]);
      half[a] = static_cast<float>(half_dir[a]);
    }
  }
};

// x^n for a whole n ≥ 1, by squaring and multiplying (the loop's branches depend on n alone,
// which is the same for every sample of a render).
[[gnu::always_inline]] inline float wholePower(float x, int n) {
  float result = 1.f;
  for (float square = x; n > 0; n >>= 1, square *= square)
    if (n & 1) result *= square;
  return result;
}

// Normals are −∇f/|∇f|; where the gradient vanishes (inside a uniform region) there is no
// surface, and the sample is lit fully and without highlight.
[[gnu::always_inline]] inline PhongTerms phong(const PhongSetup& p, const float g[3]) {
  const float len = std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
  if (!(len > 1e-6f)) return {p.ambient + p.diffuse, 0.f};
  const float inv_len = 1.f / len;  // one division for both cosines
  const float nl = (g[0] * p.light[0] + g[1] * p.light[1] + g[2] * p.light[2]) * inv_len;
  const float nh = (g[0] * p.half[0] + g[1] * p.half[1] + g[2] * p.half[2]) * inv_len;
  const float cos_h = std::min(std::abs(nh), 1.f);
  float highlight = 0.f;
  if (cos_h > p.highlight_floor)
    highlight = p.specular * (p.whole_shininess > 0 ? wholePower(cos_h, p.whole_shininess)
                                                    : unitPower(cos_h, p.shininess));
  return {p.ambient + p.diffuse * std::abs(nl), highlight};
}

// phong for 4·N gradients at once, one lane each (gx[n], gy[n], gz[n]: their components): every
// lane takes phong's operations in phong's order, so it equals phong's result bit for bit (the
// test asserts it); lanes without a surface are selected afterwards instead of returned early.
// The N vectors go through each step together, so that the highlight's squarings, a chain of
// dependent multiplications, run N chains side by side.
template <int N>
[[gnu::always_inline]] inline void phongN(const PhongSetup& p, const Float4 (&gx)[N],
                                          const Float4 (&gy)[N], const Float4 (&gz)[N],
                                          Float4 (&shade)[N], Float4 (&highlight)[N]) {
  Float4 len[N], nl[N], cos_h[N];
  for (int n = 0; n < N; ++n) {
    len[n] = sqrt4(gx[n] * gx[n] + gy[n] * gy[n] + gz[n] * gz[n]);
    const Float4 inv_len = 1.f / len[n];
    nl[n] = (gx[n] * p.light[0] + gy[n] * p.light[1] + gz[n] * p.light[2]) * inv_len;
    const Float4 nh = (gx[n] * p.half[0] + gy[n] * p.half[1] + gz[n] * p.half[2]) * inv_len;
    const Float4 abs_nh = abs4(nh);
    cos_h[n] = 1.f < abs_nh ? splat4(1.f) : abs_nh;  // std::min(|nh|, 1)
  }
  Float4 power[N];
  if (p.whole_shininess > 0) {
    // wholePower4, N at a time.
    Float4 square[N];
    for (int n = 0; n < N; ++n) power[n] = splat4(1.f), square[n] = cos_h[n];
    for (int e = p.whole_shininess; e > 0; e >>= 1) {
      if (e & 1)
        for (int n = 0; n < N; ++n) power[n] *= square[n];
      for (int n = 0; n < N; ++n) square[n] *= square[n];
    }
  } else {
    for (int n = 0; n < N; ++n)
      for (int lane = 0; lane < 4; ++lane)
        power[n][lane] =
            cos_h[n][lane] > p.highlight_floor ? unitPower(cos_h[n][lane], p.shininess) : 0.f;
  }
  for (int n = 0; n < N; ++n) {
    const auto lit = len[n] > 1e-6f;
    const auto shiny = cos_h[n] > p.highlight_floor;
    shade[n] = lit ? p.ambient + p.diffuse * abs4(nl[n]) : splat4(p.ambient + p.diffuse);
    highlight[n] = (lit & shiny) ? p.specular * power[n] : splat4(0.f);
  }
}

[[gnu::always_inline]] inline void phong4(const PhongSetup& p, Float4 gx, Float4 gy, Float4 gz,
                                          Float4& shade, Float4& highlight) {
  const Float4 x[1] = {gx}, y[1] = {gy}, z[1] = {gz};
  Float4 s[1], h[1];
  phongN<1>(p, x, y, z, s, h);
  shade = s[0], highlight = h[0];
}

}  // namespace svr
