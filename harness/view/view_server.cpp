#include "harness/view/view_server.h"

#include <fmt/format.h>
#include <httplib.h>

#include <sys/socket.h>

#include <optional>
#include <sstream>

#include "base/error.h"
#include "spectral/light_mixer.h"
#include "harness/view/frame_format.h"
#include "harness/view/view_params.h"
#include "harness/view/web_assets.h"

namespace svr {

namespace {

constexpr size_t kMaxBody = 64 * 1024;  // a saved mix is a few hundred bytes

void answer(httplib::Response& res, int status, const std::string& message) {
  res.status = status;
  // Messages may quote what a client sent: bytes that are not UTF-8 are replaced, not thrown.
  res.set_content(nlohmann::json{{"error", message}}.dump(-1, ' ', false,
                                                        nlohmann::json::error_handler_t::replace) +
                      "\n",
                  "application/json");
}

void answerJson(httplib::Response& res, const nlohmann::json& body) {
  res.set_header("Cache-Control", "no-store");
  res.set_content(body.dump() + "\n", "application/json");
}

// Runs a handler, turning what it throws into the answer the API promises: BadRequest → 400,
// SceneFileChanged → 409, svr::Error (a render or file that failed) → `error_status` with the
// reason.
template <class F>
void guarded(httplib::Response& res, int error_status, F&& f) {
  try {
    f();
  } catch (const BadRequest& e) {
    answer(res, 400, e.what());
  } catch (const SceneFileChanged& e) {
    answer(res, 409, e.what());
  } catch (const Error& e) {
    answer(res, error_status, e.what());
  } catch (const std::bad_alloc&) {
    answer(res, 503, "out of memory for this request");
  } catch (const std::exception& e) {
    answer(res, 500, e.what());
  }
}

// nodes=x:y:on,x:y:on,… (on is 0 or 1), as the mixer they describe.
LightMixer parseNodes(const std::string& text) {
  LightMixer mixer;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    std::array<double, 3> n{};
    std::stringstream fields(item);
    std::string f;
    int i = 0;
    while (std::getline(fields, f, ':')) {
      if (i == 3) break;
      n[i] = parseFiniteNumber(f, fmt::format("nodes item '{}'", item.substr(0, 40)));
      ++i;
    }
    if (i != 3 || (n[2] != 0 && n[2] != 1) || std::abs(n[0]) > 1e6 || std::abs(n[1]) > 1e6)
      throw BadRequest(fmt::format("nodes item '{}' is not x:y:on with |x|,|y| ≤ 1e6 and on 0 or 1",
                                   item.substr(0, 40)));
    mixer.nodes.push_back({n[0], n[1], n[2] == 1});
    if (mixer.nodes.size() > 64) throw BadRequest("nodes: more than 64 lights");
  }
  if (mixer.nodes.empty()) throw BadRequest("nodes is empty");
  return mixer;
}

}  // namespace

ViewServer::ViewServer(ViewSession& session)
    : session_(session), server_(std::make_unique<httplib::Server>()) {
  server_->set_payload_max_length(kMaxBody);
  // An idle keep-alive connection holds one of the worker threads: let it go soon.
  server_->set_keep_alive_timeout(2);
  server_->set_keep_alive_max_count(100);
  // The socket options hook is the one place httplib shows the listening socket: keep it, to
  // widen the accept queue after bind (below). SO_REUSEADDR as httplib's default sets it; not
  // SO_REUSEPORT, which would let another process listen on the same port.
  server_->set_socket_options([this](socket_t sock) {
    int yes = 1;
    ::setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof(yes));
    listen_socket_ = sock;
  });
  routes();
}

ViewServer::~ViewServer() = default;

int ViewServer::bind(const std::string& host, int port, const std::string& token,
                     const std::vector<std::string>& extra_hosts) {
  const int bound = port == 0 ? server_->bind_to_any_port(host) : server_->bind_to_port(host, port) ? port : -1;
  if (bound <= 0)
    throw Error(fmt::format("view: cannot listen on {}:{} (in use, or not an address of this "
                            "machine)", host, port));
  // Debian's libcpp-httplib is built with an accept queue of 5: a burst of connections beyond
  // it waits for TCP's SYN retries (1 s, 3 s, 7 s, …). Listening again only resizes the queue.
  if (listen_socket_ >= 0) ::listen(listen_socket_, SOMAXCONN);
  guard_ = std::make_unique<RequestGuard>(host, bound, token, extra_hosts);
  return bound;
}

