// Designed scenes (issue 8): a scene names a designed palette's spectra as "palette/NAME", and
// rendering it through every backend shows the designed effect.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <map>

#include "renderers/classification/classification.h"
#include "renderers/scene/scene.h"
#include "renderers/render/scene_render.h"
#include "renderers/model/scene_model.h"
#include "renderers/registry.h"
#include "spectral/colour_model.h"
#include "spectral/design_palette.h"
#include "spectral/design_solver.h"
#include "base/disk_cache.h"
#include "spectral/componentwise_model.h"
#include "base/error.h"
#include "spectral/image_difference.h"
#include "spectral/post_illumination.h"
#include "tests/renderers/test_scenes.h"

namespace svr {
namespace {

Scene loadShipped(const std::string& name) {
  return loadScene(test::rendererDataDir() + "/scenes/" + name + ".json", test::rendererLibrary());
}

// Mean relit Y (white under the light = 1) over the pixels the volume covers.
double meanCoveredY(const LightIndependentImage& image, const ColourModel& model,
                    const Spectrum& light) {
  PostIlluminator post(model);
  post.setLight(test::rendererObserver().unitLuminance(light));
  std::vector<float> xyz(3 * image.pixels());
  post.relightLinear(image, xyz, RelitSpace::kXyz);
  double sum = 0;
  int covered = 0;
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x)
      if (image.transmittance(0, x, y) < 0.95) {
        sum += xyz[3 * (static_cast<std::size_t>(y) * image.width() + x) + 1];
        ++covered;
      }
  return covered ? sum / covered : -1.0;
}

// Paper Fig. 7 on the phantom: each material rendered alone (the others made transparent) is lit
// under its own light and black under the other three — through every backend, with the
// palette's 5 nm grid (spectral:81), where metameric blacks cancel exactly.
TEST(DesignedScenes, UnderEachLightOnlyItsMaterialShows) {
  Scene scene = loadShipped("one_light_per_material");
  scene.width = scene.height = 40;
  const auto model = makeSpectralModel(test::rendererObserver(), 81);
  ASSERT_EQ(scene.lights.size(), 4u);
  ASSERT_EQ(scene.transfer_function.materials.size(), 4u);
  // Which light each material was designed for (mat_a … mat_d in the scene file).
  const std::map<std::string, std::size_t> own_light{{"body", 0}, {"box", 1}, {"ball", 2},
                                                     {"small", 3}};
  for (const std::string& backend : rendererNames()) {
    const auto renderer = makeRenderer(backend);
    for (std::size_t m = 0; m < 4; ++m) {
      Scene alone = scene;
      for (std::size_t o = 0; o < 4; ++o)
        if (o != m) alone.transfer_function.materials[o].extinction = 0.0;
      const auto image = test::render(*renderer, alone, *model);
      for (std::size_t l = 0; l < 4; ++l) {
        SCOPED_TRACE(backend + " " + scene.transfer_function.materials[m].name + " under " +
                     scene.lights[l].name);
        const double y = meanCoveredY(image, *model, scene.lights[l].spectrum);
        ASSERT_GE(y, 0.0) << "the material covers no pixel";
        if (l == own_light.at(scene.transfer_function.materials[m].name))
          EXPECT_GT(y, 0.02);
        else
          EXPECT_LT(y, 0.002);
      }
    }
  }
}

// The engine designs its palette when it loads (3 s, with its projection rounds); its n-gon mixes resolve to weights.
TEST(DesignedScenes, EngineDesignsItsPaletteOnLoadAndMixesByHandlePosition) {
  const Scene scene = loadShipped("engine_designed");
  ASSERT_EQ(scene.lights.size(), 3u);
  const LightMix* centre = nullptr;
  for (const auto& mix : scene.mixes)
    if (mix.name == "centre") centre = &mix;
  ASSERT_NE(centre, nullptr);
  ASSERT_EQ(centre->weights.size(), 3u);
  for (const auto& [light, weight] : centre->weights) EXPECT_NEAR(weight, 1.0 / 3.0, 1e-12);
  // light1 was designed so that the block and the parts are metamers and the smoke is black.
  const Observer& observer = test::rendererObserver();
  const auto& materials = scene.transfer_function.materials;
  const auto relative = [&](const Spectrum& r, const Spectrum& l) {
    const Spectrum light = observer.unitLuminance(l);
    return observer.xyz(light * r);
  };
  const Spectrum& light1 = scene.lights[0].spectrum;
  const auto under1 = [&](const std::string& name) {
    for (const Material& m : materials)
      if (m.name == name) return relative(m.reflectance, light1);
    ADD_FAILURE() << "no material " << name;
    return Xyz(Xyz::Zero());
  };
  const Xyz block = under1("block"), parts = under1("parts"), smoke = under1("smoke");
  EXPECT_LT((block - parts).norm(), 0.01 * block.norm());
  EXPECT_LT(smoke.y(), 0.01);
}

// Issue 8's projection requirement: the engine's palette is designed with the projection-error
// term for factor:6 with projected light matrices (the term projects light × material signals),
// so that model (trained on the designed spectra when the scene loads) keeps every signal
// within ΔE2000 0.5 of the full spectrum's colour when projected onto its span — where a
// generic basis needs k ≈ 9 — and a factor:6 rendering, with either light matrix, relights like
// the spectral:81 one.
TEST(DesignedScenes, EnginePaletteProjectsOntoTheScenesFactor6WithinHalfAUnit) {
  Scene scene = loadShipped("engine_designed");
  const Observer& observer = test::rendererObserver();
  const SceneModel factor6 = makeSceneModel("factor:6/projected", scene, observer);
  const auto* model = dynamic_cast<const ComponentwiseModel*>(factor6.model.get());
  ASSERT_NE(model, nullptr);
  const Eigen::MatrixXd bp = model->basis() * model->projection();
  double worst = 0;
  for (const auto& named : scene.lights) {
    const Spectrum light = observer.unitLuminance(named.spectrum);
    const Xyz white = observer.xyz(light);
    for (const Material& m : scene.transfer_function.materials) {
      const Spectrum signal = light * m.reflectance;
      const Xyz full = observer.xyz(signal);
      const Xyz projected = observer.xyz(Spectrum(signal.grid(), bp * signal.values()));
      const double de = deltaE2000(xyzToLab(full, white), xyzToLab(projected, white));
      EXPECT_LE(de, 0.5) << m.name << " under " << named.name;
      worst = std::max(worst, de);
    }
  }
  EXPECT_GT(worst, 0.01);  // a span that held the signals exactly would test nothing

  scene.width = scene.height = 48;
  ClassificationOptions options;
  options.step_world = scene.stepWorld();
  const auto spectral = makeSpectralModel(observer, 81);
  const auto renderer = makeRenderer("raycast");
  auto render = [&](const ColourModel& m) {
    return test::render(*renderer, scene,
                        classify(scene.volume, scene.transfer_function, m, options));
  };
  const auto b = render(*spectral);
  for (const char* name : {"factor:6/projected", "factor:6"}) {
    const SceneModel chosen = makeSceneModel(name, scene, observer);
    const auto a = render(*chosen.model);
    for (const auto& named : scene.lights) {
      const Spectrum light = observer.unitLuminance(named.spectrum);
      const auto d = compareRelit(a, *chosen.model, b, *spectral, light, observer.xyz(light));
      // Projected: measured 0.5–1.6 (light3 worst; the palette designed without the term gives
      // 4.3 there); full: 0.07–0.18.
      EXPECT_LT(d.stats.mean, 2.0) << name << " " << named.name;
    }
  }
}

// Issue 19 goal 4: every designed scene renders with the model its file names, at most 8
// channels, within mean ΔE2000 1 of spectral:81 under every designed light and mix (same step,
// so only the colour model differs). Their materials absorb achromatically: the image is a sum
// of the designed reflectances (and the specular white), which factor:k spans exactly once k
// covers them, and full light matrices take each light whole — metameric blacks included.
TEST(DesignedScenes, EachRendersWithItsOwnFactorModelOfAtMost8ChannelsWithinOneUnit) {
  const Observer& observer = test::rendererObserver();
  const auto spectral = makeSpectralModel(observer, 81);
  const auto renderer = makeRenderer("raycast");
  for (const char* name : {"frog_designed", "one_light_per_material", "engine_designed"}) {
    Scene scene = loadShipped(name);
    scene.height = scene.height * 64 / scene.width;
    scene.width = 64;
    const SceneModel chosen = makeSceneModel(scene.model, scene, observer);
    EXPECT_LE(chosen.model->channels(), 8) << name << ": " << chosen.description;
    const auto a = test::render(*renderer, scene, *chosen.model);
    const auto b = test::render(*renderer, scene, *spectral);
    const auto illuminations = sceneIlluminations(scene, observer);
    ASSERT_EQ(illuminations.size(), scene.lights.size() + scene.mixes.size());
    for (std::size_t i = 0; i < illuminations.size(); ++i) {
      const Spectrum& light = illuminations[i];
      const auto d = compareRelit(a, *chosen.model, b, *spectral, light, observer.xyz(light));
      // auto's probe (96 px, the same step) measures frog_designed's factor:8 at 0.001 and the
      // other two at 0.000: the palettes fit exactly, and what remains is float rounding.
      EXPECT_LE(d.stats.mean, 1.0) << name << " illumination " << i;
    }
  }
}

TEST(DesignedScenes, APaletteNeedsExactlyOneSource) {
  const nlohmann::json both = {{"design", "a.json"}, {"designed", "b.json"}};
  nlohmann::json scene = nlohmann::json::parse(R"({"volume": {"procedural": "phantom"}})");
  scene["palette"] = both;
  try {
    parseScene(scene, "/tmp/x.json", test::rendererLibrary(), {});
    FAIL() << "accepted both";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("palette"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("exactly one"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace svr

namespace svr {
namespace {

// A designed palette is stored in the disk cache and read back bit for bit: the cached spectra
// equal a fresh design of the same palette file (the second load of engine_designed takes
// milliseconds instead of seconds; cache failures are tested in disk_cache_test and cli.cache).
TEST(DesignedScenes, TheCachedPaletteEqualsAFreshDesign) {
  const DiskCache& cache = DiskCache::process();
  ASSERT_TRUE(cache.enabled()) << "ctest sets XDG_CACHE_HOME";
  const Scene first = loadShipped("engine_designed");
  const Scene second = loadShipped("engine_designed");  // a hit, whatever the first was
  bool stored = false;
  for (const auto& entry : std::filesystem::directory_iterator(cache.directory()))
    stored = stored || entry.path().filename().string().rfind("palette-", 0) == 0;
  EXPECT_TRUE(stored) << cache.directory();
  const Observer& observer = test::rendererObserver();
  const DesignResult fresh = designPalette(
      loadDesignPalette(test::rendererDataDir() + "/palettes/engine.json", test::rendererLibrary(),
                        observer),
      observer);
  ASSERT_EQ(second.lights.size(), 3u);
  for (const NamedSpectrum& light : fresh.lights) {
    bool found = false;
    for (const auto& l : second.lights)
      if (l.name == "palette/" + light.name || l.name == light.name) {
        found = true;
        EXPECT_EQ(l.spectrum.values(), light.spectrum.values()) << light.name;
      }
    EXPECT_TRUE(found) << light.name;
  }
  for (std::size_t m = 0; m < first.transfer_function.materials.size(); ++m)
    EXPECT_EQ(first.transfer_function.materials[m].reflectance.values(),
              second.transfer_function.materials[m].reflectance.values());
}

}  // namespace
}  // namespace svr
