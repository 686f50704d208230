// svr view's server over real HTTP (cpp-httplib's client against ViewServer on loopback): what
// it answers, what it refuses, under load, and where it listens.

#include "harness/view/view_server.h"

#include <gtest/gtest.h>
#include <httplib.h>

#include <atomic>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <thread>

#include "renderers/render/scene_render.h"
#include "renderers/registry.h"
#include "base/error.h"
#include "harness/view/frame_format.h"

#include <fmt/format.h>

namespace svr {
namespace {
namespace fs = std::filesystem;

// A small scene of its own: a procedural sphere, two library lights and a mix, the rgb model (no
// training), so every test starts in well under a second; or another fixed model.
std::string writeScene(const fs::path& dir, const std::string& model = "rgb") {
  fs::create_directories(dir);
  const fs::path file = dir / "sphere.json";
  std::ofstream(file) << R"json({
  "volume": {"procedural": "sphere", "size": 24},
  "materials": {"red": {"reflectance": "ColorChecker/red", "opacity": 0.6},
                "blue": {"reflectance": "ColorChecker/blue", "opacity": 0.6}},
  "transfer_function": {"type": "scalar", "points": [[0.2, "red"], [0.8, "blue"]],
                        "opacity": [[0.0, 0.0], [0.2, 1.0]]},
  "lights": [{"name": "D65", "library": "D65"}, {"name": "A", "library": "A"}],
  "light_mixes": {"half": {"D65": 0.5, "A": 0.5}},
  "background": "ColorChecker/white 9.5 (.05 D)",
  "image": {"width": 48, "height": 40},
  "model": ")json" << model << R"json("
})json";
  return file.string();
}

// The JSON header and the plane bytes of a frame (harness/view/frame_format.h).
std::pair<nlohmann::json, std::string> splitFrame(const std::string& body) {
  EXPECT_EQ(body.substr(0, 4), "SVRI");
  std::uint32_t n = 0;
  for (int b = 0; b < 4; ++b) n |= std::uint32_t(static_cast<unsigned char>(body[4 + b])) << (8 * b);
  EXPECT_EQ((8 + n) % 4, 0u);
  return {nlohmann::json::parse(body.substr(8, n)), body.substr(8 + n)};
}

// The frame's plane bytes are the image's planes, sample for sample.
void expectPlanes(const std::string& planes, const LightIndependentImage& image, size_t sample_bytes) {
  const size_t plane_bytes = image.pixels() * sample_bytes;
  ASSERT_EQ(planes.size(), plane_bytes * image.planes());
  for (int p = 0; p < image.planes(); ++p)
    EXPECT_EQ(0, std::memcmp(planes.data() + p * plane_bytes, image.planeData(p), plane_bytes))
        << "plane " << p;
}

