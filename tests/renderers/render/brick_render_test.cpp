// Bricks rendered one after another in one process and composited in visibility order equal the
// whole volume's render (design.md §5b): the distributed render's correctness without MPI. The MPI
// executable runs the same steps across ranks (tests/mpi_render.py checks it end to end).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "renderers/render/front_transmittance.h"
#include "renderers/kernels/gradient_volume.h"
#include "renderers/render/image_compositing.h"
#include "renderers/model/scene_model.h"
#include "renderers/render/brick_order.h"
#include "renderers/volume/volume_brick.h"
#include "renderers/render/work_estimate.h"
#include "renderers/registry.h"
#include "base/error.h"
#include "tests/renderers/test_scenes.h"

namespace svr {
namespace {

TEST(Bricks, KdSplitTilesTheGrid) {
  const Dims dims{50, 31, 7};
  for (int n = 1; n <= 9; ++n) {
    const auto bricks = kdSplit(dims, n);
    ASSERT_EQ(bricks.size(), static_cast<std::size_t>(n));
    std::vector<int> cover(50 * 31 * 7, 0);
    std::size_t smallest = SIZE_MAX, largest = 0;
    for (const KdBrick& b : bricks) {
      smallest = std::min(smallest, b.own.voxels());
      largest = std::max(largest, b.own.voxels());
      for (int z = b.own.lo[2]; z < b.own.hi[2]; ++z)
        for (int y = b.own.lo[1]; y < b.own.hi[1]; ++y)
          for (int x = b.own.lo[0]; x < b.own.hi[0]; ++x) ++cover[(z * 31 + y) * 50 + x];
    }
    for (int c : cover) ASSERT_EQ(c, 1) << n;
    // Voxels are shared in proportion: no brick holds more than a plane's rounding over 1/n.
    EXPECT_LE(static_cast<double>(largest), 1.0 / n * 50 * 31 * 7 + 31 * 7 * 2 + 50 * 7) << n;
  }
  EXPECT_THROW(kdSplit(dims, 0), Error);
  EXPECT_THROW(kdSplit({2, 1, 1}, 3), Error);
}

TEST(Bricks, GhostLayersStayInsideTheGrid) {
  const auto bricks = kdSplit({64, 64, 64}, 4);
  for (const KdBrick& b : bricks) {
    const VolumeBrick brick = brickOf({64, 64, 64}, b.own);
    for (int a = 0; a < 3; ++a) {
      EXPECT_EQ(brick.stored.lo[a], std::max(b.own.lo[a] - kGhostLayers, 0));
      EXPECT_EQ(brick.stored.hi[a], std::min(b.own.hi[a] + kGhostLayers, 64));
    }
  }
}

TEST(Bricks, VisibilityOrderPutsTheEyesSideFirst) {
  const auto bricks = kdSplit({64, 8, 8}, 2);  // split across x at 32
  ASSERT_EQ(bricks[0].own.hi[0], 32);
  const glm::dvec3 spacing(1.0);
  // Orthographic from −x (rays travel +x): the low brick first; from +x the high one.
  Camera from_low = Camera::orbit(180.0, 0.0, 200.0, 0.0, 80.0);
  EXPECT_EQ(visibilityOrder(bricks, from_low, {64, 8, 8}, spacing), (std::vector<int>{0, 1}));
  Camera from_high = Camera::orbit(0.0, 0.0, 200.0, 0.0, 80.0);
  EXPECT_EQ(visibilityOrder(bricks, from_high, {64, 8, 8}, spacing), (std::vector<int>{1, 0}));
  // Perspective with the eye inside the high brick, looking towards −x: high first.
  Camera inside = from_high;
  inside.eye = {20.0, 0.0, 0.0};
  inside.fov_degrees = 60.0;
  EXPECT_EQ(visibilityOrder(bricks, inside, {64, 8, 8}, spacing), (std::vector<int>{1, 0}));
}

TEST(Bricks, OverIsAssociative) {
  // Three random images: (a over b) over c == a over (b over c), and T multiplies.
  const int k = 3, kt = 3;
  std::vector<LightIndependentImage> im;
  unsigned seed = 7;
  const auto rnd = [&] { return (seed = seed * 1103515245u + 12345u) % 1000 / 1000.f; };
  for (int i = 0; i < 3; ++i) {
    im.emplace_back(4, 4, k, kt);
    for (int p = 0; p < k + kt; ++p)
      for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x) im[i].setSample(p, x, y, rnd());
  }
  LightIndependentImage left = im[1];
  compositeOver(im[0], left);  // a over b
  LightIndependentImage c1 = im[2];
  compositeOver(left, c1);
  LightIndependentImage bc = im[2];
  compositeOver(im[1], bc);
  compositeOver(im[0], bc);
  for (int p = 0; p < k + kt; ++p)
    for (int y = 0; y < 4; ++y)
      for (int x = 0; x < 4; ++x) EXPECT_NEAR(c1.sample(p, x, y), bc.sample(p, x, y), 1e-6);
  // Pixel 0 by hand: S = Sa + Ta Sb, T = Ta Tb.
  LightIndependentImage ab = im[1];
  compositeOver(im[0], ab);
  EXPECT_FLOAT_EQ(ab.scattered(1, 0, 0), im[0].scattered(1, 0, 0) +
                                             im[0].transmittance(1, 0, 0) * im[1].scattered(1, 0, 0));
  EXPECT_FLOAT_EQ(ab.transmittance(2, 0, 0),
                  im[0].transmittance(2, 0, 0) * im[1].transmittance(2, 0, 0));
  // Interleaved and planar agree.
  std::vector<float> f = interleavedSamples(im[0]), b = interleavedSamples(im[1]);
  compositeOverInterleaved(f.data(), b.data(), 16, k, kt);
  const LightIndependentImage back = fromInterleaved(b, 4, 4, k, kt);
  for (int p = 0; p < k + kt; ++p) EXPECT_EQ(back.sample(p, 3, 2), ab.sample(p, 3, 2));
}

// The bricks in front, in one process: each brick renders its footprint's blocks with the product
// of the T of the bricks rendered before it (in visibility order), as svr-mpi's ranks pass it.
class SequentialFront final : public FrontTransmittance {
 public:
  SequentialFront(const LightIndependentImage& in_front, std::vector<int> order)
      : in_front_(in_front), order_(std::move(order)) {}
  int blocks() const override { return static_cast<int>(order_.size()); }
  int next() override { return given_ < order_.size() ? order_[given_++] : -1; }
  const float* front(int block) override {
    constexpr int n = kBlock;
    buffer_.resize(static_cast<std::size_t>(in_front_.transmittanceChannels()) * n * n);
    copyBlockTransmittance(in_front_, block, buffer_.data());
    return buffer_.data();
  }
  void finished(int block, const LightIndependentImage&) override { finished_.push_back(block); }
  void done() override { done_ = true; }
  void abandon() override {}
  bool complete() const { return done_ && finished_ == order_; }

