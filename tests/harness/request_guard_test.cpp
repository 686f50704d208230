// Who may ask svr view (issue 41): Host, Origin and token, decided before any work.

#include "harness/view/request_guard.h"

#include <gtest/gtest.h>

#include <set>

namespace svr {
namespace {

RequestCredentials from(const char* host, const char* origin = nullptr, const char* cookie = nullptr,
                        const char* token = nullptr) {
  RequestCredentials r;
  if (host) r.host = host;
  if (origin) r.origin = origin;
  if (cookie) r.cookie = cookie;
  if (token) r.token = token;
  return r;
}

TEST(RequestGuard, LoopbackAnswersItsOwnNamesWithThePortAndNothingElse) {
  const RequestGuard guard("127.0.0.1", 8765, "");
  for (const char* host : {"127.0.0.1:8765", "localhost:8765", "LocalHost:8765", "[::1]:8765"})
    EXPECT_EQ(guard.check(from(host)).status, 0) << host;
  for (const char* host : {"attacker.example:8765", "127.0.0.1:8766", "127.0.0.1", "localhost",
                           "127.0.0.2:8765", "", "localhost.attacker.example:8765", "127.0.0.1:8765 "}) {
    const GuardVerdict v = guard.check(from(host));
    EXPECT_EQ(v.status, 403) << host;
    EXPECT_NE(v.message.find("is not this server"), std::string::npos) << v.message;
  }
  const GuardVerdict none = guard.check(from(nullptr));
  EXPECT_EQ(none.status, 400);
  EXPECT_NE(none.message.find("no Host header"), std::string::npos);
}

TEST(RequestGuard, ThePortMayBeLeftOutOnlyOnPort80) {
  const RequestGuard guard("127.0.0.1", 80, "");
  EXPECT_EQ(guard.check(from("localhost")).status, 0);
  EXPECT_EQ(guard.check(from("localhost:80")).status, 0);
}

TEST(RequestGuard, AnOriginMustBeThisServersOwn) {
  const RequestGuard guard("127.0.0.1", 8765, "");
  for (const char* origin : {"http://127.0.0.1:8765", "http://localhost:8765", "HTTP://LOCALHOST:8765"})
    EXPECT_EQ(guard.check(from("127.0.0.1:8765", origin)).status, 0) << origin;
  for (const char* origin : {"http://attacker.example", "http://attacker.example:8765", "null",
                             "https://127.0.0.1:8765", "http://127.0.0.1:8766", "file://", ""}) {
    const GuardVerdict v = guard.check(from("127.0.0.1:8765", origin));
    EXPECT_EQ(v.status, 403) << origin;
    EXPECT_NE(v.message.find("Origin '"), std::string::npos) << v.message;
  }
}

TEST(RequestGuard, ATokenComesInTheQueryOrInThisPortsCookie) {
  const std::string token = makeAccessToken();
  const RequestGuard guard("192.0.2.7", 9000, token);
  EXPECT_EQ(guard.cookieName(), "svr-token-9000");
  EXPECT_EQ(guard.setCookieValue(), "svr-token-9000=" + token + "; Path=/; HttpOnly; SameSite=Strict");
  const GuardVerdict query = guard.check(from("192.0.2.7:9000", nullptr, nullptr, token.c_str()));
  EXPECT_EQ(query.status, 0);
  EXPECT_TRUE(query.set_cookie);
  const std::string cookie = "theme=dark; svr-token-9000=" + token + "; other=1";
  const GuardVerdict by_cookie = guard.check(from("192.0.2.7:9000", nullptr, cookie.c_str()));
  EXPECT_EQ(by_cookie.status, 0);
  EXPECT_FALSE(by_cookie.set_cookie);
  const std::string other_port = "svr-token-9001=" + token;
  const std::string wrong = token.substr(0, 31) + (token[31] == '0' ? "1" : "0");
  const std::string prefix = "svr-token-9000=" + token.substr(0, 16);
  for (const RequestCredentials& r :
       {from("192.0.2.7:9000"), from("192.0.2.7:9000", nullptr, other_port.c_str()),
        from("192.0.2.7:9000", nullptr, nullptr, wrong.c_str()),
        from("192.0.2.7:9000", nullptr, prefix.c_str()), from("192.0.2.7:9000", nullptr, nullptr, "")}) {
    const GuardVerdict v = guard.check(r);
    EXPECT_EQ(v.status, 403);
    EXPECT_NE(v.message.find("token"), std::string::npos) << v.message;
  }
  // The token does not excuse a foreign Host or Origin.
  EXPECT_EQ(guard.check(from("attacker.example:9000", nullptr, nullptr, token.c_str())).status, 403);
  EXPECT_EQ(guard.check(from("192.0.2.7:9000", "http://attacker.example", nullptr, token.c_str())).status, 403);
}

TEST(RequestGuard, RepeatedHeadersAreRefused) {
  const RequestGuard guard("127.0.0.1", 8765, "");
  RequestCredentials r = from("127.0.0.1:8765");
  r.repeated = {"Host"};
  const GuardVerdict v = guard.check(r);
  EXPECT_EQ(v.status, 400);
  EXPECT_EQ(v.message, "'Host' is given more than once");
}

TEST(RequestGuard, AWildcardBindAnswersThisMachinesNamesAndAllowedOnes) {
  const RequestGuard guard("0.0.0.0", 8765, "t0k3n-long-enough", {"viewer.lab.example"});
  const auto& allowed = guard.allowedHosts();
  const std::set<std::string> names(allowed.begin(), allowed.end());
  for (const char* host : {"127.0.0.1:8765", "localhost:8765", "viewer.lab.example:8765"})
    EXPECT_TRUE(names.count(host)) << host;
  EXPECT_FALSE(names.count("0.0.0.0:8765"));
  EXPECT_EQ(guard.check(from("attacker.example:8765", nullptr, nullptr, "t0k3n-long-enough")).status, 403);
}

TEST(RequestGuard, LoopbackAndWildcardAddressesAreRecognised) {
  for (const char* h : {"127.0.0.1", "127.1.2.3", "::1", "[::1]", "localhost", "LOCALHOST"})
    EXPECT_TRUE(isLoopbackHost(h)) << h;
  for (const char* h : {"0.0.0.0", "192.168.1.2", "128.0.0.1", "::", "example.com", ""})
    EXPECT_FALSE(isLoopbackHost(h)) << h;
  for (const char* h : {"0.0.0.0", "::", ""}) EXPECT_TRUE(isWildcardHost(h)) << h;
  EXPECT_FALSE(isWildcardHost("127.0.0.1"));
}

TEST(RequestGuard, TokensAreFreshHex) {
  const std::string a = makeAccessToken(), b = makeAccessToken();
  EXPECT_EQ(a.size(), 32u);
  EXPECT_EQ(a.find_first_not_of("0123456789abcdef"), std::string::npos);
  EXPECT_NE(a, b);
}

}  // namespace
}  // namespace svr