class ViewServerTest : public ::testing::Test {
 protected:
  void start(bool read_only = false, std::uint64_t budget = 0, const std::string& host = "127.0.0.1",
             const std::string& token = "", const std::string& model = "rgb") {
    dir_ = fs::temp_directory_path() / ("svr_view_test_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    ViewOptions o;
    o.scene = writeScene(dir_, model);
    o.renderer = "raycast";
    o.data_dir = SVR_TEST_DATA_DIR;
    o.read_only = read_only;
    if (budget) o.memory_budget = budget;
    session_ = std::make_unique<ViewSession>(o);
    server_ = std::make_unique<ViewServer>(*session_);
    port_ = server_->bind(host, 0, token);
    thread_ = std::thread([this] { server_->listen(); });
    host_ = host;
  }
  void TearDown() override {
    if (server_) server_->stop();
    if (thread_.joinable()) thread_.join();
    fs::remove_all(dir_);
  }
  httplib::Client client() const {
    httplib::Client c(host_, port_);
    c.set_read_timeout(60, 0);
    return c;
  }
  // status and body of GET path
  std::pair<int, std::string> get(const std::string& path) const {
    auto c = client();
    const auto r = c.Get(path.c_str());
    return r ? std::pair{r->status, r->body} : std::pair{-1, std::string()};
  }

  fs::path dir_;
  std::unique_ptr<ViewSession> session_;
  std::unique_ptr<ViewServer> server_;
  std::thread thread_;
  std::string host_;
  int port_ = 0;
};

TEST_F(ViewServerTest, SceneInfoHasEveryLightAsARelightMatrix) {
  start();
  const auto [status, body] = get("/api/scene");
  ASSERT_EQ(status, 200) << body;
  const auto info = nlohmann::json::parse(body);
  EXPECT_EQ(info["model"]["name"], "rgb");
  ASSERT_EQ(info["lights"].size(), 2u);
  const int planes = info["channels"].get<int>() + info["t_channels"].get<int>();
  for (const auto& light : info["lights"]) {
    ASSERT_EQ(light["matrix"].size(), 3u);
    EXPECT_EQ(light["matrix"][0].size(), static_cast<size_t>(planes));
  }
  // A library light asked for by name is the same matrix as the scene light of that spectrum.
  const auto [s2, b2] = get("/api/light?name=D65");
  ASSERT_EQ(s2, 200) << b2;
  EXPECT_EQ(nlohmann::json::parse(b2)["matrix"], info["lights"][0]["matrix"]);
  EXPECT_EQ(info["mixes"][0]["name"], "half");
  EXPECT_EQ(info["mixes"][0]["weights"], nlohmann::json({0.5, 0.5}));
}

TEST_F(ViewServerTest, RenderIsTheBackendsImageOfThatView) {
  start();
  auto c = client();
  const auto r = c.Get("/api/render?azimuth=30&elevation=10&zoom=1.5&width=32&height=24&samples=float");
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200) << r->body;
  // The same view rendered directly.
  const Scene& scene = session_->scene();
  RenderRequest req = sceneRequest(scene, session_->classified());
  req.camera = orbitCamera(scene.camera, {30, 10, 1.5});
  req.width = 32, req.height = 24;
  const LightIndependentImage image = makeRenderer("raycast")->render(req);
  const auto [header, planes] = splitFrame(r->body);
  EXPECT_EQ(header["width"], 32);
  EXPECT_EQ(header["height"], 24);
  EXPECT_EQ(header["channels"], image.channels());
  EXPECT_EQ(header["t_channels"], image.transmittanceChannels());
  EXPECT_EQ(header["samples"], "float");
  expectPlanes(planes, image, 4);
  // Half samples: the same image rounded to half floats.
  const auto h = c.Get("/api/render?azimuth=30&elevation=10&zoom=1.5&width=32&height=24&samples=half");
  ASSERT_TRUE(h);
  const LightIndependentImage half = image.withStorage(SampleStorage::kHalf);
  const auto [half_header, half_planes] = splitFrame(h->body);
  EXPECT_EQ(half_header["samples"], "half");
  expectPlanes(half_planes, half, 2);
}

struct Refusal {
  const char* path;
  int status;
  const char* message;
};

