#pragma once
// Per-band accumulation state shared by both compositing modes: the band's slice of the output
// image (S and T, planar), and early termination bookkeeping — which pixels are done (max over
// channels of T below the threshold) and how many live pixels each 8-pixel column block still
// has, so a splat over finished pixels is skipped without touching them.

#include <algorithm>
#include <cstdint>
#include <limits>
#include <vector>

#include "spectral/light_independent_image.h"

namespace svr::splat {

class BandState {
 public:
  static constexpr int kBlock = 8;
  BandState(LightIndependentImage& image, int y0, int y1, float termination)
      : width_(image.width()),
        y0_(y0),
        y1_(y1),
        k_(image.channels()),
        kt_(image.transmittanceChannels()),
        termination_(termination),
        pixels_(image.pixels()),
        out_(image.planeFloat(0).data()),
        done_(static_cast<std::size_t>(y1 - y0) * width_, 0),
        live_per_block_((width_ + kBlock - 1) / kBlock, 0) {
    for (int y = y0; y < y1; ++y)
      for (int x = 0; x < width_; ++x) {
        const std::size_t p = pixel(x, y);
        for (int c = 0; c < k_; ++c) out_[c * pixels_ + p] = 0.f;
        for (int c = 0; c < kt_; ++c) out_[(k_ + c) * pixels_ + p] = 1.f;
      }
    for (int x = 0; x < width_; ++x) live_per_block_[x / kBlock] += y1 - y0;
    live_ = static_cast<std::size_t>(y1 - y0) * width_;
  }
  int width() const { return width_; }
  int y0() const { return y0_; }
  int y1() const { return y1_; }
  std::size_t pixel(int x, int y) const { return static_cast<std::size_t>(y) * width_ + x; }
  std::size_t planePixels() const { return pixels_; }  // the image's: planes lie this far apart
  float* scattered(int c) { return out_ + c * pixels_; }
  float* transmittance(int c) { return out_ + (k_ + c) * pixels_; }
  bool done(int x, int y) const { return done_[static_cast<std::size_t>(y - y0_) * width_ + x]; }
  const std::uint8_t* doneRow(int y) const {  // done(x, y) is doneRow(y)[x] != 0
    return done_.data() + static_cast<std::size_t>(y - y0_) * width_;
  }
  bool allDone() const { return live_ == 0; }
  // True when every pixel in columns [x0, x1] of this band is finished.
  bool columnsDone(int x0, int x1) const {
    for (int b = x0 / kBlock; b <= x1 / kBlock; ++b)
      if (live_per_block_[b] > 0) return false;
    return true;
  }
  // Call after a pixel's T changed: marks it finished once max T falls below the threshold.
  void update(int x, int y) {
    if (termination_ <= 0.f || done(x, y)) return;
    const std::size_t p = pixel(x, y);
    float tmax = 0.f;
    for (int c = 0; c < kt_; ++c) tmax = std::max(tmax, out_[(k_ + c) * pixels_ + p]);
    if (tmax < termination_) finish(x, y);
  }
  // T's threshold; −∞ without early termination, so that no T (factor models' may dip below 0)
  // falls below it.
  float termination() const {
    return termination_ > 0.f ? termination_ : -std::numeric_limits<float>::infinity();
  }
  // Marks a live pixel finished (update() for a caller that has compared T itself).
  void finish(int x, int y) {
    done_[static_cast<std::size_t>(y - y0_) * width_ + x] = 1;
    --live_per_block_[x / kBlock];
    --live_;
  }

 private:
  int width_, y0_, y1_, k_, kt_;
  float termination_;
  std::size_t pixels_;
  float* out_;
  std::vector<std::uint8_t> done_;
  std::vector<int> live_per_block_;
  std::size_t live_ = 0;
};

}  // namespace svr::splat
