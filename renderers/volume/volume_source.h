#pragma once
// Internal to the volume readers: a parsed header plus where its voxels are, and the one
// payload reader (raw, gzip, zlib) every format shares. Not for use outside renderers/volume/.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <memory>
#include <string>
#include <vector>

#include "renderers/volume/axis_map.h"
#include "renderers/volume/volume_io.h"

namespace svr::detail {

// A volume stored as 2-D images, one per z (TIFF pages or files, DICOM files).
class SliceStack {
 public:
  virtual ~SliceStack() = default;
  // Slice z of the file's grid: dims[0] × dims[1] voxels of `type`, x fastest, native byte order.
  virtual std::vector<std::byte> slice(int z) const = 0;
  virtual ScalarType type() const = 0;
};

// values = slope × stored + intercept, as float32 (NIfTI's scl_slope and scl_inter).
struct ValueScale {
  double slope = 1.0, intercept = 0.0;
};

struct VolumeSource {
  VolumeHeader header;
  AxisMap axes;                             // file axes → x, y, z
  std::optional<ValueScale> scale;          // stored → volume values
  std::shared_ptr<const SliceStack> slices;  // set: voxels come from it, not a payload
  std::uint64_t offset = 0;                       // bytes of header.data_file before the payload
  std::uint64_t skip_decompressed = 0;            // bytes to drop from the decompressed stream
  std::optional<std::uint64_t> compressed_bytes;  // length of the compressed payload, if known
};

// The path of a header's data file `name`, resolved against the header's folder. Throws
// svr::Error naming `header_path` and `key` when `name` has a ".." component, is absolute and
// outside that folder, or does not exist.
std::string resolveDataFile(const std::string& header_path, const std::string& name,
                            const std::string& key);

// Size of a file in bytes; throws svr::Error naming `source` when it cannot be read.
std::uint64_t fileSize(const std::string& path, const std::string& source);

// For raw encodings: throws when the data file does not hold exactly header.data_bytes after
// the offset ("header says … = N bytes but the data file holds M bytes").
void checkRawPayloadSize(const VolumeSource& source);

// The payload in file byte order, exactly header.data_bytes long. Throws svr::Error for short
// files, truncated or corrupt compressed streams and streams that hold more than expected.
std::vector<std::byte> readPayload(const VolumeSource& source);
// Only the voxels in `box` (of header.dims), x fastest, in file byte order. Raw payloads are
// read with a seek per run of contiguous bytes; compressed ones are inflated as a stream (all
// of it, so that its checksum is checked as for a whole read) keeping only the box.
std::vector<std::byte> readPayloadBox(const VolumeSource& source, const VoxelBox& box);
// Only the voxels at the given indices along each axis (a sub-lattice: a coarse copy), x
// fastest, in file byte order. Raw: a seek and a read per chosen row; compressed: the whole
// stream, keeping only those voxels.
std::vector<std::byte> readPayloadLattice(const VolumeSource& source, const LatticeIndices& at);

// Readers per format (nrrd_header.cpp, metaimage_header.cpp). A header may be of any length
// within `budget` bytes (and 1 MiB always) (the memory budget: the format sets no limit, and comments or key/value
// metadata can run to megabytes); a line holding binary bytes is refused, so a data file given
// by mistake fails at once with a clear error instead of being read as text.
VolumeSource readNrrdSource(const std::string& path, std::uint64_t budget);
VolumeSource readMetaImageSource(const std::string& path, std::uint64_t budget);
// nifti_source.cpp, tiff_stack.cpp (a file or a folder of numbered files), dicom_series.cpp
// (a folder holding one series; a slice, which GDCM decodes whole, must fit `budget`, as must
// a TIFF tile).
VolumeSource readNiftiSource(const std::string& path);
VolumeSource readTiffSource(const std::string& path, const glm::dvec3& spacing,
                            std::uint64_t budget);
VolumeSource readDicomSource(const std::string& folder, std::uint64_t budget);
// Voxels of `box` from a slice stack, x fastest (slices outside the box's z are not read).
std::vector<std::byte> readSliceBox(const SliceStack& stack, const Dims& dims, const VoxelBox& box);
std::vector<std::byte> readSliceLattice(const SliceStack& stack, const Dims& dims,
                                        const LatticeIndices& at);

// Throws "PATH: line N of the header holds binary data (byte 0x00 at column C) …" when the
// line has a byte that no text header holds (control characters other than tab and CR).
void checkHeaderLineIsText(const std::string& path, const std::string& line, int line_number);
// Throws "PATH: the header runs past B bytes …, over the memory budget" when consumed > budget.
void checkHeaderWithinBudget(const std::string& path, std::uint64_t consumed,
                             std::uint64_t budget, const char* what_ends_it);

// A .tif or .tiff name, in any case (files of a TIFF stack, and folders that hold them).
bool isTiffName(const std::string& path);

// Shared header-text helpers.
std::string trim(const std::string& text);
std::string toLower(std::string text);
std::vector<std::string> splitWhitespace(const std::string& text);

}  // namespace svr::detail