TEST_F(ViewServerTest, BadRequestsAreRefusedWithTheParameterAndTheServerKeepsServing) {
  start();
  const std::string long_query = "/api/render?azimuth=" + std::string(10000, '1');
  const Refusal cases[] = {
      {"/api/render?width=0", 400, "parameter width=0 is outside 1..2048"},
      {"/api/render?height=1000000", 400, "parameter height=1000000 is outside 1..2048"},
      {"/api/render?width=99999999999999", 400, "parameter width='99999999999999' is not a whole number"},
      {"/api/render?width=12.5", 400, "parameter width='12.5' is not a whole number"},
      {"/api/render?zoom=nan", 400, "parameter zoom='nan' is not a finite number"},
      {"/api/render?zoom=inf", 400, "parameter zoom='inf' is not a finite number"},
      {"/api/render?azimuth=1e400", 400, "parameter azimuth='1e400' is not a finite number"},
      {"/api/render?zoom=0", 400, "parameter zoom=0 is outside 0.01..100"},
      {"/api/render?elevation=91", 400, "parameter elevation=91 is outside -90..90"},
      {"/api/render?azimuth=abc", 400, "parameter azimuth='abc' is not a finite number"},
      {"/api/render?azimuth=", 400, "parameter azimuth='' is not a finite number"},
      {"/api/render?samples=double", 400, "parameter samples='double' is not half or float"},
      {"/api/render?width=8&width=9", 400, "parameter 'width' is given more than once"},
      {"/api/render?colour=red", 400, "unknown parameter 'colour'; expected azimuth"},
      {"/api/light?name=NoSuchLight", 404, "unknown spectrum 'NoSuchLight'"},
      {"/api/light", 400, "parameter 'name' is missing"},
      {"/api/scene?x=1", 400, "unknown parameter 'x' (this path takes none)"},
      {"/api/mixer-weights?x=1&nodes=0:0", 400, "nodes item '0:0' is not x:y:on"},
      {"/api/mixer-weights?y=nan", 400, "parameter y='nan' is not a finite number"},
      {"/nothing", 404, "no such path '/nothing'"},
      {"/api/nothing", 404, "no such path '/api/nothing'"},
      {"/../../etc/passwd", 404, "no such path"},
      {"/%2e%2e/%2e%2e/etc/passwd", 404, "no such path"},
      {"/viewer.js?x=1", 400, "unknown parameter 'x'"},
      {"/?relight=vulkan", 400, "parameter relight='vulkan' is not auto, webgl2 or js"},
      {"/api/light?name=%ff%fe", 404, "unknown spectrum"},
      {"/api/light?name=a%00b", 400, "holds control characters"},
      {long_query.c_str(), 414, "request refused (HTTP 414)"},
  };
  for (const auto& c : cases) {
    const auto [status, body] = get(c.path);
    const std::string shown_path = std::string(c.path).substr(0, 60);
    EXPECT_EQ(status, c.status) << shown_path << ": " << body;
    EXPECT_NE(body.find(c.message), std::string::npos) << shown_path << ": " << body;
  }
  EXPECT_EQ(get("/api/scene").first, 200);
  EXPECT_EQ(get("/").first, 200);
  EXPECT_EQ(get("/api/render?width=8&height=8").first, 200);
}

TEST_F(ViewServerTest, SavingAMixWritesItIntoTheSceneFile) {
  start();
  auto c = client();
  const auto ok = c.Post("/api/mixes?name=dusk", R"({"weights": {"D65": 0.25, "F11": 0.75}})",
                         "application/json");
  ASSERT_TRUE(ok);
  ASSERT_EQ(ok->status, 200) << ok->body;
  std::ifstream in(dir_ / "sphere.json");
  const auto doc = nlohmann::json::parse(in);
  EXPECT_EQ(doc["light_mixes"]["dusk"], nlohmann::json({{"D65", 0.25}, {"F11", 0.75}}));
  EXPECT_EQ(doc["lights"].back(), nlohmann::json({{"name", "F11"}, {"library", "F11"}}));
  EXPECT_EQ(doc["light_mixes"]["half"], nlohmann::json({{"D65", 0.5}, {"A", 0.5}}));  // kept
  const Refusal bad[] = {
      {R"({"weights": {"D65": -1}})", 400, "weight -1 of light 'D65' must be finite and ≥ 0"},
      {R"({"weights": {"D65": 0}})", 400, "mix weights are all 0"},
      {R"({"weights": {"Nope": 1}})", 400, "unknown spectrum 'Nope'"},
      {R"({"weights": {"D65": "1"}})", 400, "weight of light 'D65' is not a number"},
      {R"(not json)", 400, "the body must be JSON"},
  };
  for (const auto& b : bad) {
    const auto r = c.Post("/api/mixes?name=x", b.path, "application/json");
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, b.status) << b.path;
    EXPECT_NE(r->body.find(b.message), std::string::npos) << r->body;
  }
  const auto name = c.Post("/api/mixes?name=../evil", R"({"weights": {"D65": 1}})", "application/json");
  EXPECT_EQ(name->status, 400);
  EXPECT_NE(name->body.find("mix name '../evil' must be"), std::string::npos) << name->body;
  const auto big = c.Post("/api/mixes?name=big", std::string(100000, ' '), "application/json");
  EXPECT_EQ(big->status, 413);
  const auto form = c.Post("/api/mixes?name=f", "weights=1", "application/x-www-form-urlencoded");
  EXPECT_EQ(form->status, 415);
  EXPECT_NE(form->body.find("the body must be application/json"), std::string::npos) << form->body;
  const auto method = c.Delete("/api/scene");
  EXPECT_EQ(method->status, 405);
  EXPECT_NE(method->body.find("method DELETE is not served"), std::string::npos) << method->body;
}

