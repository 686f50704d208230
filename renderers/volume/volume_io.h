#pragma once
// Reading volumes from files: NRRD (attached .nrrd and detached .nhdr, raw or gzip), MetaImage
// (.mhd/.mha, raw or zlib), NIfTI-1/-2 (.nii, .nii.gz), TIFF stacks (a multi-page .tif or a
// folder of numbered ones), DICOM series (a folder of one series) and headerless raw files whose
// layout the caller states. NIfTI and DICOM grids are turned to RAS+ (axis_map.h). Every
// failure is an svr::Error that names the file and what is wrong with it; the memory budget is
// checked before a byte of voxel data is allocated. Voxels are converted to native byte order.

#include <array>
#include <cstdint>
#include <functional>
#include <glm/vec3.hpp>
#include <optional>
#include <string>
#include <vector>

#include "renderers/volume/memory_budget.h"
#include "renderers/volume/volume.h"

namespace svr {

// The layout of a headerless raw file (no header states it, so the caller must).
struct RawLayout {
  Dims dims{0, 0, 0};
  ScalarType type = ScalarType::kUint8;
  Endian endian = Endian::kLittle;
  glm::dvec3 spacing{1.0};
  // Bytes before the voxels; for a gzip file, counted in the decompressed stream.
  std::uint64_t header_bytes = 0;
  // The file is a gzip stream (also assumed when the name ends in .gz).
  bool gzip = false;
};

// What a volume file says about its voxels, read without reading the voxels.
struct VolumeHeader {
  std::string path;       // the file asked for
  // "nrrd" (attached), "nhdr" (detached), "mhd", "mha", "nifti-1", "nifti-2", "tiff",
  // "dicom" or "raw"
  std::string format;
  std::string encoding;   // how the voxels are stored: "raw", "gzip", "zlib", or the codec
  std::string data_file;  // the file holding the voxels (== path when they are attached)
  Dims dims{0, 0, 0};                 // as stored (before any reorientation)
  ScalarType type = ScalarType::kUint8;  // as stored (before any rescaling)
  Endian endian = Endian::kLittle;  // of the stored voxels; native for 1-byte types
  glm::dvec3 spacing{1.0};
  std::uint64_t data_bytes = 0;       // voxel bytes once decompressed
  std::vector<std::string> comments;  // NRRD '#' lines, MetaImage Comment, NIfTI descrip
  // Set where the format says more: how the file's axes became x, y, z, and how its stored
  // values became the volume's ("stored × 2 + −1024, as float32").
  std::string orientation, values;
};

struct VolumeLoadOptions {
  // Largest voxel payload loadVolume may allocate, in bytes.
  std::uint64_t memory_budget = defaultMemoryBudget();
  // Layout for files that are not .nrrd/.nhdr/.mhd/.mha/.nii/.tif/DICOM; such files are refused
  // without it.
  std::optional<RawLayout> raw;
  // Spacing for formats that do not state one (TIFF stacks); 1 when not given. Refused for
  // formats that state their own.
  std::optional<glm::dvec3> spacing;
  // A distributed render's process reads one brick: given the file's dims, the brick (and so
  // the voxels, brick.stored) to read. Empty: the whole volume.
  std::function<VolumeBrick(const Dims&)> brick;
  // A coarse copy instead (work estimates): this many samples along each axis (at most the
  // file's), spread over the whole grid, with the spacing that keeps the grid's extent.
  std::optional<Dims> lattice;
};

// The voxel indices of each axis that a lattice of `samples` per axis takes from `dims`: the
// first and last voxel and evenly spread ones between.
using LatticeIndices = std::array<std::vector<int>, 3>;
LatticeIndices latticeIndices(const Dims& dims, const Dims& samples);
// The spacing of such a lattice: the same extent as the grid's.
glm::dvec3 latticeSpacing(const Dims& dims, const glm::dvec3& spacing, const Dims& samples);
// The voxels of `whole` at those indices (procedural volumes, made whole).
Volume latticeOf(const Volume& whole, const Dims& samples);

// Parses the header (and, for raw encodings, checks the data file's size against it). Throws
// svr::Error naming the file for a missing file, a malformed or unsupported header, a data file
// that is missing or outside the header's folder, or a size mismatch. Does not check the budget.
VolumeHeader readVolumeHeader(const std::string& path, const VolumeLoadOptions& options = {});

// readVolumeHeader, the memory budget check, then the voxels (only the brick's, when options say
// one: the Volume then holds brick.stored and carries the brick). Also throws svr::Error for
// truncated or corrupt compressed streams and non-finite float voxels.
Volume loadVolume(const std::string& path, const VolumeLoadOptions& options = {});

}  // namespace svr
