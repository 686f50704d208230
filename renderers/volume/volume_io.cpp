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

bool endsWith(const std::string& text, const std::string& tail) {
  return text.size() >= tail.size() && text.compare(text.size() - tail.size(), tail.size(), tail) == 0;
}

// A folder is a TIFF stack when it holds TIFFs, else a DICOM series.
bool holdsTiffs(const std::string& folder) {
  for (const fs::directory_entry& entry : fs::directory_iterator(folder))
    if (detail::isTiffName(entry.path().string())) return true;
  return false;
}

// Dispatch on the extension (or, for a folder, on what it holds): headers say what they are;
// anything else needs a raw layout.
VolumeSource openSource(const std::string& path, const VolumeLoadOptions& options) {
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (!fs::exists(status)) throw Error(fmt::format("{}: no such file", path));
  const std::string name = detail::toLower(fs::path(path).filename().string());
  const std::string extension = detail::toLower(fs::path(path).extension().string());
  const bool tiff = fs::is_directory(status) ? holdsTiffs(path) : detail::isTiffName(path);
  if (options.spacing && !tiff)
    throw Error(fmt::format("{}: states its own spacing (a spacing is given only for TIFF "
                            "stacks, and in a raw layout)",
                            path));
  if (tiff) return detail::readTiffSource(path, options.spacing.value_or(glm::dvec3(1.0)),
                                          options.memory_budget);
  if (fs::is_directory(status)) return detail::readDicomSource(path, options.memory_budget);
  if (extension == ".nrrd" || extension == ".nhdr") return detail::readNrrdSource(path, options.memory_budget);
  if (extension == ".mhd" || extension == ".mha") return detail::readMetaImageSource(path, options.memory_budget);
  if (extension == ".nii" || endsWith(name, ".nii.gz")) return detail::readNiftiSource(path);
  if (options.raw) return rawSource(path, *options.raw);
  throw Error(
      fmt::format("{}: unknown volume format '{}'; expected .nrrd, .nhdr, .mhd, .mha, .nii, "
                  ".nii.gz, .tif, .tiff, a folder (a DICOM series or numbered TIFFs), or a raw "
                  "layout (--raw-dims and --raw-type)",
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
  if (!source.slices && source.header.encoding == "raw") detail::checkRawPayloadSize(source);
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

namespace {

// Payload bytes in the file's byte order, turned to the machine's.
std::vector<std::byte> nativeOrder(const VolumeHeader& h, std::vector<std::byte> bytes) {
  const std::size_t width = bytesPerVoxel(h.type);
  if (width > 1 && h.endian != nativeEndian()) swapBytes(bytes, width);
  return bytes;
}

// The file's voxels of `box` (file order, native byte order, the stored type).
std::vector<std::byte> readBox(const VolumeSource& source, const VoxelBox& box) {
  const VolumeHeader& h = source.header;
  if (source.slices) return detail::readSliceBox(*source.slices, h.dims, box);
  return nativeOrder(h, box == VoxelBox{{0, 0, 0}, h.dims} ? detail::readPayload(source)
                                                             : detail::readPayloadBox(source, box));
}

std::vector<std::byte> readLattice(const VolumeSource& source, const LatticeIndices& at) {
  const VolumeHeader& h = source.header;
  if (source.slices) return detail::readSliceLattice(*source.slices, h.dims, at);
  return nativeOrder(h, detail::readPayloadLattice(source, at));
}

// File-order voxels of `file_size` to the Volume: reordered to x, y, z and rescaled as the
// source says.
Volume finish(const VolumeSource& source, std::vector<std::byte> bytes, const Dims& file_size,
              const glm::dvec3& spacing, const std::string& path) {
  const VolumeHeader& h = source.header;
  bytes = source.axes.reorder(bytes, file_size, bytesPerVoxel(h.type));
  const Dims size = source.axes.outputDims(file_size);
  Volume stored(size, spacing, h.type, std::move(bytes), path);
  if (!source.scale) return stored;
  std::vector<float> values(stored.voxelCount());
  for (std::size_t i = 0; i < values.size(); ++i) {
    values[i] = static_cast<float>(source.scale->slope * stored.value(i) + source.scale->intercept);
    if (!std::isfinite(values[i]))
      throw Error(fmt::format("{}: voxel {} is {} once rescaled ({}); not a finite float32", path,
                              i, values[i], h.values));
  }
  return Volume::fromValues(size, spacing, values, path);
}

}  // namespace

Volume loadVolume(const std::string& path, const VolumeLoadOptions& options) {
  const VolumeSource source = openSource(path, options);
  const VolumeHeader& h = source.header;
  if (!source.slices && h.encoding == "raw") detail::checkRawPayloadSize(source);
  const Dims dims = source.axes.outputDims(h.dims);
  const glm::dvec3 spacing = source.axes.outputSpacing(h.spacing);
  // Bytes a voxel takes while it loads: the stored type, and float32 beside it when rescaled.
  const std::size_t load_width = std::max(source.scale ? sizeof(float) : 0, bytesPerVoxel(h.type));
  if (options.lattice) {
    const LatticeIndices out_at = latticeIndices(dims, *options.lattice);
    const LatticeIndices at = source.axes.fileLattice(out_at, h.dims);
    const Dims size{static_cast<int>(at[0].size()), static_cast<int>(at[1].size()),
                    static_cast<int>(at[2].size())};
    return finish(source, readLattice(source, at), size,
                  latticeSpacing(dims, spacing, *options.lattice), path);
  }
  if (options.brick) {
    const VolumeBrick brick = options.brick(dims);
    checkMemoryBudget(brick.stored.voxels() * load_width, options.memory_budget,
                      fmt::format("{}: a brick of {}", path, describeShape(brick.stored.size(), h.type)));
    const VoxelBox box = source.axes.fileBox(brick.stored, h.dims);
    Volume volume = finish(source, readBox(source, box), box.size(), spacing, path);
    volume.setBrick(brick);
    return volume;
  }
  checkMemoryBudget(h.data_bytes / bytesPerVoxel(h.type) * load_width, options.memory_budget,
                    fmt::format("{}: {}", path, describeShape(dims, h.type)));
  return finish(source, readBox(source, VoxelBox{{0, 0, 0}, h.dims}), h.dims, spacing, path);
}

}  // namespace svr
