#include "renderers/simd/unit_power.h"

#include "renderers/classification/classified_sample.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <glm/geometric.hpp>

namespace svr {
namespace {

// Against libm over (0, 1] and the exponents scenes use (Phong shininess 1..1000): relative
// error within the 2e-6 · s the header states, plus float rounding of the result.
TEST(UnitPower, MatchesPowWithinTheStatedBound) {
  for (float s : {0.5f, 1.f, 5.f, 24.f, 100.f, 1000.f}) {
    double worst = 0.0;
    for (int i = 1; i <= 100000; ++i) {
      const float x = static_cast<float>(i) / 100000.f;
      const double exact = std::pow(static_cast<double>(x), static_cast<double>(s));
      if (exact < 1e-30) continue;  // underflows to 0 in float either way
      worst = std::max(worst, std::abs(unitPower(x, s) - exact) / exact);
    }
    EXPECT_LT(worst, 2e-6 * s + 1e-6) << "s = " << s;
  }
}

TEST(UnitPower, EdgesAreExact) {
  EXPECT_EQ(unitPower(0.f, 24.f), 0.f);
  EXPECT_EQ(unitPower(-0.f, 24.f), 0.f);
  EXPECT_EQ(unitPower(0.f, 0.f), 1.f);  // x⁰ = 1, as std::pow
  EXPECT_NEAR(unitPower(1.f, 24.f), 1.f, 1e-6f);
  EXPECT_NEAR(unitPower(0.5f, 2.f), 0.25f, 1e-6f);
  EXPECT_EQ(unitPower(1e-30f, 100.f), 0.f);  // far below float's range
}

// Square and multiply for whole shininess: within float rounding of one multiplication per bit
// (about n · 2⁻²⁴ relative), far inside unitPower's bound.
TEST(WholePower, MatchesPowForWholeExponents) {
  for (int n : {1, 2, 3, 7, 24, 64, 100, 1000}) {
    double worst = 0.0;
    for (int i = 1; i <= 100000; ++i) {
      const float x = static_cast<float>(i) / 100000.f;
      const double exact = std::pow(static_cast<double>(x), static_cast<double>(n));
      if (exact < 1e-30) continue;
      worst = std::max(worst, std::abs(wholePower(x, n) - exact) / exact);
    }
    EXPECT_LT(worst, 1.2e-7 * n + 1e-7) << "n = " << n;
  }
  EXPECT_EQ(wholePower(0.5f, 3), 0.125f);
  EXPECT_EQ(wholePower(1.f, 1000), 1.f);
}

// Phong takes the whole-number path for whole shininess only, and both paths agree.
TEST(WholePower, PhongUsesItForWholeShininessOnly) {
  const glm::dvec3 light(0, 0, 1), half(0, 0.6, 0.8);
  Shading shading;
  shading.ambient = 0.3, shading.diffuse = 0.7, shading.specular = 0.4;
  for (double s : {24.0, 24.5, 0.5, 2000.0}) {
    shading.shininess = s;
    const PhongSetup p(shading, light, half);
    EXPECT_EQ(p.whole_shininess, s == 24.0 ? 24 : 0) << s;
    const float g[3] = {0.f, -0.6f, -0.8f};  // normal along the half vector: cos_h = 1
    const float g2[3] = {0.f, -0.3f, -0.9f};
    EXPECT_NEAR(phong(p, g).highlight, 0.4f, 1e-6f) << s;
    const double cos_h = (0.6 * 0.3 + 0.8 * 0.9) / std::sqrt(0.09 + 0.81);
    EXPECT_NEAR(phong(p, g2).highlight, 0.4 * std::pow(cos_h, s), 1e-6 * s) << s;
  }
}

// phong4 and phongN take phong's operations in phong's order per lane: bit-equal results, for
// whole and fractional shininess, zero and tiny gradients (no surface), and gradients on both sides.
TEST(Phong4, EachLaneEqualsPhong) {
  const glm::dvec3 light = glm::normalize(glm::dvec3(0.3, -0.5, 0.8));
  const glm::dvec3 half = glm::normalize(light + glm::dvec3(0, 0, 1));
  Shading shading;
  shading.ambient = 0.3, shading.diffuse = 0.7, shading.specular = 0.4;
  std::uint32_t seed = 12345;
  const auto next = [&] {
    seed = seed * 1664525u + 1013904223u;
    return static_cast<float>(seed >> 8) / 16777216.f * 2.f - 1.f;
  };
  for (double s : {24.0, 7.5}) {
    shading.shininess = s;
    const PhongSetup p(shading, light, half);
    for (int round = 0; round < 1000; ++round) {
      float g[3][4];
      for (int lane = 0; lane < 4; ++lane)
        for (int a = 0; a < 3; ++a) g[a][lane] = next() * (lane == 3 ? 1e-7f : 1.f);
      if (round == 0) g[0][1] = g[1][1] = g[2][1] = 0.f;
      if (round == 1)  // along the half vector: the brightest highlight
        for (int a = 0; a < 3; ++a) g[a][2] = -static_cast<float>(half[a]);
      Float4 shade, highlight;
      phong4(p, load4(g[0]), load4(g[1]), load4(g[2]), shade, highlight);
      // Two vectors at once (the shear-warp kernel's phongN<2>): the second holds the lanes
      // reversed, and each lane still equals phong.
      const auto reversed = [](Float4 v) { return __builtin_shufflevector(v, v, 3, 2, 1, 0); };
      const Float4 x[2] = {load4(g[0]), reversed(load4(g[0]))};
      const Float4 y[2] = {load4(g[1]), reversed(load4(g[1]))};
      const Float4 z[2] = {load4(g[2]), reversed(load4(g[2]))};
      Float4 shades[2], highlights[2];
      phongN<2>(p, x, y, z, shades, highlights);
      for (int lane = 0; lane < 4; ++lane) {
        const float one[3] = {g[0][lane], g[1][lane], g[2][lane]};
        const PhongTerms expected = phong(p, one);
        ASSERT_EQ(shade[lane], expected.shade) << s << " " << round << " " << lane;
        ASSERT_EQ(highlight[lane], expected.highlight) << s << " " << round << " " << lane;
        ASSERT_EQ(shades[0][lane], expected.shade) << s << " " << round << " " << lane;
        ASSERT_EQ(highlights[0][lane], expected.highlight) << s << " " << round << " " << lane;
        ASSERT_EQ(shades[1][3 - lane], expected.shade) << s << " " << round << " " << lane;
        ASSERT_EQ(highlights[1][3 - lane], expected.highlight) << s << " " << round << " " << lane;
      }
    }
  }
}

// The pre-classified shear-warp records find each voxel's two entries four at a time: every
// lane gives entriesOfBin's entries and weight, bit for bit, below, across and above the table,
// on whole bins, just under them, and for one- and two-entry tables.
TEST(EntriesOfBins, EachLaneEqualsEntriesOfBin) {
  for (const int entries : {1, 2, 256, 4096}) {
    ClassifiedVolume cv;
    cv.entries = entries;
    std::vector<float> bins = {-1e30f, -3.f, -0.f, 0.f, 1e-7f, 0.5f, 1.f, 1.5f};
    const float last = static_cast<float>(entries - 1);
    for (const float b : {last - 1.f, std::nextafter(last - 1.f, 0.f), last - 0.25f,
                          std::nextafter(last, 0.f), last, std::nextafter(last, 1e30f),
                          last + 7.f, 1e30f})
      bins.push_back(b);
    std::uint32_t state = 12345u;
    for (int n = 0; n < 4000; ++n) {
      state = state * 1664525u + 1013904223u;
      bins.push_back((static_cast<float>(state >> 8) / 16777216.f) * (last + 4.f) - 2.f);
    }
    while (bins.size() % 4) bins.push_back(0.f);
    for (std::size_t n = 0; n < bins.size(); n += 4) {
      Int4 e0, e1;
      Float4 frac;
      entriesOfBins(cv, Float4{bins[n], bins[n + 1], bins[n + 2], bins[n + 3]}, e0, e1, frac);
      for (int m = 0; m < 4; ++m) {
        int s0, s1;
        float sfrac;
        entriesOfBin(cv, bins[n + m], s0, s1, sfrac);
        ASSERT_EQ(e0[m], s0) << entries << " entries, bin " << bins[n + m];
        ASSERT_EQ(e1[m], s1) << entries << " entries, bin " << bins[n + m];
        ASSERT_EQ(std::memcmp(&frac[m], &sfrac, sizeof(float)), 0)
            << entries << " entries, bin " << bins[n + m] << ": " << frac[m] << " vs " << sfrac;
        ASSERT_GE(s0, 0);
        ASSERT_LT(s1, entries);
      }
    }
  }
}

}  // namespace
}  // namespace svr
