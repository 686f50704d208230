#pragma once
// Results that take long to compute and are fully determined by their inputs — scene-trained
// colour models, designed palettes — kept on disk between runs, so that a second run of the
// same scene starts in a fraction of a second.
//
// Entries live in $XDG_CACHE_HOME/svr (else ~/.cache/svr), one JSON file each, named by kind
// and the SHA-256 of a key that must hold *everything* the result depends on (its inputs'
// values, not their file names, and a version the producer bumps when its algorithm changes).
// An entry is trusted only when it parses, has this format, names the same kind and key digest
// as its file name and its payload matches the checksum stored with it; anything else — a
// truncated write, an edit, an entry of an older format — is a miss, reported with the reason,
// and the caller rebuilds it and overwrites the entry. Entries are written atomically. A cache
// that cannot be written (read-only home, no HOME) costs the speed-up, never the run.

#include <Eigen/Core>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

namespace svr {

// Hex SHA-256 of text.
std::string sha256Hex(const std::string& text);
std::string sha256Hex(const void* data, std::size_t size);

// A piece of keys and payloads the producers share: a vector's values as a JSON array (doubles
// round-trip exactly). The observer's key is spectral/observer_key.h.
nlohmann::json valuesJson(const Eigen::VectorXd& values);

class DiskCache {
 public:
  static constexpr int kFormat = 1;

  // A cache in `dir`; an empty path is a disabled cache (every load misses, nothing written).
  explicit DiskCache(std::filesystem::path dir);
  // The process's cache: defaultDirectory() unless disabled (--no-cache).
  static DiskCache& process();
  static void disableProcessCache();
  // $XDG_CACHE_HOME/svr when XDG_CACHE_HOME is an absolute path, else $HOME/.cache/svr, else
  // empty (no cache).
  static std::filesystem::path defaultDirectory();

  bool enabled() const { return !dir_.empty(); }
  const std::filesystem::path& directory() const { return dir_; }

  struct Lookup {
    std::optional<nlohmann::json> payload;  // set on a hit
    std::string why;  // on a miss: "absent", or why the entry was not trusted
  };
  // The payload stored under (kind, key), where key is the JSON of every input.
  Lookup load(const std::string& kind, const nlohmann::json& key) const;
  // Stores it; returns false (and leaves no partial file) when the cache cannot be written.
  bool store(const std::string& kind, const nlohmann::json& key,
             const nlohmann::json& payload) const;
  // The file an entry lives in.
  std::filesystem::path entryPath(const std::string& kind, const nlohmann::json& key) const;

 private:
  std::filesystem::path dir_;
};

}  // namespace svr
