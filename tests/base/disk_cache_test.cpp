#include "base/disk_cache.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace svr {
namespace {
namespace fs = std::filesystem;

// A fresh cache folder per test, removed afterwards.
class DiskCacheTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("svr_cache_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
  }
  void TearDown() override {
    std::error_code ignored;
    fs::permissions(dir_, fs::perms::owner_all, ignored);
    fs::remove_all(dir_, ignored);
  }
  static void overwrite(const fs::path& path, const std::string& text) {
    std::ofstream(path, std::ios::binary | std::ios::trunc) << text;
  }
  static std::string contents(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
  }
  fs::path dir_;
  const nlohmann::json key_ = {{"lights", {{1.0, 0.5}, {0.25, 2.0}}}, {"k", 6}};
  const nlohmann::json payload_ = {{"model", {1, 2, 3}}, {"error", 0.125}};
};

TEST(Sha256, KnownVectors) {  // FIPS 180-2 test vectors
  EXPECT_EQ(sha256Hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_EQ(sha256Hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
}

TEST_F(DiskCacheTest, StoredPayloadComesBackForTheSameKeyOnly) {
  const DiskCache cache(dir_);
  EXPECT_EQ(cache.load("model", key_).why, "absent");
  ASSERT_TRUE(cache.store("model", key_, payload_));
  const auto hit = cache.load("model", key_);
  ASSERT_TRUE(hit.payload) << hit.why;
  EXPECT_EQ(*hit.payload, payload_);
  nlohmann::json other = key_;
  other["lights"][1][0] = 0.2500000001;  // any input value changes the entry
  EXPECT_FALSE(cache.load("model", other).payload);
  EXPECT_FALSE(cache.load("palette", key_).payload);  // kinds do not share entries
}

TEST_F(DiskCacheTest, CorruptAndStaleEntriesAreMissesThatAStoreRepairs) {
  const DiskCache cache(dir_);
  ASSERT_TRUE(cache.store("model", key_, payload_));
  const fs::path path = cache.entryPath("model", key_);
  const std::string good = contents(path);
  struct Case {
    std::string text, why;
  };
  nlohmann::json tampered = nlohmann::json::parse(good);
  tampered["payload"]["error"] = 0.5;  // edited payload, old checksum
  nlohmann::json old_format = nlohmann::json::parse(good);
  old_format["svr_cache"] = DiskCache::kFormat - 1;
  nlohmann::json moved = nlohmann::json::parse(good);
  moved["key_sha256"] = sha256Hex("another key");  // an entry copied under this name
  const Case cases[] = {
      {good.substr(0, good.size() / 2), "corrupt (not JSON)"},  // a truncated write
      {"", "corrupt (not JSON)"},
      {"[1, 2]", "corrupt (not a cache entry)"},
      {tampered.dump(), "corrupt (payload checksum mismatch)"},
      {old_format.dump(), "stale (format 0, not 1)"},
      {moved.dump(), "stale (made for other inputs)"},
  };
  for (const Case& c : cases) {
    overwrite(path, c.text);
    const auto miss = cache.load("model", key_);
    EXPECT_FALSE(miss.payload) << c.text;
    EXPECT_EQ(miss.why, c.why) << c.text;
    ASSERT_TRUE(cache.store("model", key_, payload_));  // the caller rebuilds and overwrites
    EXPECT_EQ(*cache.load("model", key_).payload, payload_);
  }
}

TEST_F(DiskCacheTest, AnUnwritableOrDisabledCacheCostsOnlyTheSpeedUp) {
  fs::create_directories(dir_);
  fs::permissions(dir_, fs::perms::owner_read | fs::perms::owner_exec);
  const DiskCache read_only(dir_);
  if (::geteuid() != 0) {  // root writes anyway
    EXPECT_FALSE(read_only.store("model", key_, payload_));
    EXPECT_FALSE(read_only.load("model", key_).payload);
  }
  const DiskCache blocked(dir_ / "file" / "below");  // a parent that is a file
  fs::permissions(dir_, fs::perms::owner_all);
  overwrite(dir_ / "file", "x");
  EXPECT_FALSE(blocked.store("model", key_, payload_));
  const DiskCache off{fs::path()};
  EXPECT_FALSE(off.enabled());
  EXPECT_FALSE(off.store("model", key_, payload_));
  EXPECT_EQ(off.load("model", key_).why, "the cache is off");
}

TEST(DiskCacheDirectory, FollowsXdgThenHome) {
  const char* xdg = std::getenv("XDG_CACHE_HOME");
  const char* home = std::getenv("HOME");
  const std::string saved_xdg = xdg ? xdg : "", saved_home = home ? home : "";
  ::setenv("XDG_CACHE_HOME", "/tmp/xdg", 1);
  EXPECT_EQ(DiskCache::defaultDirectory(), fs::path("/tmp/xdg/svr"));
  ::setenv("XDG_CACHE_HOME", "relative/dir", 1);  // the spec: relative paths are ignored
  ::setenv("HOME", "/home/someone", 1);
  EXPECT_EQ(DiskCache::defaultDirectory(), fs::path("/home/someone/.cache/svr"));
  ::unsetenv("XDG_CACHE_HOME");
  ::unsetenv("HOME");
  EXPECT_TRUE(DiskCache::defaultDirectory().empty());
  if (xdg) ::setenv("XDG_CACHE_HOME", saved_xdg.c_str(), 1);
  if (home) ::setenv("HOME", saved_home.c_str(), 1);
}

}  // namespace
}  // namespace svr
