#pragma once
// Who may ask `svr view` anything (issue 41, docs/viewer.md "Who may ask"). A server on the
// user's machine treats every request as hostile until its Host, Origin and token say otherwise:
//
// - Host must name this server (its bound address, and for loopback also localhost, 127.0.0.1
//   and [::1], each with the port; for a wildcard bind every address of this machine and its
//   host name). A page of another site whose name was made to resolve to 127.0.0.1 (DNS
//   rebinding) sends its own name as Host and is refused.
// - Origin, when a request carries one, must be this server's own. Browsers send it on every
//   cross-site POST and every CORS fetch, so another site's page can neither write the scene
//   file nor start renders; no CORS header is ever sent.
// - A token, when the server has one (by default off loopback, as Jupyter does): in the query
//   (`?token=…`) or in the cookie the page gets when it is opened with it.
//
// The checks run before routing, so a refused request costs no work and reads no body.

#include <optional>
#include <string>
#include <vector>

namespace svr {

// What the guard reads of a request: each header as sent (empty optional: absent; a header
// sent twice counts as `repeated`).
struct RequestCredentials {
  std::optional<std::string> host, origin, cookie, token;  // token: the `token` query value
  std::vector<std::string> repeated;                       // headers or parameters sent twice
};

struct GuardVerdict {
  int status = 0;            // 0: allowed; else the 4xx to answer
  std::string message;       // why, naming the value
  bool set_cookie = false;   // allowed by a query token: hand the page the cookie
};

class RequestGuard {
 public:
  // `bound_host`: the address the server listens on (as --host gives it); `token`: empty for
  // none. `extra_hosts`: further names the server answers to (--allow-host).
  RequestGuard(const std::string& bound_host, int port, std::string token,
               const std::vector<std::string>& extra_hosts = {});

  GuardVerdict check(const RequestCredentials& request) const;

  // The cookie's name carries the port: two viewers on one machine do not share one.
  std::string cookieName() const;
  // The Set-Cookie value for an allowed query token.
  std::string setCookieValue() const;
  // Host values that count as this server (lower case, with the port), for messages and tests.
  const std::vector<std::string>& allowedHosts() const { return allowed_; }

 private:
  bool hostAllowed(const std::string& host) const;
  bool tokenMatches(const std::string& candidate) const;

  int port_;
  std::string token_;
  std::vector<std::string> allowed_;
};

// True for 127.0.0.0/8, ::1 and "localhost".
bool isLoopbackHost(const std::string& host);
// True for 0.0.0.0, :: and the empty address (every interface).
bool isWildcardHost(const std::string& host);
// A fresh random token (32 hex digits of 128 random bits, OpenSSL's RAND_bytes).
std::string makeAccessToken();

}  // namespace svr
