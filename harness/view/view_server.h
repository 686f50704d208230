#pragma once
// The HTTP face of a ViewSession (cpp-httplib): the page's files, and a small JSON + binary API
// (docs/viewer.md). Every bad request is answered 4xx with {"error": message naming the
// parameter and value}; a render that fails is answered 500 with its reason; the server keeps
// serving either way.

#include <memory>
#include <string>

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
  int bind(const std::string& host, int port);
  // Serves until stop() (from another thread).
  void listen();
  void stop();

 private:
  void routes();
  void answerRender(const httplib::Request& req, httplib::Response& res);
  void answerSaveMix(const httplib::Request& req, httplib::Response& res);
  ViewSession& session_;
  std::unique_ptr<httplib::Server> server_;
  int listen_socket_ = -1;
};

}  // namespace svr
