// The render session's reused parts make the frames a fresh session makes: another model
// through setModel is the image of a session built with that model, another view through
// renderView is the image of a session whose scene has that camera and size, and taking the
// image out leaves the session with none. A model chosen on a probe render leaves its
// classification to the session.

#include "harness/render_session.h"

#include <gtest/gtest.h>

#include <memory>

#include "base/disk_cache.h"
#include "base/error.h"
#include "renderers/model/scene_model.h"
#include "renderers/render/scene_render.h"
#include "renderers/scene/camera.h"
#include "tests/renderers/test_scenes.h"

namespace svr {
namespace {

std::shared_ptr<const SessionSpectra> spectra() {
  static const auto loaded = std::make_shared<const SessionSpectra>(test::rendererDataDir());
  return loaded;
}

FrameSettings raycastWith(const std::string& model) {
  FrameSettings s;
  s.renderer = "raycast";
  s.model = model;
  return s;
}

void expectSameImage(const LightIndependentImage& a, const LightIndependentImage& b) {
  ASSERT_EQ(a.width(), b.width());
  ASSERT_EQ(a.height(), b.height());
  ASSERT_EQ(a.planes(), b.planes());
  for (int p = 0; p < a.planes(); ++p)
    for (int y = 0; y < a.height(); ++y)
      for (int x = 0; x < a.width(); ++x)
        ASSERT_EQ(a.sample(p, x, y), b.sample(p, x, y)) << "plane " << p << " at " << x << ", " << y;
}

TEST(RenderSession, SetModelRendersAsAFreshSessionWithThatModel) {
  RenderSession reused(spectra(), test::phantomScene(), raycastWith("rgb"), "phantom");
  reused.render();
  EXPECT_EQ(reused.image().channels(), 3);
  reused.setModel("factor:6");
  EXPECT_FALSE(reused.rendered());  // the rgb image is dropped with its classification
  reused.render();
  RenderSession fresh(spectra(), test::phantomScene(), raycastWith("factor:6"), "phantom");
  fresh.render();
  EXPECT_EQ(reused.model().model->name(), fresh.model().model->name());
  expectSameImage(reused.image(), fresh.image());
}

TEST(RenderSession, RenderViewRendersAsASessionWithThatCamera) {
  RenderSession session(spectra(), test::phantomScene(), raycastWith("rgb"), "phantom");
  const Camera other = orbitCamera(session.scene().camera, OrbitView{40, 25, 1.3});
  const LightIndependentImage view = session.renderView(other, 40, 30);
  Scene moved = test::phantomScene();
  moved.camera = other;
  moved.width = 40;
  moved.height = 30;
  RenderSession fresh(spectra(), std::move(moved), raycastWith("rgb"), "phantom");
  fresh.render();
  expectSameImage(view, fresh.image());
  EXPECT_FALSE(session.rendered());  // a view is returned, not kept
}

// A factor:k chosen on a probe render hands the probe's classification of the volume on to
// the session, which bakes the chosen model's tables into it instead of classifying again: the
// same classification as a fresh one, table for table.
TEST(RenderSession, TakesTheClassificationTheModelsProbeMade) {
  // A cached choice renders no probe; this process runs without the cache from here on.
  DiskCache::disableProcessCache();
  const Scene scene = test::phantomScene();
  SceneModel chosen = makeSceneModel("factor:6", scene, spectra()->observer);
  ASSERT_TRUE(chosen.classification) << chosen.description;
  RenderSession session(spectra(), scene, raycastWith("factor:6"), "phantom");
  EXPECT_EQ(session.model().model->toJson(), chosen.model->toJson());
  const ClassifiedVolume fresh = classifyScene(scene, *chosen.model);
  const ClassifiedVolume& taken = session.classified();
  EXPECT_EQ(taken.k, 6);
  test::expectSameClassification(taken, fresh);
  EXPECT_FALSE(session.model().classification);  // taken, not kept twice
}

TEST(RenderSession, TakeImageLeavesNone) {
  RenderSession session(spectra(), test::phantomScene(), raycastWith("rgb"), "phantom");
  EXPECT_THROW(session.takeImage(), Error);
  session.render();
  const LightIndependentImage taken = session.takeImage();
  EXPECT_EQ(taken.width(), session.scene().width);
  EXPECT_FALSE(session.rendered());
  EXPECT_THROW(session.image(), Error);
}

}  // namespace
}  // namespace svr
