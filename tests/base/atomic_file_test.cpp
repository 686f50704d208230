#include "base/atomic_file.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "base/error.h"

namespace svr {
namespace {
namespace fs = std::filesystem;

// A fresh folder per test; a leftover temporary shows up as a second entry.
fs::path freshDir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("svr_atomic_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::string contents(const fs::path& path) {
  std::ifstream in(path);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

std::size_t entries(const fs::path& dir) {
  return static_cast<std::size_t>(std::distance(fs::directory_iterator(dir), {}));
}

TEST(AtomicFile, WritesTheWholeFileAndNoTemporary) {
  const fs::path dir = freshDir("writes");
  writeTextAtomically((dir / "a.json").string(), "{\"x\": 1}\n");
  writeTextAtomically((dir / "a.json").string(), "{\"x\": 2}\n");  // replaces
  EXPECT_EQ(contents(dir / "a.json"), "{\"x\": 2}\n");
  EXPECT_EQ(entries(dir), 1u);
}

TEST(AtomicFile, AFailingWriteKeepsThePreviousFileAndRemovesTheTemporary) {
  const fs::path dir = freshDir("failing");
  writeTextAtomically((dir / "a.png").string(), "old");
  EXPECT_THROW(writeFileAtomically((dir / "a.png").string(),
                                   [](const std::string& tmp) {
                                     std::ofstream(tmp) << "half an ima";
                                     throw std::runtime_error("disk full");
                                   }),
               std::runtime_error);
  EXPECT_EQ(contents(dir / "a.png"), "old");
  EXPECT_EQ(entries(dir), 1u);
}

TEST(AtomicFile, ARenameOntoAFolderFailsNamingThePath) {
  const fs::path dir = freshDir("folder");
  fs::create_directories(dir / "render.json" / "inside");
  try {
    writeTextAtomically((dir / "render.json").string(), "{}");
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()).rfind((dir / "render.json").string() + ": cannot write: ", 0),
              0u)
        << e.what();
  }
  EXPECT_EQ(entries(dir), 1u);
}

}  // namespace
}  // namespace svr
