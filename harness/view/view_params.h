#pragma once
// The query parameters of one viewer request, checked as strictly as scene keys are: every
// key must be one the endpoint knows and appear once, and numbers must parse whole, be finite
// and lie in range. Failures are BadRequest, which the server answers 400 with the message.

#include <map>
#include <stdexcept>
#include <string>

namespace svr {

struct BadRequest : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The access token, which any path takes (harness/view/request_guard.h checks it before routing).
inline constexpr const char* kTokenParameter = "token";

class QueryParams {
 public:
  // `known`: the keys this endpoint takes; any other key, or a repeated one, is a BadRequest.
  QueryParams(const std::multimap<std::string, std::string>& params,
              std::initializer_list<const char*> known);

  bool has(const std::string& key) const { return values_.count(key) != 0; }
  std::string text(const std::string& key, const std::string& fallback, size_t max_length) const;
  double number(const std::string& key, double fallback, double lo, double hi) const;
  int integer(const std::string& key, int fallback, int lo, int hi) const;

 private:
  std::map<std::string, std::string> values_;
};

// A decimal number, whole string, finite; BadRequest naming `what` otherwise.
double parseFiniteNumber(const std::string& text, const std::string& what);

}  // namespace svr
