#pragma once
// Small volume files written by the tests themselves, with known voxels, in every format and
// encoding the readers take; plus SHA-256 and error-message helpers.

#include <cstddef>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "renderers/volume/volume.h"

namespace svr::test {

// A fresh folder under the system temp folder, removed with everything in it on destruction.
class TempDir {
 public:
  TempDir();
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  const std::filesystem::path& dir() const { return dir_; }

 private:
  std::filesystem::path dir_;
};

void writeFile(const std::string& path, const std::string& text);
void writeFile(const std::string& path, const std::vector<std::byte>& bytes);
std::vector<std::byte> readFile(const std::string& path);
std::vector<std::byte> bytesOf(const std::string& text);

std::vector<std::byte> gzipCompress(const std::vector<std::byte>& bytes);
std::vector<std::byte> zlibCompress(const std::vector<std::byte>& bytes);
std::vector<std::byte> gunzipFile(const std::string& path);
std::string sha256Hex(const std::vector<std::byte>& bytes);

// Voxel values that reach both ends of the type's range (and negative and fractional values
// where the type has them), `count` of them, exactly representable in the type.
std::vector<double> knownValues(ScalarType type, std::size_t count);
// Those values as bytes of the type in the given byte order.
std::vector<std::byte> encodeValues(const std::vector<double>& values, ScalarType type,
                                    Endian endian);

// NRRD's and MetaImage's names for a type.
std::string nrrdTypeName(ScalarType type);
std::string metaTypeName(ScalarType type);

// The message of the svr::Error that f throws; "" (and a test failure) if it throws none.
std::string errorOf(const std::function<void()>& f);

}  // namespace svr::test