TEST_F(ViewServerTest, ReadOnlyRefusesToSave) {
  start(/*read_only=*/true);
  auto c = client();
  const auto r = c.Post("/api/mixes?name=dusk", R"({"weights": {"D65": 1}})", "application/json");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 403);
  EXPECT_NE(r->body.find("--read-only"), std::string::npos);
}

TEST_F(ViewServerTest, TheExactModelIsServedWithinTheFrameValueLimit) {
  // spectral:81 makes 81 S planes and one T plane: 2048² of them is over the 2048² × 32 values a
  // frame may hold, refused before any work; the scene's own size is served, every plane.
  start(false, 0, "127.0.0.1", "", "spectral:81");
  const auto [status, body] = get("/api/render?width=2048&height=2048");
  EXPECT_EQ(status, 400) << body;
  EXPECT_NE(body.find("a 2048×2048 frame of 82 planes holds 343932928 values, over the viewer's "
                      "limit of 134217728; ask for at most 1636801 pixels"),
            std::string::npos)
      << body;
  const auto [ok, frame] = get("/api/render?width=48&height=40");
  ASSERT_EQ(ok, 200) << frame;
  const auto [header, planes] = splitFrame(frame);
  EXPECT_EQ(header["channels"], 81);
  EXPECT_EQ(header["t_channels"], 1);
  const std::size_t sample_bytes = session_->sceneInfo()["samples"] == "half" ? 2 : 4;
  EXPECT_EQ(planes.size(), 48u * 40u * 82u * sample_bytes);
  const auto [scene_status, scene] = get("/api/scene");
  EXPECT_EQ(nlohmann::json::parse(scene)["lights"][0]["matrix"][0].size(), 82u) << scene;
}

TEST_F(ViewServerTest, ARenderThatFailsAnswers500AndTheServerGoesOn) {
  // 8 MiB holds the voxels and small frames, not a 2048² frame of its planes.
  start(false, 8u << 20);
  const auto [status, body] = get("/api/render?width=2048&height=2048");
  EXPECT_EQ(status, 500) << body;
  EXPECT_NE(body.find("memory budget"), std::string::npos) << body;
  EXPECT_EQ(get("/api/render?width=16&height=16").first, 200);
}

long residentKiB() {
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("VmRSS:", 0) == 0) return std::stol(line.substr(6));
  return -1;
}

TEST_F(ViewServerTest, HundredsOfConcurrentRequestsAreAllAnsweredInBoundedMemory) {
  start();
  get("/api/render?width=48&height=40");  // warm
  const long before = residentKiB();
  constexpr int kClients = 300;
  std::atomic<int> ok{0}, superseded{0}, other{0};
  std::vector<std::thread> clients;
  for (int i = 0; i < kClients; ++i) {
    clients.emplace_back([&, i] {
      const std::string path = i % 3 == 0   ? "/api/scene"
                               : i % 3 == 1 ? "/api/light?name=F11"
                                            : "/api/render?width=48&height=40&azimuth=" + std::to_string(i);
      httplib::Client c(host_, port_);
      c.set_read_timeout(120, 0);
      c.set_connection_timeout(60, 0);
      const auto r = c.Get(path.c_str());
      if (r && r->status == 200) ++ok;
      else if (r && r->status == 409 && r->body.find("superseded") != std::string::npos) ++superseded;
      else ++other;
    });
  }
  for (auto& t : clients) t.join();
  EXPECT_EQ(other.load(), 0);
  EXPECT_EQ(ok + superseded, kClients);
  EXPECT_GE(ok.load(), 2 * kClients / 3);  // only renders may be superseded
  const long grown = residentKiB() - before;
  EXPECT_LT(grown, 256 * 1024) << "resident memory grew by " << grown << " KiB";
  // Requests one after another are never superseded.
  for (int i = 0; i < 5; ++i) EXPECT_EQ(get("/api/render?width=16&height=16").first, 200);
}

TEST_F(ViewServerTest, ListensOnLoopbackOnlyByDefault) {
  start();
  EXPECT_EQ(get("/api/scene").first, 200);
  // 127.0.0.2 is this machine too, but the server bound 127.0.0.1 alone: not 0.0.0.0.
  httplib::Client other("127.0.0.2", port_);
  other.set_connection_timeout(2, 0);
  EXPECT_FALSE(other.Get("/api/scene"));
}

