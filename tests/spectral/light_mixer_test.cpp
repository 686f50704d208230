#include "spectral/light_mixer.h"

#include <gtest/gtest.h>

#include <cmath>

#include "base/error.h"

namespace svr {
namespace {

TEST(LightMixer, HandleOnANodeGivesThatLightAlone) {
  const auto mixer = LightMixer::regularPolygon(5);
  for (int i = 0; i < 5; ++i) {
    const auto w = mixer.weights(mixer.nodes[i].x, mixer.nodes[i].y);
    for (int j = 0; j < 5; ++j) EXPECT_EQ(w[j], i == j ? 1.0 : 0.0);
  }
}

TEST(LightMixer, CentreOfARegularPolygonWeighsAllEqually) {
  for (int n : {3, 4, 6}) {
    const auto w = LightMixer::regularPolygon(n).weights(0, 0);
    for (double v : w) EXPECT_NEAR(v, 1.0 / n, 1e-12);
  }
}

TEST(LightMixer, MidpointOfAnEdgeFollowsInverseDistance) {
  // Square: nodes at 90°, 180°, 270°, 0°. Midpoint of the edge between nodes 0 and 1 is at
  // distance s/2 from both (s = √2), and √(1/2 + 2)·… from nodes 2 and 3: d² = (s/2)² + s².
  auto mixer = LightMixer::regularPolygon(4, 2.0);
  const double mx = (mixer.nodes[0].x + mixer.nodes[1].x) / 2;
  const double my = (mixer.nodes[0].y + mixer.nodes[1].y) / 2;
  const auto w = mixer.weights(mx, my);
  const double near_d2 = 0.5, far_d2 = 0.5 + 2.0;
  const double sum = 2 / near_d2 + 2 / far_d2;
  EXPECT_NEAR(w[0], (1 / near_d2) / sum, 1e-12);
  EXPECT_NEAR(w[1], (1 / near_d2) / sum, 1e-12);
  EXPECT_NEAR(w[2], (1 / far_d2) / sum, 1e-12);
  EXPECT_NEAR(w[3], (1 / far_d2) / sum, 1e-12);
}

TEST(LightMixer, LightsSwitchedOffGetNoWeightAndMovedNodesCount) {
  auto mixer = LightMixer::regularPolygon(3);
  mixer.nodes[1].on = false;
  auto w = mixer.weights(0, 0);
  EXPECT_EQ(w[1], 0.0);
  EXPECT_NEAR(w[0], 0.5, 1e-12);
  EXPECT_NEAR(w[2], 0.5, 1e-12);
  // On a switched-off node the handle does not select it.
  w = mixer.weights(mixer.nodes[1].x, mixer.nodes[1].y);
  EXPECT_EQ(w[1], 0.0);
  mixer.nodes[0] = {0.0, 0.0, true};  // moved onto the handle
  w = mixer.weights(0, 0);
  EXPECT_EQ(w[0], 1.0);
}

TEST(LightMixer, HigherPowerFavoursTheNearestLight) {
  auto mixer = LightMixer::regularPolygon(3, 1.0);
  const double w1 = mixer.weights(0, 0.5)[0];
  mixer.power = 4.0;
  EXPECT_GT(mixer.weights(0, 0.5)[0], w1);
}

TEST(LightMixer, RejectsImpossibleParameters) {
  EXPECT_THROW(LightMixer::regularPolygon(0), Error);
  auto mixer = LightMixer::regularPolygon(3);
  EXPECT_THROW(mixer.weights(NAN, 0), Error);
  mixer.power = -1;
  EXPECT_THROW(mixer.weights(0, 0), Error);
}

TEST(LightMix, WeightedSumAndIntensityNormalisation) {
  const std::vector<Eigen::VectorXd> lights{Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 2, 0)};
  const std::vector<double> w{0.25, 0.75};
  EXPECT_TRUE(mixLights(lights, w).isApprox(Eigen::Vector3d(0.25, 1.5, 0)));
  const auto n = normaliseIntensity(w, std::vector<double>{2.0, 4.0});  // Y = 0.5 + 3 = 3.5
  EXPECT_NEAR(n[0] * 2.0 + n[1] * 4.0, 1.0, 1e-12);
  EXPECT_NEAR(n[0] / n[1], 0.25 / 0.75, 1e-12);
  EXPECT_THROW(mixLights(lights, std::vector<double>{1.0}), Error);
}

}  // namespace
}  // namespace svr
