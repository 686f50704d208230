#include "spectral/light_independent_image.h"

#include <gtest/gtest.h>

#include <cmath>

#include "base/error.h"

namespace svr {
namespace {

TEST(Half, KnownEncodingsAndRoundTrip) {
  EXPECT_EQ(floatToHalf(0.0f), 0x0000);
  EXPECT_EQ(floatToHalf(-0.0f), 0x8000);
  EXPECT_EQ(floatToHalf(1.0f), 0x3c00);
  EXPECT_EQ(floatToHalf(-2.0f), 0xc000);
  EXPECT_EQ(floatToHalf(65504.0f), 0x7bff);         // largest finite half
  EXPECT_EQ(floatToHalf(1e6f), 0x7c00);             // overflow → Inf
  EXPECT_EQ(floatToHalf(5.9604645e-8f), 0x0001);    // smallest subnormal
  EXPECT_EQ(floatToHalf(1.0f + 1.0f / 2048), 0x3c00);  // tie rounds to even
  EXPECT_EQ(floatToHalf(1.0f + 3.0f / 2048), 0x3c02);  // tie rounds to even (up)
  EXPECT_TRUE(std::isnan(halfToFloat(floatToHalf(NAN))));
  EXPECT_TRUE(std::isinf(halfToFloat(floatToHalf(INFINITY))));
  for (int bits = 0; bits < 0x7c00; ++bits)  // every finite positive half survives the trip
    ASSERT_EQ(floatToHalf(halfToFloat(static_cast<std::uint16_t>(bits))), bits) << bits;
}

TEST(LightIndependentImage, PlanarLayoutAndStorageConversion) {
  LightIndependentImage img(3, 2, 4, 1);
  EXPECT_EQ(img.planes(), 5);
  EXPECT_EQ(img.bytes(), 3u * 2 * 5 * 4);
  img.setSample(2, 1, 1, 0.25f);
  EXPECT_EQ(img.planeFloat(2)[1 * 3 + 1], 0.25f);
  EXPECT_EQ(img.scattered(2, 1, 1), 0.25f);
  img.setSample(4, 2, 0, 0.5f);
  EXPECT_EQ(img.transmittance(0, 2, 0), 0.5f);
  const auto half = img.withStorage(SampleStorage::kHalf);
  EXPECT_EQ(half.bytes(), 3u * 2 * 5 * 2);
  EXPECT_EQ(half.scattered(2, 1, 1), 0.25f);
  EXPECT_EQ(half.planeHalf(2)[4], floatToHalf(0.25f));
}

TEST(LightIndependentImage, RejectsImpossibleSizes) {
  EXPECT_THROW(LightIndependentImage(0, 10, 3, 0), Error);
  EXPECT_THROW(LightIndependentImage(10, -1, 3, 0), Error);
  EXPECT_THROW(LightIndependentImage(1 << 20, 10, 3, 0), Error);
  EXPECT_THROW(LightIndependentImage(10, 10, 0, 0), Error);
  EXPECT_THROW(LightIndependentImage(10, 10, 6, 2), Error);  // T is 0, 1 or k channels
  // An image whose renderer writes every sample: the same checks, and float planes of the size.
  EXPECT_THROW(LightIndependentImage::unset(0, 10, 3, 1), Error);
  EXPECT_THROW(LightIndependentImage::unset(10, 10, 6, 2), Error);
  LightIndependentImage unset = LightIndependentImage::unset(5, 3, 6, 1);
  EXPECT_EQ(unset.storage(), SampleStorage::kFloat);
  EXPECT_EQ(unset.planes(), 7);
  EXPECT_EQ(unset.planeFloat(6).size(), 15u);
  EXPECT_EQ(unset.planeFloat(6).data(), unset.planeFloat(0).data() + 6 * 15);
  unset.setSample(6, 4, 2, 0.5f);
  EXPECT_EQ(unset.transmittance(0, 4, 2), 0.5f);
}

}  // namespace
}  // namespace svr
