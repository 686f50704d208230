#include "renderers/volume/volume_io.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <utility>

#include "renderers/volume/volume_source.h"
#include "base/error.h"

namespace svr {

namespace {

using detail::VolumeSource;
namespace fs = std::filesystem;

VolumeSource rawSource(const std::string& path, const RawLayout& layout) {
  VolumeSource source;
  VolumeHeader& h = source.header;
  h.path = path;
  h.format = "raw";
  h.data_file = path;
  const std::string name = detail::toLower(path);
  const bool gz_name = name.size() >= 3 && name.compare(name.size() - 3, 3, ".gz") == 0;
  h.encoding = layout.gzip || gz_name ? "gzip" : "raw";
  h.type = layout.type;
  h.data_bytes = volumeBytes({layout.dims[0], layout.dims[1], layout.dims[2]}, layout.type, path);
  h.dims = layout.dims;
  for (int a = 0; a < 3; ++a)
    if (!std::isfinite(layout.spacing[a]) || layout.spacing[a] <= 0)
      throw Error(fmt::format("{}: raw spacing {} is {}; spacing must be finite and > 0", path,
                              "xyz"[a], layout.spacing[a]));
  h.spacing = layout.spacing;
  h.endian = bytesPerVoxel(h.type) == 1 ? nativeEndian() : layout.endian;
  if (h.encoding == "raw")
    source.offset = layout.header_bytes;
  else
    source.skip_decompressed = layout.header_bytes;
  return source;
}

// Dispatch on the extension: headers say what they are; anything else needs a raw layout.
VolumeSource openSource(const std::string& path, const VolumeLoadOptions& options) {
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (!fs::exists(status)) throw Error(fmt::format("{}: no such file", path));
  if (fs::is_directory(status))
    throw Error(fmt::format("{}: is a folder, not a volume file", path));
  const std::string extension = detail::toLower(fs::path(path).extension().string());
  if (extension == ".nrrd" || extension == ".nhdr") return detail::readNrrdSource(path, options.memory_budget);
  if (extension == ".mhd" || extension == ".mha") return detail::readMetaImageSource(path, options.memory_budget);
  if (options.raw) return rawSource(path, *options.raw);
  throw Error(
      fmt::format("{}: unknown volume format '{}'; expected .nrrd, .nhdr, .mhd or .mha, "
                  "or a raw layout (--raw-dims and --raw-type)",
                  path, extension));
}

// In place, from the file's byte order to the machine's.
void swapBytes(std::vector<std::byte>& bytes, std::size_t width) {
  for (std::size_t i = 0; i + width <= bytes.size(); i += width)
    std::reverse(bytes.begin() + static_cast<std::ptrdiff_t>(i),
                 bytes.begin() + static_cast<std::ptrdiff_t>(i + width));
}

}  // namespace

VolumeHeader readVolumeHeader(const std::string& path, const VolumeLoadOptions& options) {
  VolumeSource source = openSource(path, options);
  if (source.header.encoding == "raw") detail::checkRawPayloadSize(source);
  return std::move(source.header);
}

LatticeIndices latticeIndices(const Dims& dims, const Dims& samples) {
  LatticeIndices at;
  for (int a = 0; a < 3; ++a) {
    const int n = std::clamp(samples[a], 1, dims[a]);
    for (int i = 0; i < n; ++i)
      at[a].push_back(n == 1 ? 0
                             : static_cast<int>(std::lround(static_cast<double>(i) *
                                                            (dims[a] - 1) / (n - 1))));
  }
  return at;
}

glm::dvec3 latticeSpacing(const Dims& dims, const glm::dvec3& spacing, const Dims& samples) {
  glm::dvec3 out = spacing;
  for (int a = 0; a < 3; ++a) {
    const int n = std::clamp(samples[a], 1, dims[a]);
    if (n > 1) out[a] = spacing[a] * (dims[a] - 1) / (n - 1);
  }
  return out;
}

Volume latticeOf(const Volume& whole, const Dims& samples) {
  const LatticeIndices at = latticeIndices(whole.dims(), samples);
  const std::size_t w = bytesPerVoxel(whole.type());
  std::vector<std::byte> bytes(at[0].size() * at[1].size() * at[2].size() * w);
  std::byte* dest = bytes.data();
  for (const int z : at[2])
    for (const int y : at[1])
      for (const int x : at[0])
        dest = std::copy_n(whole.data().data() + whole.index(x, y, z) * w, w, dest);
  const Dims size{static_cast<int>(at[0].size()), static_cast<int>(at[1].size()),
                  static_cast<int>(at[2].size())};
  return Volume(size, latticeSpacing(whole.dims(), whole.spacing(), samples), whole.type(),
                std::move(bytes), whole.source());
}

Volume loadVolume(const std::string& path, const VolumeLoadOptions& options) {
  const VolumeSource source = openSource(path, options);
  const VolumeHeader& h = source.header;
  if (h.encoding == "raw") detail::checkRawPayloadSize(source);
  if (options.lattice) {
    const LatticeIndices at = latticeIndices(h.dims, *options.lattice);
    const Dims size{static_cast<int>(at[0].size()), static_cast<int>(at[1].size()),
                    static_cast<int>(at[2].size())};
    std::vector<std::byte> bytes = detail::readPayloadLattice(source, at);
    const std::size_t width = bytesPerVoxel(h.type);
    if (width > 1 && h.endian != nativeEndian()) swapBytes(bytes, width);
    return Volume(size, latticeSpacing(h.dims, h.spacing, *options.lattice), h.type,
                  std::move(bytes), path);
  }
  if (options.brick) {
    const VolumeBrick brick = options.brick(h.dims);
    const Dims size = brick.stored.size();
    checkMemoryBudget(brick.stored.voxels() * bytesPerVoxel(h.type), options.memory_budget,
                      fmt::format("{}: a brick of {}", path, describeShape(size, h.type)));
    std::vector<std::byte> bytes = detail::readPayloadBox(source, brick.stored);
    const std::size_t width = bytesPerVoxel(h.type);
    if (width > 1 && h.endian != nativeEndian()) swapBytes(bytes, width);
    Volume volume(size, h.spacing, h.type, std::move(bytes), path);
    volume.setBrick(brick);
    return volume;
  }
  checkMemoryBudget(h.data_bytes, options.memory_budget,
                    fmt::format("{}: {}", path, describeShape(h.dims, h.type)));
  std::vector<std::byte> bytes = detail::readPayload(source);
  const std::size_t width = bytesPerVoxel(h.type);
  if (width > 1 && h.endian != nativeEndian()) swapBytes(bytes, width);
  return Volume(h.dims, h.spacing, h.type, std::move(bytes), path);
}

}  // namespace svr
