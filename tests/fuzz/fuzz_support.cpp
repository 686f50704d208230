#include "tests/fuzz/fuzz_support.h"

#include <fmt/format.h>
#include <unistd.h>
#include <zlib.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <vector>

#include "renderers/volume/volume_io.h"
#include "base/data_dir.h"
#include "base/error.h"

namespace svr::fuzz {
namespace fs = std::filesystem;

namespace {

void writeBytes(const fs::path& path, const void* data, std::size_t size) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(static_cast<const char*>(data), static_cast<std::streamsize>(size));
  if (!out) throw std::runtime_error("fuzz: cannot write " + path.string());
}

// zlib's compress2 (windowBits 15) or a gzip wrapper (windowBits 31) around `bytes`.
std::vector<unsigned char> deflated(const std::vector<unsigned char>& bytes, int window_bits) {
  z_stream z{};
  if (deflateInit2(&z, Z_BEST_COMPRESSION, Z_DEFLATED, window_bits, 8, Z_DEFAULT_STRATEGY) != Z_OK)
    throw std::runtime_error("fuzz: deflateInit2 failed");
  std::vector<unsigned char> out(deflateBound(&z, bytes.size()) + 32);
  z.next_in = const_cast<unsigned char*>(bytes.data());
  z.avail_in = static_cast<uInt>(bytes.size());
  z.next_out = out.data();
  z.avail_out = static_cast<uInt>(out.size());
  const int status = deflate(&z, Z_FINISH);
  out.resize(z.total_out);
  deflateEnd(&z);
  if (status != Z_STREAM_END) throw std::runtime_error("fuzz: deflate failed");
  return out;
}

fs::path makeScratchDir() {
  std::string pattern = (fs::temp_directory_path() / "svr_fuzz_XXXXXX").string();
  if (!mkdtemp(pattern.data())) throw std::runtime_error("fuzz: mkdtemp failed");
  const fs::path dir = pattern;
  std::vector<unsigned char> voxels(64);
  for (std::size_t i = 0; i < voxels.size(); ++i) voxels[i] = static_cast<unsigned char>(i);
  writeBytes(dir / "data.raw", voxels.data(), voxels.size());
  const auto gz = deflated(voxels, 15 + 16);
  writeBytes(dir / "data.raw.gz", gz.data(), gz.size());
  const auto zl = deflated(voxels, 15);
  writeBytes(dir / "data.zlib", zl.data(), zl.size());
  const std::string nhdr =
      "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 4 4 4\nspacings: 1 1 1\n"
      "encoding: raw\ndata file: data.raw\n";
  writeBytes(dir / "volume.nhdr", nhdr.data(), nhdr.size());
  const std::string csv = "wavelength_nm,flat,ramp\n380,0.5,0\n580,0.5,0.5\n780,0.5,1\n";
  writeBytes(dir / "spectrum.csv", csv.data(), csv.size());
  // A good slice of a DICOM series, beside which fuzz_dicom puts its input.
  fs::create_directory(dir / "series");
  fs::copy_file(fs::path(SVR_SOURCE_DIR) / "tests/data/formats/series/IM0001.dcm",
                dir / "series/IM0001.dcm");
  return dir;
}

}  // namespace

const std::string& scratchDir() {
  // Never destroyed, so the exit handler below can still read it after static destructors.
  static const std::string* const dir = [] {
    const auto* made = new std::string(makeScratchDir().string());
    std::atexit([] {
      std::error_code ignored;
      fs::remove_all(scratchDir(), ignored);
    });
    return made;
  }();
  return *dir;
}

std::string writeInput(const std::string& name, const std::uint8_t* data, std::size_t size) {
  const fs::path path = fs::path(scratchDir()) / name;
  writeBytes(path, data, size);
  return path.string();
}

int loadFolderInput(const std::string& name, const std::uint8_t* data, std::size_t size) {
  const fs::path path = writeInput(name, data, size);
  VolumeLoadOptions options;
  options.memory_budget = kMemoryBudget;
  try {
    loadVolume(path.parent_path().string(), options);
  } catch (const Error&) {
  }
  return 0;
}

const SpectrumLibrary& library() {
  static const SpectrumLibrary lib = SpectrumLibrary::load(defaultDataDir(), WavelengthGrid::standard());
  return lib;
}

const Observer& observer() {
  static const Observer obs = Observer::cie1931(defaultDataDir(), WavelengthGrid::standard());
  return obs;
}

int loadVolumeInput(const std::string& name, const std::uint8_t* data, std::size_t size) {
  const std::string path = writeInput(name, data, size);
  VolumeLoadOptions options;
  options.memory_budget = kMemoryBudget;
  try {
    loadVolume(path, options);
  } catch (const Error&) {
  }
  return 0;
}

}  // namespace svr::fuzz