TEST_F(ViewServerTest, ListensWhereHostSays) {
  start(false, 0, "127.0.0.2");
  EXPECT_EQ(get("/api/scene").first, 200);
  httplib::Client loopback("127.0.0.1", port_);
  loopback.set_connection_timeout(2, 0);
  EXPECT_FALSE(loopback.Get("/api/scene"));
}

// The scene file's text, whole.
std::string fileText(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

bool hasCorsHeader(const httplib::Result& r) {
  for (const auto& [key, value] : r->headers)
    if (key.rfind("Access-Control-", 0) == 0) return true;
  return false;
}

TEST_F(ViewServerTest, AnotherSitesHostOrOriginIsRefusedBeforeAnyWork) {
  start();
  auto c = client();
  const std::string own = fmt::format("127.0.0.1:{}", port_), foreign = fmt::format("attacker.example:{}", port_);
  const std::string scene_before = fileText(dir_ / "sphere.json");
  // DNS rebinding: the attacker's name as Host.
  for (const char* path : {"/api/scene", "/api/render?width=8&height=8", "/", "/api/light?name=D65"}) {
    const auto r = c.Get(path, {{"Host", foreign}});
    ASSERT_TRUE(r) << path;
    EXPECT_EQ(r->status, 403) << path;
    EXPECT_NE(r->body.find("Host 'attacker.example:" + std::to_string(port_) + "' is not this server"),
              std::string::npos) << r->body;
    EXPECT_FALSE(hasCorsHeader(r)) << path;
  }
  const std::string mix = R"({"weights": {"D65": 1}})";
  const auto rebound = c.Post("/api/mixes?name=evil", {{"Host", foreign}}, mix, "application/json");
  ASSERT_TRUE(rebound);
  EXPECT_EQ(rebound->status, 403);
  // A page of another site posting to the real address: its Origin gives it away.
  for (const char* origin : {"http://attacker.example", "null"}) {
    const auto r = c.Post("/api/mixes?name=evil", {{"Origin", origin}}, mix, "application/json");
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 403) << origin;
    EXPECT_NE(r->body.find("is not this server's page"), std::string::npos) << r->body;
  }
  const auto cors_get = c.Get("/api/scene", {{"Origin", "http://attacker.example"}});
  EXPECT_EQ(cors_get->status, 403);
  // A large body from a refused sender is not read: the answer is the refusal, not 413.
  const auto big = c.Post("/api/mixes?name=evil", {{"Host", foreign}}, std::string(100000, ' '), "application/json");
  EXPECT_EQ(big->status, 403);
  EXPECT_EQ(fileText(dir_ / "sphere.json"), scene_before) << "a refused request wrote the scene file";
  // The server's own names and Origin pass.
  for (const std::string& host : {own, fmt::format("localhost:{}", port_), fmt::format("[::1]:{}", port_)})
    EXPECT_EQ(c.Get("/api/scene", {{"Host", host}})->status, 200) << host;
  const auto ok = c.Post("/api/mixes?name=mine", {{"Origin", "http://" + own}}, mix, "application/json");
  EXPECT_EQ(ok->status, 200) << ok->body;
  EXPECT_FALSE(hasCorsHeader(ok));
  const auto options = c.Options("/api/mixes", {{"Origin", "http://attacker.example"}});
  ASSERT_TRUE(options);
  EXPECT_EQ(options->status, 403);
  EXPECT_FALSE(hasCorsHeader(options));
}