 private:
  const LightIndependentImage& in_front_;
  std::vector<int> order_, finished_;
  std::size_t given_ = 0;
  std::vector<float> buffer_;
  bool done_ = false;
};

// The scene rendered whole, and as `count` bricks composited in visibility order.
struct BrickedRender {
  LightIndependentImage whole, bricked;
};

// front: each brick stops its rays where the whole render does (SequentialFront).
BrickedRender renderBothWays(const Scene& scene, const ColourModel& model,
                             const std::string& backend, int count, double termination,
                             bool front = false) {
  const auto renderer = makeRenderer(backend);
  BrickedRender out;
  {
    const ClassifiedVolume cv = classifyScene(scene, model);
    RenderRequest req = sceneRequest(scene, cv);
    req.termination = termination;
    out.whole = renderer->render(req);
  }
  const Dims whole = scene.volume.dims();
  const auto bricks = kdSplit(whole, count);
  // What the ranks agree on: the value range, then (once classified) the shading field's.
  std::vector<Scene> parts;
  std::vector<ClassifiedVolume> classified;
  std::optional<std::pair<double, double>> range;
  for (const KdBrick& b : bricks) {
    parts.push_back(scene);
    parts.back().volume = cropToBrick(scene.volume, brickOf(whole, b.own));
    const auto local = parts.back().volume.localRange();
    range = range ? mergeRanges(*range, local) : local;
  }
  std::optional<FieldRange> field;
  for (Scene& part : parts) {
    VolumeBrick brick = *part.volume.brick();
    brick.whole_range = range;
    part.volume.setBrick(brick);
    classified.push_back(classifyScene(part, model));
    const FieldRange f = fieldRangeOver(classified.back(), ownInStored(brick));
    field = field ? mergeRanges(*field, f) : f;
  }
  const auto order = visibilityOrder(bricks, scene.camera, whole, scene.volume.spacing());
  std::vector<LightIndependentImage> images(parts.size());
  // The product of the T of the bricks rendered so far: what lies in front of the next one.
  LightIndependentImage in_front(scene.width, scene.height, classified[0].k,
                                 classified[0].t_channels);
  for (int c = 0; c < in_front.transmittanceChannels(); ++c)
    for (float& t : in_front.planeFloat(in_front.channels() + c)) t = 1.f;
  for (const int i : order) {
    classified[i].brick->whole_field = field;
    RenderRequest req = sceneRequest(parts[i], classified[i]);
    req.termination = termination;
    std::optional<SequentialFront> exchange;
    if (front) {
      exchange.emplace(in_front, footprintBlocks(bricks[i].own, whole, scene.volume.spacing(),
                                                 scene.camera, scene.width, scene.height));
      req.front = &*exchange;
    }
    images[i] = renderer->render(req);
    if (exchange) {
      EXPECT_TRUE(exchange->complete()) << "every block finished, then done";
    }
    const int k = in_front.channels();
    for (int c = 0; c < in_front.transmittanceChannels(); ++c) {
      const auto own = images[i].planeFloat(k + c);
      const auto acc = in_front.planeFloat(k + c);
      for (std::size_t p = 0; p < acc.size(); ++p) acc[p] *= own[p];
    }
  }
  out.bricked = images[order.back()];
  for (int i = static_cast<int>(order.size()) - 2; i >= 0; --i)
    compositeOver(images[order[i]], out.bricked);
  RenderRequest req = sceneRequest(parts[0], classified[0]);
  req.termination = termination;
  out.bricked = renderer->finishBricks(std::move(out.bricked), req);
  return out;
}

// Largest |a − b| / (1 + |a|) over every sample, and the largest sample.
std::pair<double, double> difference(const LightIndependentImage& a, const LightIndependentImage& b) {
  double worst = 0, largest = 0;
  for (int p = 0; p < a.planes(); ++p)
    for (int y = 0; y < a.height(); ++y)
      for (int x = 0; x < a.width(); ++x) {
        const double u = a.sample(p, x, y), v = b.sample(p, x, y);
        worst = std::max(worst, std::abs(u - v) / (1.0 + std::abs(u)));
        largest = std::max(largest, std::abs(u));
      }
  return {worst, largest};
}

Scene engineScene() {
  Scene s = loadScene(test::rendererDataDir() + "/scenes/engine.json", test::rendererLibrary());
  s.width = s.height = 64;
  return s;
}

class BrickedEqualsWhole
    : public ::testing::TestWithParam<std::tuple<std::string, std::string, std::string>> {};

TEST_P(BrickedEqualsWhole, ForOneToFourBricks) {
  const auto& [scene_name, backend, model_name] = GetParam();
  const Scene scene = scene_name == "engine" ? engineScene() : test::phantomScene();
  const SceneModel model = makeSceneModel(model_name, scene, test::rendererObserver());
  for (int n = 1; n <= 4; ++n) {
    // Without early termination every sample is taken by exactly one brick: equal to the
    // rounding of the compositing order.
    const BrickedRender r = renderBothWays(scene, *model.model, backend, n, 0.0);
    ASSERT_EQ(r.bricked.planes(), r.whole.planes());
    const auto [worst, largest] = difference(r.whole, r.bricked);
    EXPECT_GT(largest, 0.05) << "the view shows something";
    EXPECT_LT(worst, 2e-6) << n << " bricks";
  }
}

INSTANTIATE_TEST_SUITE_P(
    Scenes, BrickedEqualsWhole,
    ::testing::Values(std::make_tuple("engine", "raycast", "rgb"),
                      std::make_tuple("engine", "raycast", "factor:6"),
                      std::make_tuple("phantom", "raycast", "factor:6"),  // spectral T
                      std::make_tuple("engine", "shearwarp", "rgb"),
                      std::make_tuple("engine", "shearwarp", "factor:6"),
                      std::make_tuple("phantom", "shearwarp", "factor:6")),
    [](const auto& info) {
      std::string name = std::get<0>(info.param) + "_" + std::get<1>(info.param) + "_" +
                         std::get<2>(info.param);
      // "Factor6": the sanitize preset leaves out tests that train factor models by that name.
      const auto at = name.find("factor:");
      if (at != std::string::npos) name.replace(at, 7, "Factor");
      return name;
    });

TEST(Bricks, EarlyTerminationDiffersByAtMostItsThreshold) {
  // A brick cannot see the transmittance in front of it, so it goes on past where the whole
  // render stopped: what it adds lies behind T < ε, at most ε times the radiance behind.
  const Scene scene = engineScene();
  const SceneModel model = makeSceneModel("rgb", scene, test::rendererObserver());
  const BrickedRender r = renderBothWays(scene, *model.model, "raycast", 4, 0.01);
  const auto [worst, largest] = difference(r.whole, r.bricked);
  EXPECT_LT(worst, 0.01 * std::max(largest, 1.0));
}

// With the transmittance in front passed block by block, every brick stops its rays where the
// whole render stops them: equal to the rounding of the compositing order, early termination on.
// The footprints decide which blocks a brick renders, so this also checks that they cover every
// pixel whose ray takes an owned sample.
class FrontEqualsWhole : public ::testing::TestWithParam<std::tuple<std::string, std::string>> {};

TEST_P(FrontEqualsWhole, ForOneToFourBricks) {
  const auto& [scene_name, model_name] = GetParam();
  Scene scene = scene_name == "phantom" ? test::phantomScene() : engineScene();
  scene.width = 150, scene.height = 130;  // blocks cut by the image's edges
  if (scene_name == "engine_perspective") scene.camera.fov_degrees = 40.0;
  const SceneModel model = makeSceneModel(model_name, scene, test::rendererObserver());
  for (int n = 1; n <= 4; ++n) {
    const BrickedRender with = renderBothWays(scene, *model.model, "raycast", n, 0.05, true);
    const auto [worst, largest] = difference(with.whole, with.bricked);
    EXPECT_GT(largest, 0.05) << "the view shows something";
    // A ray whose T_front·T and the whole render's T fall on either side of ε by rounding may
    // take one sample more or less: none did here.
    EXPECT_LT(worst, 2e-6) << n << " bricks";
  }
}

INSTANTIATE_TEST_SUITE_P(Scenes, FrontEqualsWhole,
                         ::testing::Values(std::make_tuple("engine", "rgb"),
                                           std::make_tuple("engine_perspective", "rgb"),
                                           std::make_tuple("phantom", "factor:6")),
                         [](const auto& info) {
                           const std::string model = std::get<1>(info.param) == "rgb" ? "rgb" : "Factor6";
                           return std::get<0>(info.param) + "_" + model;
                         });

// Whether the ray through pixel (x, y) crosses the box's voxels (a slab test in world space).
bool rayCrosses(const RayGenerator& rays, int x, int y, const VoxelBox& box, const Dims& whole,
                const glm::dvec3& spacing) {
  const Ray ray = rays.ray(x + 0.5, y + 0.5);
  double t0 = 0, t1 = 1e300;
  for (int a = 0; a < 3; ++a) {
    const double lo = (box.lo[a] - 0.5 * (whole[a] - 1)) * spacing[a];
    const double hi = (box.hi[a] - 1 - 0.5 * (whole[a] - 1)) * spacing[a];
    if (std::abs(ray.direction[a]) < 1e-12) {
      if (ray.origin[a] < lo || ray.origin[a] > hi) return false;
      continue;
    }
    double u = (lo - ray.origin[a]) / ray.direction[a], v = (hi - ray.origin[a]) / ray.direction[a];
    if (u > v) std::swap(u, v);
    t0 = std::max(t0, u), t1 = std::min(t1, v);
  }
  return t0 <= t1;
}

TEST(Bricks, FootprintsHoldEveryPixelWhoseRayCrossesTheBox) {
  Scene scene = engineScene();
  const Dims dims = scene.volume.dims();
  const glm::dvec3 spacing = scene.volume.spacing();
  for (const double fov : {0.0, 40.0}) {
    scene.camera.fov_degrees = fov;
    const RayGenerator rays(scene.camera, 200, 170);
    for (const KdBrick& brick : kdSplit(dims, 4)) {
      const auto blocks = footprintBlocks(brick.own, dims, spacing, scene.camera, 200, 170);
      int crossing = 0;
      for (int y = 0; y < 170; ++y)
        for (int x = 0; x < 200; ++x) {
          if (!rayCrosses(rays, x, y, brick.own, dims, spacing)) continue;
          ++crossing;
          const int b = y / FrontTransmittance::kBlock * FrontTransmittance::blocksAcross(200) +
                        x / FrontTransmittance::kBlock;
          ASSERT_NE(std::find(blocks.begin(), blocks.end(), b), blocks.end())
              << "pixel " << x << ", " << y << " (fov " << fov << ")";
        }
      EXPECT_GT(crossing, 0);
      const int all = FrontTransmittance::blocksAcross(200) * FrontTransmittance::blocksAcross(170);
      EXPECT_LT(static_cast<int>(blocks.size()), all) << "a quarter of the grid leaves blocks out";
    }
  }
}

TEST(Bricks, KdSplitSharesOutWorkWithinTheVoxelCap) {
  const Dims dims{64, 8, 8};
  WorkGrid work{dims, std::vector<float>(64 * 8 * 8, 0.f)};  // a cell per voxel
  for (int z = 0; z < 8; ++z)
    for (int y = 0; y < 8; ++y)
      for (int x = 0; x < 16; ++x) work.cost[(z * 8 + y) * 64 + x] = 1.f;
  // Uncapped, each brick takes half the work: the plane at x = 8.
  EXPECT_EQ(kdSplit(dims, 2, &work, 100.0)[0].own.hi[0], 8);
  // Within 1.25× the voxel share the high brick holds at most 40 of the 64 columns.
  const auto capped = kdSplit(dims, 2, &work, 1.25);
  EXPECT_EQ(capped[0].own.hi[0], 24);
  EXPECT_EQ(capped[1].own.lo[0], 24);
  // No work at all: voxels, as without an estimate.
  std::fill(work.cost.begin(), work.cost.end(), 0.f);
  EXPECT_EQ(kdSplit(dims, 2, &work)[0].own.hi[0], 32);
  // An estimate of another grid is refused.
  work.cells = {65, 8, 8};
  EXPECT_THROW(kdSplit(dims, 2, &work), Error);
}

// A uniform absorber, 32 voxels deep along x, each sample keeping half the light: with early
// termination at 0.01 a ray stops after 7 samples (0.5⁷ < 0.01 < 0.5⁶), so the work lies in
// the 7–8 columns the rays enter by, on whichever side the eye is.
TEST(Bricks, WorkEstimateFollowsEarlyTerminationFromTheEye) {
  ClassifiedVolume cv;
  cv.dims = {32, 8, 8};
  cv.values.assign(32 * 8 * 8, 1.f);
  cv.entries = 2, cv.value_lo = 0.0, cv.value_scale = 1.0, cv.step_world = 1.0;
  cv.alpha = {0.f, 0.5f}, cv.transmission = {1.f, 0.5f};
  const auto columns = [](const WorkGrid& w) {
    std::vector<double> out(32, 0.0);
    for (std::size_t i = 0; i < w.cost.size(); ++i) out[i % 32] += w.cost[i];
    return out;
  };
  Camera camera{.eye = {-100, 0, 0}, .target = {0, 0, 0}, .up = {0, 0, 1}, .ortho_height = 8.0};
  const auto from_low = columns(estimateWork(cv, camera, 64, 64, 0.01));
  double near = 0, far = 0;
  for (int x = 0; x < 32; ++x) (x <= 8 ? near : far) += from_low[x];
  EXPECT_GT(near, 0.0);
  EXPECT_EQ(far, 0.0);
  camera.eye = {100, 0, 0};
  const auto from_high = columns(estimateWork(cv, camera, 64, 64, 0.01));
  for (int x = 0; x < 23; ++x) EXPECT_EQ(from_high[x], 0.0) << x;
  // Without early termination every column takes the same work.
  const auto all = columns(estimateWork(cv, camera, 64, 64, 0.0));
  for (int x = 1; x < 31; ++x) EXPECT_EQ(all[x], all[1]) << x;
}

TEST(Bricks, PhantomHasSpectralTransmittance) {
  const Scene scene = test::phantomScene();
  const SceneModel model = makeSceneModel("factor:6", scene, test::rendererObserver());
  EXPECT_EQ(classifyScene(scene, *model.model).t_channels, 6);
}

}  // namespace
}  // namespace svr
