// `svr view SCENE`: the scene served to a browser for interactive relighting and orbiting
// (harness/view/, docs/viewer.md).

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <csignal>
#include <cstdio>
#include <memory>
#include <regex>
#include <thread>
#include <unistd.h>

#include "harness/command.h"
#include "renderers/volume/memory_budget.h"
#include "renderers/registry.h"
#include "base/error.h"

#ifdef SVR_HAVE_VIEWER
#include "harness/view/request_guard.h"
#include "harness/view/view_server.h"
#include "harness/view/view_session.h"
#endif

namespace svr {

namespace {

struct ViewCommandOptions {
  std::string scene, host = "127.0.0.1", renderer = "shearwarp", model;
  std::vector<std::string> options;
  int port = 8765;
  std::string memory_budget, token;
  std::vector<std::string> allow_hosts;
  bool read_only = false, quiet = false, no_token = false;
};

#ifdef SVR_HAVE_VIEWER
// Ctrl-C or SIGTERM while serving: the handler only writes a byte to a pipe (all a signal
// handler may safely do); a thread waiting on it stops the server, and the command returns 0.
// Before serving, while the scene loads, the signals keep their usual effect.
int g_stop_pipe[2] = {-1, -1};
extern "C" void onStopSignal(int) {
  const char byte = 1;
  [[maybe_unused]] const auto n = ::write(g_stop_pipe[1], &byte, 1);
}

// The access token (docs/viewer.md "Who may ask"): --token's, none with --no-token, a fresh
// random one off loopback, none on loopback (where Host and Origin keep other sites out).
std::string accessToken(const ViewCommandOptions& o) {
  if (!o.token.empty()) {
    static const std::regex kToken("[A-Za-z0-9_-]{8,128}");
    if (!std::regex_match(o.token, kToken))
      throw Error("view: --token must be 8–128 letters, digits, '_' or '-'");
    return o.token;
  }
  if (o.no_token) return "";
  return isLoopbackHost(o.host) ? "" : makeAccessToken();
}

// The URL to open: on a wildcard bind, this machine's loopback one.
std::string serverUrl(const ViewCommandOptions& o, int port, const std::string& token) {
  const std::string address = isWildcardHost(o.host) ? "127.0.0.1" : o.host;
  const std::string host = address.find(':') != std::string::npos ? "[" + address + "]" : address;
  return fmt::format("http://{}:{}/{}", host, port, token.empty() ? "" : "?token=" + token);
}

int runView(const ViewCommandOptions& o, const std::string& data_dir) {
  if (o.port < 0 || o.port > 65535)
    throw Error(fmt::format("view: --port {} is outside 0..65535", o.port));
  if (o.no_token && !o.token.empty()) throw Error("view: --token and --no-token exclude each other");
  const std::string token = accessToken(o);
  ViewOptions vo{o.scene, o.renderer, o.model, data_dir, o.options, o.read_only};
  if (!o.memory_budget.empty()) vo.memory_budget = parseByteSize(o.memory_budget, "--memory-budget");
  ViewSession session(vo);
  ViewServer server(session);
  const int port = server.bind(o.host, o.port, token, o.allow_hosts);
  if (::pipe(g_stop_pipe) != 0) throw Error("view: cannot create the stop pipe");
  std::thread stopper([&server] {
    char byte = 0;
    while (::read(g_stop_pipe[0], &byte, 1) < 0 && errno == EINTR) {}
    server.stop();
  });
  std::signal(SIGINT, onStopSignal);
  std::signal(SIGTERM, onStopSignal);
  const auto& info = session.sceneInfo();
  fmt::print("svr view: {} with {} ({}) at {}  (Ctrl-C stops)\n", o.scene,
             info["renderer"].get<std::string>(), info["model"]["name"].get<std::string>(),
             serverUrl(o, port, token));
  std::fflush(stdout);
  if (o.no_token && !isLoopbackHost(o.host))
    fmt::print(stderr, "svr view: WARNING: --no-token on {}: anyone who can reach port {} can read "
                       "this scene and{} write its file\n",
               o.host, port, o.read_only ? " (not with --read-only)" : "");
  else if (o.no_token)
    fmt::print(stderr, "svr view: --no-token: no token asked for (loopback: Host and Origin are "
                       "still checked)\n");
  server.listen();
  onStopSignal(0);  // listen() also returns when the socket fails: let the stopper end
  stopper.join();
  if (!o.quiet) fmt::print("svr view: stopped\n");
  return 0;
}
#endif

}  // namespace

namespace commands {

CommandEntry view() {
  return {"view", "serve a scene to a browser: relight with the light dial, orbit and zoom",
          [](CLI::App& sub, CommandContext& context) {
            auto o = std::make_shared<ViewCommandOptions>();
            sub.add_option("SCENE", o->scene, "scene JSON (see docs/scenes.md)")->required();
            sub.add_option("--port", o->port, "TCP port (0: any free one)")->capture_default_str();
            sub.add_option("--host", o->host,
                           "address to listen on (loopback unless you say otherwise)")
                ->capture_default_str();
            sub.add_option("--renderer", o->renderer,
                           fmt::format("backend: {}", fmt::join(rendererNames(), ", ")))
                ->capture_default_str();
            sub.add_option("--model", o->model,
                           "colour model: rgb, factor:k, spectral:n or auto (default: the scene's)");
            sub.add_option("--option", o->options, "backend option BACKEND.KEY=VALUE (repeatable)");
            sub.add_option("--memory-budget", o->memory_budget,
                           "most bytes of voxels and of one frame's images, e.g. 512M (default: "
                           "the memory available now)");
            sub.add_flag("--read-only", o->read_only, "never write the scene file (no saved mixes)");
            sub.add_option("--token", o->token,
                           "access token every request must carry (default: a random one when "
                           "--host is not loopback, none on loopback)");
            sub.add_flag("--no-token", o->no_token,
                         "serve without a token even off loopback (anyone who reaches the port "
                         "may read the scene and save mixes)");
            sub.add_option("--allow-host", o->allow_hosts,
                           "a further name the server answers to in the Host header, e.g. behind "
                           "a proxy (repeatable)");
            sub.add_flag("-q,--quiet", o->quiet, "say nothing but the URL");
            addCacheFlag(sub);
            sub.callback([o, &context] {
#ifdef SVR_HAVE_VIEWER
              context.status = runView(*o, context.data_dir);
#else
              throw Error("view: this svr was built without cpp-httplib (install "
                          "libcpp-httplib-dev, then configure and build again)");
#endif
            });
          }};
}

}  // namespace commands

}  // namespace svr
