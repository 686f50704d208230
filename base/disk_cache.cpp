#include "base/disk_cache.h"

#include <fmt/format.h>
#include <openssl/evp.h>

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <system_error>

#include "base/atomic_file.h"

namespace svr {
namespace fs = std::filesystem;

std::string sha256Hex(const std::string& text) { return sha256Hex(text.data(), text.size()); }

std::string sha256Hex(const void* data, std::size_t size) {
  unsigned char digest[EVP_MAX_MD_SIZE];
  unsigned int length = 0;
  if (EVP_Digest(data, size, digest, &length, EVP_sha256(), nullptr) != 1)
    throw std::runtime_error("sha256: EVP_Digest failed");
  std::string hex;
  for (unsigned int i = 0; i < length; ++i) hex += fmt::format("{:02x}", digest[i]);
  return hex;
}

nlohmann::json valuesJson(const Eigen::VectorXd& values) {
  return std::vector<double>(values.data(), values.data() + values.size());
}

namespace {

// nlohmann's dump is canonical for our purpose: objects keep their keys sorted (std::map) and
// doubles print with round-trip precision, so equal inputs give equal text.
std::string keyDigest(const std::string& kind, const nlohmann::json& key) {
  return sha256Hex(kind + '\n' + key.dump());
}

bool disabled_by_flag = false;

}  // namespace

DiskCache::DiskCache(fs::path dir) : dir_(std::move(dir)) {}

DiskCache& DiskCache::process() {
  static DiskCache enabled(defaultDirectory());
  static DiskCache disabled{fs::path()};
  return disabled_by_flag ? disabled : enabled;
}

void DiskCache::disableProcessCache() { disabled_by_flag = true; }

fs::path DiskCache::defaultDirectory() {
  const char* xdg = std::getenv("XDG_CACHE_HOME");
  if (xdg && fs::path(xdg).is_absolute()) return fs::path(xdg) / "svr";  // the spec: ignore relative
  const char* home = std::getenv("HOME");
  if (home && *home) return fs::path(home) / ".cache" / "svr";
  return {};
}

fs::path DiskCache::entryPath(const std::string& kind, const nlohmann::json& key) const {
  return dir_ / (kind + "-" + keyDigest(kind, key) + ".json");
}

DiskCache::Lookup DiskCache::load(const std::string& kind, const nlohmann::json& key) const {
  if (!enabled()) return {std::nullopt, "the cache is off"};
  const fs::path path = entryPath(kind, key);
  std::ifstream in(path, std::ios::binary);
  if (!in) return {std::nullopt, "absent"};
  std::stringstream text;
  text << in.rdbuf();
  const nlohmann::json entry = nlohmann::json::parse(text.str(), nullptr, false);
  if (entry.is_discarded()) return {std::nullopt, "corrupt (not JSON)"};
  if (!entry.is_object()) return {std::nullopt, "corrupt (not a cache entry)"};
  const auto field = [&](const char* name) {
    const auto it = entry.find(name);
    return it == entry.end() ? nlohmann::json() : *it;
  };
  if (field("svr_cache") != kFormat)
    return {std::nullopt, fmt::format("stale (format {}, not {})", field("svr_cache").dump(), kFormat)};
  if (field("kind") != kind || field("key_sha256") != keyDigest(kind, key))
    return {std::nullopt, "stale (made for other inputs)"};
  const nlohmann::json payload = field("payload");
  if (payload.is_null() || field("payload_sha256") != sha256Hex(payload.dump()))
    return {std::nullopt, "corrupt (payload checksum mismatch)"};
  return {payload, {}};
}

bool DiskCache::store(const std::string& kind, const nlohmann::json& key,
                      const nlohmann::json& payload) const {
  if (!enabled()) return false;
  std::error_code error;
  fs::create_directories(dir_, error);
  if (error) return false;
  const nlohmann::json entry = {{"svr_cache", kFormat},
                                {"kind", kind},
                                {"key_sha256", keyDigest(kind, key)},
                                {"payload_sha256", sha256Hex(payload.dump())},
                                {"payload", payload}};
  try {
    writeTextAtomically(entryPath(kind, key).string(), entry.dump() + "\n");
  } catch (const std::exception&) {
    return false;  // a read-only or full cache costs the speed-up, not the run
  }
  return true;
}

}  // namespace svr
