// The public API (include/svr/svr.h) as a program sees it: linked to libsvr.so only, through
// the public header only.

#include <svr/svr.h>

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

namespace {

namespace fs = std::filesystem;

const std::string kPhantom = std::string(SVR_TEST_DATA_DIR) + "/scenes/phantom.json";

svr::RenderSettings small(const std::string& model = "rgb") {
  svr::RenderSettings s;
  s.model = model;
  s.width = 40;
  s.height = 32;
  s.data_dir = SVR_TEST_DATA_DIR;
  return s;
}

std::string errorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const svr::Error& e) {
    return e.what();
  }
  return "no error";
}

TEST(Session, RendersTheSceneAtTheAskedSizeWithTheAskedModel) {
  svr::Session session = svr::Session::fromFile(kPhantom, small("factor:4"));
  EXPECT_EQ(session.width(), 40);
  EXPECT_EQ(session.height(), 32);
  // factor:4 is the best of its candidates on the scene's render; on the phantom that is rgb
  // in four channels, which relights with projected light matrices (factor:4/projected).
  EXPECT_EQ(session.modelName().rfind("factor:4", 0), 0u) << session.modelName();
  EXPECT_EQ(session.rendererName(), "raycast");
  EXPECT_GE(session.imagePlanes(), 5);  // 4 S channels and at least one T channel
  const svr::RgbImage image = session.relight(session.lights().front());
  EXPECT_EQ(image.width, 40);
  EXPECT_EQ(image.height, 32);
  ASSERT_EQ(image.pixels.size(), 3u * 40 * 32);
  long lit = 0;
  for (auto v : image.pixels) lit += v > 0;
  EXPECT_GT(lit, 100) << "the phantom is not black under its first light";
}

TEST(Session, AMixOfOneLightIsThatLightAndMixesAreLinear) {
  svr::Session session = svr::Session::fromFile(kPhantom, small());
  session.render();
  const svr::RgbImage d65 = session.relight("D65");
  EXPECT_EQ(session.relight({{"D65", 1.0}}).pixels, d65.pixels);
  EXPECT_EQ(session.relight({{"D65", 0.5}, {"D65", 0.5}}).pixels, d65.pixels);
  EXPECT_NE(session.relight("F11").pixels, d65.pixels);
}

TEST(Session, ASceneWrittenInCodeIsTheSceneOfItsFile) {
  std::ifstream in(kPhantom);
  std::stringstream text;
  text << in.rdbuf();
  svr::Session from_file = svr::Session::fromFile(kPhantom, small());
  svr::Session from_json = svr::Session::fromJson(text.str(), fs::path(kPhantom).parent_path().string(), small());
  EXPECT_EQ(from_json.lights(), from_file.lights());
  EXPECT_EQ(from_json.relight(from_file.lights().front()).pixels, from_file.relight(from_file.lights().front()).pixels);
}

TEST(Session, SavedPngIsWrittenAndABadImageIsRefused) {
  svr::Session session = svr::Session::fromFile(kPhantom, small());
  const fs::path png = fs::temp_directory_path() / ("svr_api_test_" + std::to_string(::getpid()) + ".png");
  session.relight("A").savePng(png.string());
  EXPECT_GT(fs::file_size(png), 100u);
  fs::remove(png);
  svr::RgbImage bad{4, 4, std::vector<std::uint8_t>(10)};
  EXPECT_EQ(errorOf([&] { bad.savePng("x.png"); }), "x.png: an RgbImage of 4×4 must hold 48 bytes, not 10");
}

TEST(Session, BadInputIsAnErrorNamingIt) {
  svr::RenderSettings bad_renderer = small();
  bad_renderer.renderer = "raytrace";
  EXPECT_NE(errorOf([&] { svr::Session::fromFile(kPhantom, bad_renderer); }).find("raytrace"), std::string::npos);
  EXPECT_NE(errorOf([] { svr::Session::fromFile("/nonexistent/scene.json", small()); }).find("/nonexistent/scene.json"),
            std::string::npos);
  EXPECT_NE(errorOf([] { svr::Session::fromJson("{\"volume\": ", ".", small()); }).find("scene JSON"), std::string::npos);
  svr::Session session = svr::Session::fromFile(kPhantom, small());
  EXPECT_NE(errorOf([&] { session.relight("NoSuchLight"); }).find("NoSuchLight"), std::string::npos);
  EXPECT_EQ(errorOf([&] { session.relight({{"D65", -1.0}}); }), "relight: weight -1 of light 'D65' must be finite and ≥ 0");
  EXPECT_EQ(errorOf([&] { session.relight(std::vector<std::pair<std::string, double>>{}); }), "relight: the mix has no lights");
}

TEST(Session, VersionIsTheProjects) { EXPECT_EQ(svr::version(), SVR_TEST_VERSION); }

}  // namespace