TEST_F(ViewServerTest, WithATokenEveryRequestNeedsItAndThePageGetsACookie) {
  const std::string token = "s3cret-token-for-this-test";
  start(false, 0, "127.0.0.1", token);
  auto c = client();
  for (const char* path : {"/", "/api/scene", "/viewer.js", "/api/render?width=8&height=8"}) {
    const auto r = c.Get(path);
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 403) << path;
    EXPECT_NE(r->body.find("needs its token"), std::string::npos) << r->body;
  }
  EXPECT_EQ(c.Get("/api/scene?token=wrong-token")->status, 403);
  EXPECT_EQ(c.Post("/api/mixes?name=x", R"({"weights": {"D65": 1}})", "application/json")->status, 403);
  // The page, opened with the token, hands the browser a cookie for this port only.
  const auto page = c.Get(("/?token=" + token + "&relight=js").c_str());
  ASSERT_EQ(page->status, 200) << page->body;
  EXPECT_EQ(page->get_header_value("Set-Cookie"),
            fmt::format("svr-token-{}={}; Path=/; HttpOnly; SameSite=Strict", port_, token));
  const httplib::Headers cookie = {{"Cookie", fmt::format("svr-token-{}={}", port_, token)}};
  EXPECT_EQ(c.Get("/api/scene", cookie)->status, 200);
  EXPECT_EQ(c.Get("/api/render?width=8&height=8", cookie)->status, 200);
  EXPECT_EQ(c.Get(("/api/scene?token=" + token).c_str())->status, 200);
  EXPECT_FALSE(c.Get(("/api/scene?token=" + token).c_str())->has_header("Set-Cookie"));
  EXPECT_EQ(c.Post("/api/mixes?name=x", cookie, R"({"weights": {"D65": 1}})", "application/json")->status, 200);
  // Another port's cookie is not this server's.
  EXPECT_EQ(c.Get("/api/scene", {{"Cookie", fmt::format("svr-token-{}={}", port_ + 1, token)}})->status, 403);
}

TEST_F(ViewServerTest, SavingAMixChangesOnlyItsEntriesOfTheSceneText) {
  start();
  const fs::path file = dir_ / "sphere.json";
  const std::string before = fileText(file);
  auto c = client();
  const auto r = c.Post("/api/mixes?name=dusk", R"({"weights": {"D65": 0.25, "F11": 0.75}})", "application/json");
  ASSERT_EQ(r->status, 200) << r->body;
  std::string expected = before;
  const std::string lights = R"({"name": "A", "library": "A"})";
  expected.insert(expected.find(lights) + lights.size(), R"(, {"name": "F11", "library": "F11"})");
  const std::string mixes = R"({"D65": 0.5, "A": 0.5})";
  expected.insert(expected.find(mixes) + mixes.size(), R"(, "dusk": {"D65": 0.25, "F11": 0.75})");
  EXPECT_EQ(fileText(file), expected);
  // Saved again under the same name: replaced where it stands.
  ASSERT_EQ(c.Post("/api/mixes?name=dusk", R"({"weights": {"A": 1}})", "application/json")->status, 200);
  expected.replace(expected.find(R"({"D65": 0.25, "F11": 0.75})"), 26, R"({"A": 1.0})");
  EXPECT_EQ(fileText(file), expected);
  // The file changed by someone else: not overwritten, 409, the file as they left it.
  const std::string theirs = expected + "\n";
  std::ofstream(file, std::ios::binary) << theirs;
  const auto conflict = c.Post("/api/mixes?name=late", R"({"weights": {"A": 1}})", "application/json");
  ASSERT_TRUE(conflict);
  EXPECT_EQ(conflict->status, 409);
  EXPECT_NE(conflict->body.find("changed on disk since svr view loaded it"), std::string::npos) << conflict->body;
  EXPECT_EQ(fileText(file), theirs);
  fs::remove(file);
  const auto gone = c.Post("/api/mixes?name=late", R"({"weights": {"A": 1}})", "application/json");
  EXPECT_EQ(gone->status, 409);
  EXPECT_FALSE(fs::exists(file));
}

TEST(ViewServerBind, AnAddressNotOfThisMachineIsAClearError) {
  const fs::path dir = fs::temp_directory_path() / ("svr_view_bind_" + std::to_string(::getpid()));
  ViewOptions o;
  o.scene = writeScene(dir);
  o.renderer = "raycast";
  o.data_dir = SVR_TEST_DATA_DIR;
  ViewSession session(o);
  ViewServer server(session);
  // 192.0.2.1 is TEST-NET-1 (RFC 5737): never an address of this machine; binding is refused
  // locally, nothing is sent.
  try {
    server.bind("192.0.2.1", 0);
    ADD_FAILURE() << "bind succeeded";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("cannot listen on 192.0.2.1:0"), std::string::npos) << e.what();
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace svr
