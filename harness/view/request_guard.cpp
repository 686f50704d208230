#include "harness/view/request_guard.h"

#include <fmt/format.h>
#include <openssl/crypto.h>
#include <openssl/rand.h>

#include <arpa/inet.h>
#include <ifaddrs.h>
#include <netinet/in.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>

#include "base/error.h"

namespace svr {

namespace {

std::string lowered(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

// Header values are echoed in refusals: cut, and anything unprintable shown as '?'.
std::string shown(const std::string& value) {
  std::string out = value.substr(0, 80);
  for (char& c : out)
    if (c < 0x20 || c >= 0x7f) c = '?';
  return value.size() > 80 ? out + "…" : out;
}

// An address as it is written in a Host header: IPv6 in brackets.
std::string hostForm(const std::string& address) {
  return address.find(':') != std::string::npos && address.front() != '[' ? "[" + address + "]"
                                                                           : address;
}

// Every address of this machine's interfaces, and its host name: what a client that reached a
// wildcard bind may have typed. Link-local IPv6 addresses need a zone in a URL and are left out.
std::vector<std::string> machineNames() {
  std::vector<std::string> names;
  ifaddrs* list = nullptr;
  if (::getifaddrs(&list) == 0) {
    for (const ifaddrs* a = list; a; a = a->ifa_next) {
      if (!a->ifa_addr) continue;
      char text[INET6_ADDRSTRLEN] = {};
      if (a->ifa_addr->sa_family == AF_INET) {
        ::inet_ntop(AF_INET, &reinterpret_cast<const sockaddr_in*>(a->ifa_addr)->sin_addr, text, sizeof(text));
      } else if (a->ifa_addr->sa_family == AF_INET6) {
        const auto* in6 = reinterpret_cast<const sockaddr_in6*>(a->ifa_addr);
        if (IN6_IS_ADDR_LINKLOCAL(&in6->sin6_addr)) continue;
        ::inet_ntop(AF_INET6, &in6->sin6_addr, text, sizeof(text));
      } else {
        continue;
      }
      names.push_back(text);
    }
    ::freeifaddrs(list);
  }
  char host[256] = {};
  if (::gethostname(host, sizeof(host) - 1) == 0 && host[0]) names.push_back(host);
  return names;
}

}  // namespace

bool isLoopbackHost(const std::string& host) {
  const std::string h = lowered(host);
  if (h == "localhost" || h == "::1" || h == "[::1]") return true;
  in_addr v4{};
  return ::inet_pton(AF_INET, h.c_str(), &v4) == 1 && (ntohl(v4.s_addr) >> 24) == 127;
}

bool isWildcardHost(const std::string& host) {
  return host.empty() || host == "0.0.0.0" || host == "::" || host == "[::]";
}

std::string makeAccessToken() {
  unsigned char bytes[16];
  if (RAND_bytes(bytes, sizeof(bytes)) != 1)
    throw Error("view: the system's random source gave no bytes for an access token");
  std::string token;
  for (unsigned char b : bytes) token += fmt::format("{:02x}", b);
  return token;
}

RequestGuard::RequestGuard(const std::string& bound_host, int port, std::string token,
                           const std::vector<std::string>& extra_hosts)
    : port_(port), token_(std::move(token)) {
  std::vector<std::string> names = extra_hosts;
  names.push_back(bound_host);
  if (isLoopbackHost(bound_host) || isWildcardHost(bound_host))
    names.insert(names.end(), {"localhost", "127.0.0.1", "::1"});
  if (isWildcardHost(bound_host)) {
    const auto machine = machineNames();
    names.insert(names.end(), machine.begin(), machine.end());
  }
  for (const std::string& name : names) {
    if (isWildcardHost(name)) continue;
    const std::string host = lowered(hostForm(name));
    for (const std::string& h : {host + ":" + std::to_string(port), host}) {
      // A browser leaves out the port only when it is the scheme's default.
      if (h == host && port != 80) continue;
      if (std::find(allowed_.begin(), allowed_.end(), h) == allowed_.end()) allowed_.push_back(h);
    }
  }
}

bool RequestGuard::hostAllowed(const std::string& host) const {
  return std::find(allowed_.begin(), allowed_.end(), lowered(host)) != allowed_.end();
}

bool RequestGuard::tokenMatches(const std::string& candidate) const {
  return candidate.size() == token_.size() &&
         CRYPTO_memcmp(candidate.data(), token_.data(), token_.size()) == 0;
}

std::string RequestGuard::cookieName() const { return fmt::format("svr-token-{}", port_); }

std::string RequestGuard::setCookieValue() const {
  return fmt::format("{}={}; Path=/; HttpOnly; SameSite=Strict", cookieName(), token_);
}

GuardVerdict RequestGuard::check(const RequestCredentials& r) const {
  if (!r.repeated.empty())
    return {400, fmt::format("'{}' is given more than once", shown(r.repeated.front()))};
  if (!r.host)
    return {400, "the request has no Host header: svr view answers only requests addressed to it"};
  if (!hostAllowed(*r.host))
    return {403, fmt::format("Host '{}' is not this server (it answers to {}): a page of another "
                             "site whose name resolves to this machine is refused",
                             shown(*r.host), allowed_.front())};
  if (r.origin) {
    const std::string origin = lowered(*r.origin);
    const std::string scheme = "http://";
    if (origin.rfind(scheme, 0) != 0 || !hostAllowed(origin.substr(scheme.size())))
      return {403, fmt::format("Origin '{}' is not this server's page: requests from other sites "
                               "are refused", shown(*r.origin))};
  }
  if (token_.empty()) return {};
  if (r.token && tokenMatches(*r.token)) return {0, "", true};
  if (r.cookie) {
    // Cookie: a=b; c=d — the one named for this port.
    const std::string& c = *r.cookie;
    const std::string key = cookieName() + "=";
    for (size_t at = 0; at < c.size();) {
      while (at < c.size() && (c[at] == ' ' || c[at] == ';')) ++at;
      const size_t end = std::min(c.find(';', at), c.size());
      if (c.compare(at, key.size(), key) == 0 && tokenMatches(c.substr(at + key.size(), end - at - key.size())))
        return {};
      at = end;
    }
  }
  return {403, r.token ? "the token is wrong: open the URL svr view printed (it ends in ?token=…)"
                       : "this server needs its token: open the URL svr view printed (it ends in "
                         "?token=…), or send ?token=… or the cookie"};
}

}  // namespace svr
