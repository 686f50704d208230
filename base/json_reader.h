#pragma once
// Strict reading of JSON input files (scenes, palettes): every value is read through a
// JsonReader that knows its key path, so a wrong type, an out-of-range value or an unknown key
// is an svr::Error naming the file, the key path and the offending value.

#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace svr {

class JsonReader {
 public:
  JsonReader(const nlohmann::json& value, std::string file, std::string path = "");
  // Parses JSON text; `source` (the file name) prefixes every error. Besides malformed JSON,
  // rejects an object that repeats a key (nlohmann keeps the last silently, so a typo-free
  // but doubled "camera" would drop the first without a word), naming the key path.
  static nlohmann::json parse(const std::string& text, const std::string& source);
  static nlohmann::json parseFile(const std::string& path);

  const nlohmann::json& json() const { return value_; }
  const std::string& file() const { return file_; }
  const std::string& path() const { return path_; }
  std::string where() const;  // "scene.json: camera.azimuth"

  bool isObject() const { return value_.is_object(); }
  bool isArray() const { return value_.is_array(); }
  bool isString() const { return value_.is_string(); }
  bool contains(const std::string& key) const;

  // Child readers; marking the key as used.
  JsonReader at(const std::string& key) const;  // required
  std::optional<JsonReader> find(const std::string& key) const;
  JsonReader at(std::size_t index) const;
  std::size_t size() const;
  std::vector<std::string> keys() const;  // in file order

  // Typed values of this node.
  double number(double lo = -INFINITY, double hi = INFINITY) const;
  int integer(int lo, int hi) const;
  bool boolean() const;
  std::string string() const;
  std::vector<double> numbers(std::size_t count) const;  // exactly count (0 = any, ≥ 1)

  // Typed values of a child with a default when absent.
  double number(const std::string& key, double fallback, double lo = -INFINITY,
                double hi = INFINITY) const;
  int integer(const std::string& key, int fallback, int lo, int hi) const;
  bool boolean(const std::string& key, bool fallback) const;
  std::string string(const std::string& key, const std::string& fallback) const;

  // Throws for any key of this object that was never looked at (typos, unsupported options).
  void rejectUnknownKeys() const;
  [[noreturn]] void fail(const std::string& what) const;

 private:
  std::string childPath(const std::string& key) const;
  const nlohmann::json& value_;
  std::string file_, path_;
  mutable std::set<std::string> used_;
};

}  // namespace svr