bool ViewServer::refused(const httplib::Request& req, httplib::Response& res) const {
  if (!guard_) {
    answer(res, 503, "the server is not bound yet");
    return true;
  }
  RequestCredentials credentials;
  const auto header = [&](const char* key) -> std::optional<std::string> {
    const size_t n = req.get_header_value_count(key);
    if (n > 1) credentials.repeated.push_back(key);
    return n ? std::optional(req.get_header_value(key)) : std::nullopt;
  };
  credentials.host = header("Host");
  credentials.origin = header("Origin");
  credentials.cookie = header("Cookie");
  const size_t tokens = req.params.count(kTokenParameter);
  if (tokens > 1) credentials.repeated.push_back(kTokenParameter);
  if (tokens) credentials.token = req.params.find(kTokenParameter)->second;
  const GuardVerdict verdict = guard_->check(credentials);
  if (verdict.status) {
    answer(res, verdict.status, verdict.message);
    return true;
  }
  if (verdict.set_cookie && (req.path == "/" || req.path == "/index.html"))
    res.set_header("Set-Cookie", guard_->setCookieValue());
  return false;
}

void ViewServer::listen() { server_->listen_after_bind(); }
void ViewServer::stop() { server_->stop(); }

void ViewServer::answerRender(const httplib::Request& req, httplib::Response& res) {
  const QueryParams q(req.params, {"azimuth", "elevation", "zoom", "width", "height", "samples"});
  const auto& info = session_.sceneInfo();
  const OrbitView& v0 = session_.initialView();
  ViewRequest r;
  r.view.azimuth = q.number("azimuth", v0.azimuth, -3600, 3600);
  r.view.elevation = q.number("elevation", v0.elevation, -90, 90);
  r.view.zoom = q.number("zoom", 1.0, 0.01, 100);
  r.width = q.integer("width", info["width"], 1, ViewSession::kMaxSide);
  r.height = q.integer("height", info["height"], 1, ViewSession::kMaxSide);
  const std::int64_t planes = info["channels"].get<std::int64_t>() + info["t_channels"].get<std::int64_t>();
  if (std::int64_t{r.width} * r.height * planes > ViewSession::kMaxFrameValues)
    throw BadRequest(fmt::format(
        "a {}×{} frame of {} planes holds {} values, over the viewer's limit of {}; ask for at "
        "most {} pixels",
        r.width, r.height, planes, std::int64_t{r.width} * r.height * planes,
        ViewSession::kMaxFrameValues, ViewSession::kMaxFrameValues / planes));
  if (q.has("samples")) {
    const std::string samples = q.text("samples", "", 8);
    if (samples != "half" && samples != "float")
      throw BadRequest(fmt::format("parameter samples='{}' is not half or float", samples));
    r.samples = samples == "half" ? SampleStorage::kHalf : SampleStorage::kFloat;
  }
  const auto frame = session_.render(r);
  if (!frame) {
    answer(res, 409, "superseded by a newer view request");
    return;
  }
  const nlohmann::json header = {
      {"width", frame->image.width()}, {"height", frame->image.height()},
      {"channels", frame->image.channels()},
      {"t_channels", frame->image.transmittanceChannels()},
      {"render_ms", frame->render_ms}, {"sequence", frame->sequence},
      {"azimuth", r.view.azimuth}, {"elevation", r.view.elevation}, {"zoom", r.view.zoom}};
  res.set_header("Cache-Control", "no-store");
  res.set_content(encodeFrame(frame->image, header), "application/octet-stream");
}

void ViewServer::answerSaveMix(const httplib::Request& req, httplib::Response& res) {
  // A form-encoded body would be read as query parameters: JSON only.
  if (req.get_header_value("Content-Type").rfind("application/json", 0) != 0) {
    answer(res, 415, fmt::format("the body must be application/json, not '{}'",
                                 req.get_header_value("Content-Type").substr(0, 60)));
    return;
  }
  const QueryParams q(req.params, {"name"});
  if (session_.readOnly()) {
    answer(res, 403, "the server was started with --read-only: mixes are not saved");
    return;
  }
  if (!q.has("name")) throw BadRequest("parameter 'name' is missing");
  // Ordered: the mix is written in the order the page lists its lights.
  const auto body = nlohmann::ordered_json::parse(req.body, nullptr, false);
  if (body.is_discarded() || !body.is_object() || !body.contains("weights") ||
      !body["weights"].is_object())
    throw BadRequest("the body must be JSON {\"weights\": {\"LIGHT\": WEIGHT, …}}");
  std::vector<std::pair<std::string, double>> weights;
  for (const auto& [light, w] : body["weights"].items()) {
    if (!w.is_number())
      throw BadRequest(fmt::format("weight of light '{}' is not a number", light.substr(0, 64)));
    weights.emplace_back(light, w.get<double>());
  }
  const std::string name = q.text("name", "", 64);
  session_.saveMix(name, weights);
  answerJson(res, {{"saved", name}, {"file", session_.options().scene}});
}

