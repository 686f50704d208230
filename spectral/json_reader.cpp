#include "spectral/json_reader.h"

#include <fmt/format.h>

#include <cmath>
#include <fstream>

#include "spectral/error.h"

namespace svr {

JsonReader::JsonReader(const nlohmann::json& value, std::string file, std::string path)
    : value_(value), file_(std::move(file)), path_(std::move(path)) {}

nlohmann::json JsonReader::parseFile(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw Error(fmt::format("{}: cannot open", path));
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw Error(fmt::format("{}: invalid JSON: {}", path, e.what()));
  }
}

std::string JsonReader::where() const {
  return path_.empty() ? file_ : fmt::format("{}: {}", file_, path_);
}

void JsonReader::fail(const std::string& what) const {
  throw Error(fmt::format("{}: {}", where(), what));
}

std::string JsonReader::childPath(const std::string& key) const {
  return path_.empty() ? key : path_ + "." + key;
}

bool JsonReader::contains(const std::string& key) const {
  return value_.is_object() && value_.contains(key);
}

JsonReader JsonReader::at(const std::string& key) const {
  if (!value_.is_object()) fail(fmt::format("expected an object, got {}", value_.dump()));
  used_.insert(key);
  if (!value_.contains(key)) fail(fmt::format("missing key '{}'", key));
  return {value_.at(key), file_, childPath(key)};
}

std::optional<JsonReader> JsonReader::find(const std::string& key) const {
  if (!value_.is_object()) fail(fmt::format("expected an object, got {}", value_.dump()));
  used_.insert(key);
  if (!value_.contains(key) || value_.at(key).is_null()) return std::nullopt;
  return JsonReader(value_.at(key), file_, childPath(key));
}

JsonReader JsonReader::at(std::size_t index) const {
  if (!value_.is_array()) fail(fmt::format("expected an array, got {}", value_.dump()));
  if (index >= value_.size()) fail(fmt::format("index {} is past the end", index));
  return {value_.at(index), file_, fmt::format("{}[{}]", path_, index)};
}

std::size_t JsonReader::size() const {
  if (!value_.is_array() && !value_.is_object())
    fail(fmt::format("expected an array or object, got {}", value_.dump()));
  return value_.size();
}

std::vector<std::string> JsonReader::keys() const {
  if (!value_.is_object()) fail(fmt::format("expected an object, got {}", value_.dump()));
  std::vector<std::string> out;
  for (auto it = value_.begin(); it != value_.end(); ++it) {
    out.push_back(it.key());
    used_.insert(it.key());
  }
  return out;
}

double JsonReader::number(double lo, double hi) const {
  if (!value_.is_number()) fail(fmt::format("expected a number, got {}", value_.dump()));
  const double v = value_.get<double>();
  if (!std::isfinite(v) || v < lo || v > hi)
    fail(fmt::format("value {} is outside {}..{}", v, lo, hi));
  return v;
}

int JsonReader::integer(int lo, int hi) const {
  if (!value_.is_number_integer()) fail(fmt::format("expected an integer, got {}", value_.dump()));
  const auto v = value_.get<long long>();
  if (v < lo || v > hi) fail(fmt::format("value {} is outside {}..{}", v, lo, hi));
  return static_cast<int>(v);
}

bool JsonReader::boolean() const {
  if (!value_.is_boolean()) fail(fmt::format("expected true or false, got {}", value_.dump()));
  return value_.get<bool>();
}

std::string JsonReader::string() const {
  if (!value_.is_string()) fail(fmt::format("expected a string, got {}", value_.dump()));
  return value_.get<std::string>();
}

std::vector<double> JsonReader::numbers(std::size_t count) const {
  if (!value_.is_array()) fail(fmt::format("expected an array of numbers, got {}", value_.dump()));
  if (count > 0 && value_.size() != count)
    fail(fmt::format("expected {} numbers, got {}", count, value_.size()));
  std::vector<double> out;
  for (std::size_t i = 0; i < value_.size(); ++i) out.push_back(at(i).number());
  return out;
}

double JsonReader::number(const std::string& key, double fallback, double lo, double hi) const {
  const auto child = find(key);
  return child ? child->number(lo, hi) : fallback;
}

int JsonReader::integer(const std::string& key, int fallback, int lo, int hi) const {
  const auto child = find(key);
  return child ? child->integer(lo, hi) : fallback;
}

bool JsonReader::boolean(const std::string& key, bool fallback) const {
  const auto child = find(key);
  return child ? child->boolean() : fallback;
}

std::string JsonReader::string(const std::string& key, const std::string& fallback) const {
  const auto child = find(key);
  return child ? child->string() : fallback;
}

void JsonReader::rejectUnknownKeys() const {
  if (!value_.is_object()) return;
  for (auto it = value_.begin(); it != value_.end(); ++it)
    if (!used_.count(it.key()))
      throw Error(fmt::format("{}: unknown key '{}'", file_, childPath(it.key())));
}

}  // namespace svr
