// Renderer::render's last check: a backend's image with a NaN or an infinity anywhere is an
// error naming the channel and pixel, never an image; every finite value passes, the largest
// and the subnormal ones included. The backend here is a stand-in that returns a chosen image,
// since no real backend makes a non-finite value on purpose.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "renderers/render/renderer.h"
#include "base/error.h"

namespace svr {
namespace {

// Returns a 7×5 image of k = 3 and scalar T, all 0.5 but for one value.
class OneValueBackend final : public Renderer {
 public:
  OneValueBackend(int plane, int x, int y, float value)
      : plane_(plane), x_(x), y_(y), value_(value) {}
  const BackendInfo& info() const override {
    static const BackendInfo info{"one-value", "returns a chosen image", {}, {}};
    return info;
  }

 protected:
  LightIndependentImage renderImpl(const RenderRequest& request, const BackendOptions&,
                                   ProgressCounter&) const override {
    LightIndependentImage image(request.width, request.height, 3, 1);
    for (int p = 0; p < image.planes(); ++p)
      for (float& v : image.planeFloat(p)) v = 0.5f;
    image.planeFloat(plane_)[static_cast<std::size_t>(y_) * request.width + x_] = value_;
    return image;
  }

 private:
  int plane_, x_, y_;
  float value_;
};

LightIndependentImage renderOne(int plane, int x, int y, float value) {
  ClassifiedVolume cv;
  cv.k = 3;
  cv.t_channels = 1;
  const RenderRequest request{.volume = cv,
                              .camera = Camera::orbit(0.0, 0.0, 10.0, 0.0, 1.0),
                              .width = 7,
                              .height = 5,
                              .shading = {},
                              .light_direction = std::nullopt,
                              .note = nullptr};
  return OneValueBackend(plane, x, y, value).render(request);
}

TEST(NonFiniteReport, NamesTheChannelAndPixel) {
  const float bad[] = {std::numeric_limits<float>::quiet_NaN(),
                       std::numeric_limits<float>::infinity(),
                       -std::numeric_limits<float>::infinity()};
  for (float value : bad) {
    try {
      renderOne(1, 6, 4, value);  // S channel 1, the last pixel
      FAIL() << value << " was not reported";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("non-finite"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("S channel 1 at pixel (6, 4)"), std::string::npos)
          << e.what();
    }
    try {
      renderOne(3, 0, 0, value);  // T, the first pixel
      FAIL() << value << " was not reported";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("T channel 0 at pixel (0, 0)"), std::string::npos)
          << e.what();
    }
  }
}

TEST(NonFiniteReport, EveryFiniteValuePasses) {
  const float good[] = {std::numeric_limits<float>::max(), -std::numeric_limits<float>::max(),
                        std::numeric_limits<float>::denorm_min(), -0.f, 0.f, 1e-30f};
  for (float value : good) {
    const LightIndependentImage image = renderOne(2, 3, 2, value);
    EXPECT_EQ(image.planeFloat(2)[2 * 7 + 3], value);
  }
}

}  // namespace
}  // namespace svr
