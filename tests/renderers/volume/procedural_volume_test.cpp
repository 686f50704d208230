#include "renderers/volume/procedural_volume.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "base/error.h"

namespace svr {
namespace {

TEST(ProceduralVolume, MarschnerLobbAtKnownPoints) {
  // Origin: sin 0 = 0, ρr(0) = cos(2π·6) = 1, so (1 + 0.25·2)/2.5 = 0.6.
  EXPECT_NEAR(marschnerLobb({0, 0, 0}), 0.6, 1e-15);
  // z = 1: sin(π/2) = 1 leaves α(1 + ρr)/(2(1 + α)) = 0.5/2.5.
  EXPECT_NEAR(marschnerLobb({0, 0, 1}), 0.2, 1e-15);
  // z = −1: (2 + 0.5)/2.5.
  EXPECT_NEAR(marschnerLobb({0, 0, -1}), 1.0, 1e-15);
  // r = 1: cos(π/2) = 0, ρr = cos 0 = 1.
  EXPECT_NEAR(marschnerLobb({1, 0, 0}), 0.6, 1e-15);
  EXPECT_NEAR(marschnerLobb({0.6, 0.8, 0}), 0.6, 1e-14);
  // cos(πr/2) = 1/12 gives ρr = cos π = −1: (1 + 0)/2.5.
  const double r = 2 / std::numbers::pi * std::acos(1.0 / 12);
  EXPECT_NEAR(marschnerLobb({0, r, 0}), 0.4, 1e-14);
  // ∂ρ/∂z = −(π/2) cos(πz/2) / (2(1 + α)) = −π/5 at the origin; x and y vanish on the axis.
  const glm::dvec3 g = marschnerLobbGradient({0, 0, 0});
  EXPECT_EQ(g.x, 0);
  EXPECT_EQ(g.y, 0);
  EXPECT_NEAR(g.z, -std::numbers::pi / 5, 1e-15);
}

TEST(ProceduralVolume, MarschnerLobbGradientMatchesCentralDifferences) {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> coordinate(-1, 1);
  const double h = 1e-5;
  for (int i = 0; i < 200; ++i) {
    const glm::dvec3 p(coordinate(random), coordinate(random), coordinate(random));
    const glm::dvec3 g = marschnerLobbGradient(p);
    for (int a = 0; a < 3; ++a) {
      glm::dvec3 step(0);
      step[a] = h;
      const double numeric = (marschnerLobb(p + step) - marschnerLobb(p - step)) / (2 * h);
      EXPECT_NEAR(g[a], numeric, 1e-6)
          << "axis " << a << " at " << p.x << ", " << p.y << ", " << p.z;
    }
  }
  // Near the axis, where ∂r/∂x = x/r is ill-conditioned.
  const glm::dvec3 near_axis(1e-9, -2e-9, 0.3);
  const double numeric_x = (marschnerLobb(near_axis + glm::dvec3(h, 0, 0)) -
                            marschnerLobb(near_axis - glm::dvec3(h, 0, 0))) /
                           (2 * h);
  EXPECT_NEAR(marschnerLobbGradient(near_axis).x, numeric_x, 1e-6);
}

TEST(ProceduralVolume, MarschnerLobbVolumeSpansTheCube) {
  const Volume volume = marschnerLobbVolume(41);
  EXPECT_EQ(volume.dims(), (Dims{41, 41, 41}));
  EXPECT_EQ(volume.type(), ScalarType::kFloat32);
  EXPECT_DOUBLE_EQ(volume.spacing().x, 0.05);
  EXPECT_NEAR(volume.worldPosition(0, 0, 0).x, -1, 1e-12);
  EXPECT_NEAR(volume.worldPosition(40, 40, 40).z, 1, 1e-12);
  EXPECT_FLOAT_EQ(static_cast<float>(volume.value(20, 20, 20)), 0.6f);
  for (const auto& [x, y, z] : {std::array{3, 17, 29}, std::array{40, 0, 11}}) {
    const glm::dvec3 p = volume.worldPosition(x, y, z);
    EXPECT_FLOAT_EQ(static_cast<float>(volume.value(x, y, z)),
                    static_cast<float>(marschnerLobb(p)));
  }
  EXPECT_GE(volume.valueRange().first, 0);
  EXPECT_LE(volume.valueRange().second, 1);
  EXPECT_THROW(marschnerLobbVolume(1), Error);
}

TEST(ProceduralVolume, SlabAndItsChords) {
  const Volume slab = slabVolume({8, 8, 20}, glm::dvec3(0.5), 3.0);
  // z centres run −4.75 … 4.75 in steps of 0.5; |z| ≤ 1.5 holds −1.25 … 1.25: 6 slices.
  double ones = 0;
  for (int z = 0; z < 20; ++z) ones += slab.value(3, 4, z);
  EXPECT_EQ(ones, 6);
  EXPECT_EQ(slab.valueRange(), std::make_pair(0.0, 1.0));
  EXPECT_DOUBLE_EQ(slabChordLength(3, {0, 0, 1}), 3);
  EXPECT_DOUBLE_EQ(slabChordLength(3, {0, 0, -7}), 3);
  EXPECT_DOUBLE_EQ(slabChordLength(3, {1, 0, 1}), 3 * std::sqrt(2.0));
  EXPECT_DOUBLE_EQ(slabChordLength(2, {std::sqrt(3.0), 0, 1}), 4);  // 60° from the normal
  EXPECT_TRUE(std::isinf(slabChordLength(2, {1, 0, 0})));
}

TEST(ProceduralVolume, BoxAndItsChords) {
  const glm::dvec3 half(3, 2, 1);
  const Volume box = boxVolume({16, 16, 16}, glm::dvec3(0.5), half);
  // Centres −3.75 … 3.75: |x| ≤ 3 → 12, |y| ≤ 2 → 8, |z| ≤ 1 → 4 voxels.
  double sum = 0;
  for (std::size_t i = 0; i < box.voxelCount(); ++i) sum += box.value(i);
  EXPECT_EQ(sum, 12 * 8 * 4);
  EXPECT_DOUBLE_EQ(boxChordLength(half, {0, 0, 0}, {1, 0, 0}), 6);
  EXPECT_DOUBLE_EQ(boxChordLength(half, {-10, 1.5, 0.5}, {2, 0, 0}), 6);
  EXPECT_DOUBLE_EQ(boxChordLength(half, {0, 0, 5}, {0, 0, -1}), 2);
  EXPECT_DOUBLE_EQ(boxChordLength(half, {0, 2.5, 0}, {1, 0, 0}), 0);
  EXPECT_NEAR(boxChordLength(glm::dvec3(1), {0, 0, 0}, {1, 1, 1}), 2 * std::sqrt(3.0), 1e-12);
  EXPECT_NEAR(boxChordLength(glm::dvec3(1), {0, 0.5, 0}, {1, 1, 0}), std::sqrt(2.0) * 1.5, 1e-12);
}

TEST(ProceduralVolume, SphereChordsAndTheirSums) {
  EXPECT_DOUBLE_EQ(sphereChordLength(5, 0), 10);
  EXPECT_DOUBLE_EQ(sphereChordLength(5, 3), 8);
  EXPECT_DOUBLE_EQ(sphereChordLength(5, 5), 0);
  EXPECT_DOUBLE_EQ(sphereChordLength(5, 7), 0);
  // Voxel sums along grid lines approach the chords: each line has a whole number of voxels,
  // so the sum is within one voxel of 2√(R² − b²).
  const double radius = 20;
  const Volume ball = sphereVolume({64, 64, 64}, glm::dvec3(1), radius);
  for (const int y : {32, 40, 48, 50}) {
    const double b = std::hypot(ball.worldPosition(0, y, 32).y, ball.worldPosition(0, y, 32).z);
    double sum = 0;
    for (int x = 0; x < 64; ++x) sum += ball.value(x, y, 32);
    EXPECT_NEAR(sum, sphereChordLength(radius, b), 1.0) << "b = " << b;
  }
  double total = 0;
  for (std::size_t i = 0; i < ball.voxelCount(); ++i) total += ball.value(i);
  EXPECT_NEAR(total, 4.0 / 3 * std::numbers::pi * radius * radius * radius, 0.01 * total);
}

TEST(ProceduralVolume, NestedShells) {
  const std::vector<double> radii{5, 10, 15};
  EXPECT_EQ(nestedShellIndex(radii, 0), 1);
  EXPECT_EQ(nestedShellIndex(radii, 5), 1);
  EXPECT_EQ(nestedShellIndex(radii, 5.1), 2);
  EXPECT_EQ(nestedShellIndex(radii, 15), 3);
  EXPECT_EQ(nestedShellIndex(radii, 15.1), 0);
  EXPECT_DOUBLE_EQ(shellChordLength(5, 10, 0), 10);  // 5 on each side of the centre
  EXPECT_DOUBLE_EQ(shellChordLength(3, 5, 4), 6);    // inner missed: the whole outer chord
  // Through the centre: 1·10 + 2·10 + 3·10.
  EXPECT_DOUBLE_EQ(nestedShellsLineIntegral(radii, 0), 60);
  // b = 12 meets only the outer shell: 3 · 2√(225 − 144) = 54.
  EXPECT_DOUBLE_EQ(nestedShellsLineIntegral(radii, 12), 54);
  const Volume shells = nestedShellsVolume({40, 40, 40}, glm::dvec3(1), radii);
  EXPECT_EQ(shells.valueRange(), std::make_pair(0.0, 3.0));
  EXPECT_EQ(shells.value(19, 19, 19), 1);  // (−0.5, −0.5, −0.5)
  EXPECT_EQ(shells.value(27, 19, 19), 2);  // x = 7.5
  EXPECT_EQ(shells.value(32, 19, 19), 3);  // x = 12.5
  EXPECT_EQ(shells.value(39, 19, 19), 0);  // x = 19.5
  double line = 0;
  for (int x = 0; x < 40; ++x) line += shells.value(x, 19, 19);
  EXPECT_NEAR(line, nestedShellsLineIntegral(radii, std::sqrt(0.5)), 3.0);
  EXPECT_THROW(nestedShellsVolume({4, 4, 4}, glm::dvec3(1), {5, 5}), Error);
  EXPECT_THROW(nestedShellsVolume({4, 4, 4}, glm::dvec3(1), {}), Error);
}

TEST(ProceduralVolume, PhantomLabels) {
  const Volume phantom = phantomVolume();
  EXPECT_EQ(phantom.dims(), (Dims{64, 64, 64}));
  EXPECT_EQ(phantom.valueRange(), std::make_pair(0.0, 4.0));
  std::array<double, 5> counts{};
  for (int z = 0; z < 64; ++z)
    for (int y = 0; y < 64; ++y)
      for (int x = 0; x < 64; ++x) {
        const double label = phantom.value(x, y, z);
        ASSERT_EQ(label, phantomLabel(phantom.worldPosition(x, y, z)));
        ++counts[static_cast<std::size_t>(label)];
      }
  const auto ball = [](double r) { return 4.0 / 3 * std::numbers::pi * r * r * r; };
  EXPECT_EQ(counts[2], 4032);  // 12 · 12 · 28 voxel centres in the box
  EXPECT_NEAR(counts[3], ball(8), 0.03 * ball(8));
  EXPECT_NEAR(counts[4], ball(4), 0.08 * ball(4));
  EXPECT_NEAR(counts[1], ball(28) - 4032 - ball(8) - ball(4), 0.01 * ball(28));
  EXPECT_EQ(counts[0] + counts[1] + counts[2] + counts[3] + counts[4], 64.0 * 64 * 64);
  EXPECT_EQ(phantomLabel({0, 0, 0}), 1);
  EXPECT_EQ(phantomLabel({-12, 0, 0}), 2);
  EXPECT_EQ(phantomLabel({12, 0, 0}), 3);
  EXPECT_EQ(phantomLabel({0, 12, 10}), 4);
  EXPECT_EQ(phantomLabel({30, 30, 30}), 0);
}

TEST(ProceduralVolume, SamplesAtVolumeWorldPositions) {
  // The procedural sampler and Volume::worldPosition agree on where voxel centres are.
  const Volume volume = slabVolume({5, 6, 7}, glm::dvec3(0.3, 0.7, 1.1), 2.0);
  for (int z = 0; z < 7; ++z) {
    const double expected = std::abs(volume.worldPosition(2, 3, z).z) <= 1.0 ? 1.0 : 0.0;
    EXPECT_EQ(volume.value(2, 3, z), expected) << z;
  }
  EXPECT_EQ(volume.worldPosition(2, 2.5, 3), glm::dvec3(0));
}

}  // namespace
}  // namespace svr
