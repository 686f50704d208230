#include "base/json_reader.h"

#include <fmt/format.h>

#include <cmath>
#include <set>
#include <vector>

#include "base/error.h"
#include "base/text_file.h"

namespace svr {

JsonReader::JsonReader(const nlohmann::json& value, std::string file, std::string path)
    : value_(value), file_(std::move(file)), path_(std::move(path)) {}

namespace {

constexpr std::size_t kMaxDepth = 256;

// One open object or array while parsing: its keys so far (objects) or its element count
// (arrays), and the key whose value is being read, for naming a duplicate's path.
struct OpenValue {
  bool object = false;
  std::set<std::string> keys;
  std::string key;
  std::size_t index = 0;
};

// "lights[2].name": the path through the first n open values.
std::string pathThrough(const std::vector<OpenValue>& open, std::size_t n) {
  std::string path;
  for (std::size_t i = 0; i < n; ++i) {
    if (open[i].object)
      path += (path.empty() ? "" : ".") + open[i].key;
    else
      path += fmt::format("[{}]", open[i].index);
  }
  return path;
}

// A value as an error message shows it: compact, invalid UTF-8 replaced, long ones cut.
std::string shown(const nlohmann::json& value) {
  constexpr std::size_t kMaxChars = 80;
  std::string text = value.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  if (text.size() > kMaxChars) {
    text.resize(kMaxChars);
    // Cut at a UTF-8 character boundary, then mark the cut.
    while (!text.empty() && (static_cast<unsigned char>(text.back()) & 0xC0) == 0x80)
      text.pop_back();
    if (!text.empty() && static_cast<unsigned char>(text.back()) >= 0xC0) text.pop_back();
    text += "…";
  }
  return text;
}

}  // namespace

nlohmann::json JsonReader::parse(const std::string& text, const std::string& source) {
  std::vector<OpenValue> open;
  using Event = nlohmann::json::parse_event_t;
  const auto check = [&](int, Event event, nlohmann::json& parsed) {
    switch (event) {
      case Event::object_start:
      case Event::array_start:
        // Far deeper than any scene or palette; beyond it, dumping a value into an error
        // message (which recurses) could exhaust the stack.
        if (open.size() >= kMaxDepth)
          throw Error(fmt::format("{}: '{}' nests deeper than {} levels", source,
                                  pathThrough(open, open.size()), kMaxDepth));
        open.push_back({event == Event::object_start, {}, {}, 0});
        break;
      case Event::key: {
        OpenValue& object = open.back();
        std::string key = parsed.get<std::string>();
        if (!object.keys.insert(key).second)
          throw Error(fmt::format("{}: duplicate key '{}'", source,
                                  pathThrough(open, open.size() - 1) +
                                      (open.size() > 1 ? "." : "") + key));
        object.key = std::move(key);
        break;
      }
      case Event::object_end:
      case Event::array_end:
        open.pop_back();
        [[fallthrough]];
      case Event::value:
        // A finished element of the enclosing array moves its index on.
        if (!open.empty() && !open.back().object) ++open.back().index;
        break;
    }
    return true;
  };
  try {
    return nlohmann::json::parse(text, check);
  } catch (const nlohmann::json::exception& e) {
    throw Error(fmt::format("{}: invalid JSON: {}", source, e.what()));
  }
}

nlohmann::json JsonReader::parseFile(const std::string& path) {
  return parse(readTextFile(path, "JSON file"), path);
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
  if (!value_.is_object()) fail(fmt::format("expected an object, got {}", shown(value_)));
  used_.insert(key);
  if (!value_.contains(key)) fail(fmt::format("missing key '{}'", key));
  return {value_.at(key), file_, childPath(key)};
}

std::optional<JsonReader> JsonReader::find(const std::string& key) const {
  if (!value_.is_object()) fail(fmt::format("expected an object, got {}", shown(value_)));
  used_.insert(key);
  if (!value_.contains(key) || value_.at(key).is_null()) return std::nullopt;
  return JsonReader(value_.at(key), file_, childPath(key));
}

JsonReader JsonReader::at(std::size_t index) const {
  if (!value_.is_array()) fail(fmt::format("expected an array, got {}", shown(value_)));
  if (index >= value_.size()) fail(fmt::format("index {} is past the end", index));
  return {value_.at(index), file_, fmt::format("{}[{}]", path_, index)};
}

std::size_t JsonReader::size() const {
  if (!value_.is_array() && !value_.is_object())
    fail(fmt::format("expected an array or object, got {}", shown(value_)));
  return value_.size();
}

std::vector<std::string> JsonReader::keys() const {
  if (!value_.is_object()) fail(fmt::format("expected an object, got {}", shown(value_)));
  std::vector<std::string> out;
  for (auto it = value_.begin(); it != value_.end(); ++it) {
    out.push_back(it.key());
    used_.insert(it.key());
  }
  return out;
}

double JsonReader::number(double lo, double hi) const {
  if (!value_.is_number()) fail(fmt::format("expected a number, got {}", shown(value_)));
  const double v = value_.get<double>();
  if (!std::isfinite(v) || v < lo || v > hi)
    fail(fmt::format("value {} is outside {}..{}", v, lo, hi));
  return v;
}

int JsonReader::integer(int lo, int hi) const {
  if (!value_.is_number_integer()) fail(fmt::format("expected an integer, got {}", shown(value_)));
  const auto v = value_.get<long long>();
  if (v < lo || v > hi) fail(fmt::format("value {} is outside {}..{}", v, lo, hi));
  return static_cast<int>(v);
}

bool JsonReader::boolean() const {
  if (!value_.is_boolean()) fail(fmt::format("expected true or false, got {}", shown(value_)));
  return value_.get<bool>();
}

std::string JsonReader::string() const {
  if (!value_.is_string()) fail(fmt::format("expected a string, got {}", shown(value_)));
  return value_.get<std::string>();
}

std::vector<double> JsonReader::numbers(std::size_t count) const {
  if (!value_.is_array()) fail(fmt::format("expected an array of numbers, got {}", shown(value_)));
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
