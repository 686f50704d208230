#pragma once
// The HTTP face of a ViewSession (cpp-httplib): the page's files, and a small JSON + binary API
// (docs/viewer.md). Every bad request is answered 4xx with {"error": message naming the
// parameter and value}; a render that fails is answered 500 with its reason; the server keeps
// serving either way. Before any of that, RequestGuard decides who may ask (Host, Origin, token).

#include <memory>
#include <string>
#include <vector>

#include "harness/view/request_guard.h"
#include "harness/view/view_session.h"

namespace httplib {
class Server;
struct Request;
struct Response;
}

namespace svr {

class ViewServer {
 public:
  explicit ViewServer(ViewSession& session);
  ~ViewServer();

  // Binds host:port (port 0: any free one) and returns the port; svr::Error when it cannot.
  // From then on only requests that name this server (and carry `token`, when it is not
  // empty) are answered; `extra_hosts` are further names it answers to.
  int bind(const std::string& host, int port, const std::string& token = "",
           const std::vector<std::string>& extra_hosts = {});
  // Serves until stop() (from another thread).
  void listen();
  void stop();

 private:
  void routes();
  // Refuses what the guard refuses, before routing (no body is read).
  bool refused(const httplib::Request& req, httplib::Response& res) const;
  void answerRender(const httplib::Request& req, httplib::Response& res);
  void answerSaveMix(const httplib::Request& req, httplib::Response& res);
  ViewSession& session_;
  std::unique_ptr<httplib::Server> server_;
  int listen_socket_ = -1;
  std::unique_ptr<RequestGuard> guard_;  // set by bind; until then every request is refused
};

}  // namespace svr