void ViewServer::routes() {
  httplib::Server& s = *server_;
  s.set_pre_routing_handler([this](const httplib::Request& req, httplib::Response& res) {
    return refused(req, res) ? httplib::Server::HandlerResponse::Handled
                             : httplib::Server::HandlerResponse::Unhandled;
  });
  s.Get("/api/scene", [this](const httplib::Request& req, httplib::Response& res) {
    guarded(res, 500, [&] {
      QueryParams(req.params, {});
      answerJson(res, session_.sceneInfo());
    });
  });
  s.Get("/api/light", [this](const httplib::Request& req, httplib::Response& res) {
    guarded(res, 404, [&] {
      const QueryParams q(req.params, {"name"});
      if (!q.has("name")) throw BadRequest("parameter 'name' is missing");
      answerJson(res, session_.libraryLight(q.text("name", "", 128)));
    });
  });
  s.Get("/api/mixer-weights", [this](const httplib::Request& req, httplib::Response& res) {
    guarded(res, 400, [&] {
      const QueryParams q(req.params, {"x", "y", "nodes"});
      const LightMixer mixer =
          q.has("nodes") ? parseNodes(q.text("nodes", "", 4096))
                         : LightMixer::regularPolygon(static_cast<int>(session_.sceneInfo()["lights"].size()));
      answerJson(res, {{"weights", mixer.weights(q.number("x", 0, -1e6, 1e6), q.number("y", 0, -1e6, 1e6))}});
    });
  });
  s.Get("/api/render", [this](const httplib::Request& req, httplib::Response& res) {
    guarded(res, 500, [&] { answerRender(req, res); });
  });
  s.Post("/api/mixes", [this](const httplib::Request& req, httplib::Response& res) {
    guarded(res, 400, [&] { answerSaveMix(req, res); });
  });
  // The page's files; anything else is 404 (nothing is served from the file system, so no
  // path can reach outside the page).
  s.Get(R"(/([A-Za-z0-9_.-]*))", [](const httplib::Request& req, httplib::Response& res) {
    std::string path = req.matches[1];
    if (path.empty()) path = "index.html";
    const WebAsset* asset = findWebAsset(path);
    if (!asset) return answer(res, 404, fmt::format("no such path '/{}'", path));
    guarded(res, 400, [&] {
      // The page takes ?relight=webgl2|js|auto (harness/view/web/relighter.js); its files take nothing.
      const QueryParams q(req.params, path == "index.html" ? std::initializer_list<const char*>{"relight"}
                                                           : std::initializer_list<const char*>{});
      const std::string relight = q.text("relight", "auto", 16);
      if (relight != "auto" && relight != "webgl2" && relight != "js")
        throw BadRequest(fmt::format("parameter relight='{}' is not auto, webgl2 or js", relight));
      res.set_content(std::string(asset->bytes), std::string(asset->content_type).c_str());
    });
  });
  s.set_error_handler([](const httplib::Request& req, httplib::Response& res) {
    if (!res.body.empty()) return;  // a handler's own answer
    std::string path = req.path.substr(0, 80), method = req.method.substr(0, 16);
    for (std::string* t : {&path, &method})
      for (char& c : *t)
        if (c < 0x20 || c >= 0x7f) c = '?';
    if (method.empty())  // the request line itself was refused (414: URI too long, …)
      return answer(res, res.status, fmt::format("request refused (HTTP {})", res.status));
    if (method != "GET" && method != "POST")
      return answer(res, 405, fmt::format("method {} is not served ({} {})", method, method, path));
    answer(res, res.status, res.status == 404 ? fmt::format("no such path '{}'", path)
                                              : fmt::format("{} {}: refused (HTTP {})", method, path, res.status));
  });
}

}  // namespace svr
