#include "harness/view/view_params.h"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>

namespace svr {

namespace {

// Values are echoed in messages: long or binary ones are cut and escaped.
std::string shown(const std::string& value) {
  std::string out;
  for (char c : value.substr(0, 40))
    out += (c >= 0x20 && c < 0x7f) ? std::string(1, c) : fmt::format("\\x{:02x}", static_cast<unsigned char>(c));
  return value.size() > 40 ? out + "…" : out;
}

}  // namespace

QueryParams::QueryParams(const std::multimap<std::string, std::string>& params,
                         std::initializer_list<const char*> known) {
  for (const auto& [key, value] : params) {
    if (key == kTokenParameter) continue;  // every path's: RequestGuard has checked it
    if (std::find_if(known.begin(), known.end(), [&](const char* k) { return key == k; }) ==
        known.end()) {
      std::string list;
      for (const char* k : known) list += (list.empty() ? "" : ", ") + std::string(k);
      throw BadRequest(fmt::format("unknown parameter '{}'{}", shown(key),
                                   list.empty() ? " (this path takes none)"
                                                : fmt::format("; expected {}", list)));
    }
    if (!values_.emplace(key, value).second)
      throw BadRequest(fmt::format("parameter '{}' is given more than once", key));
  }
}

std::string QueryParams::text(const std::string& key, const std::string& fallback,
                              size_t max_length) const {
  const auto it = values_.find(key);
  if (it == values_.end()) return fallback;
  if (it->second.empty() || it->second.size() > max_length)
    throw BadRequest(fmt::format("parameter {}='{}' must be 1–{} characters", key,
                                 shown(it->second), max_length));
  for (const unsigned char c : it->second)
    if (c < 0x20 || c == 0x7f)
      throw BadRequest(fmt::format("parameter {}='{}' holds control characters", key, shown(it->second)));
  return it->second;
}

double parseFiniteNumber(const std::string& text, const std::string& what) {
  double v = 0;
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, v);
  if (text.empty() || ec != std::errc() || ptr != end || !std::isfinite(v))
    throw BadRequest(fmt::format("{}='{}' is not a finite number", what, shown(text)));
  return v;
}

double QueryParams::number(const std::string& key, double fallback, double lo, double hi) const {
  const auto it = values_.find(key);
  if (it == values_.end()) return fallback;
  const double v = parseFiniteNumber(it->second, "parameter " + key);
  if (v < lo || v > hi)
    throw BadRequest(fmt::format("parameter {}={} is outside {}..{}", key, shown(it->second), lo, hi));
  return v;
}

int QueryParams::integer(const std::string& key, int fallback, int lo, int hi) const {
  const auto it = values_.find(key);
  if (it == values_.end()) return fallback;
  int v = 0;
  const char* end = it->second.data() + it->second.size();
  const auto [ptr, ec] = std::from_chars(it->second.data(), end, v);
  if (it->second.empty() || ec != std::errc() || ptr != end)
    throw BadRequest(fmt::format("parameter {}='{}' is not a whole number in {}..{}", key,
                                 shown(it->second), lo, hi));
  if (v < lo || v > hi)
    throw BadRequest(fmt::format("parameter {}={} is outside {}..{}", key, v, lo, hi));
  return v;
}

}  // namespace svr
