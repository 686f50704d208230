// The real volumes in data/volumes: layout as their headers say, and voxels whose bytes (in the
// file's byte order) have the sha256 the header's comment gives for the uncompressed data.
#include <gtest/gtest.h>

#include <algorithm>
#include <ostream>
#include <string>

#include "renderers/volume/volume_io.h"
#include "volume_test_files.h"

namespace svr {
namespace {

std::string volumePath(const std::string& stem) {
  return std::string(SVR_TEST_DATA_DIR) + "/volumes/" + stem + ".nhdr";
}

// The sha256 after "sha256 of uncompressed data " in a header comment; "" if none.
std::string checksumInComments(const VolumeHeader& header) {
  const std::string key = "sha256 of uncompressed data ";
  for (const std::string& comment : header.comments) {
    const auto at = comment.find(key);
    if (at != std::string::npos) return comment.substr(at + key.size(), 64);
  }
  return "";
}

// The voxel bytes as the file stores them (the Volume holds them in native order).
std::vector<std::byte> fileOrderBytes(const Volume& volume, Endian file_endian) {
  std::vector<std::byte> bytes = volume.data();
  const std::size_t width = bytesPerVoxel(volume.type());
  if (width > 1 && file_endian != nativeEndian())
    for (std::size_t i = 0; i < bytes.size(); i += width)
      std::reverse(bytes.begin() + i, bytes.begin() + i + width);
  return bytes;
}

struct Shipped {
  std::string stem;
  Dims dims;
  ScalarType type;
  Endian endian;  // of the file; irrelevant for 1-byte types
  glm::dvec3 spacing;
  double min, max;
};

void PrintTo(const Shipped& s, std::ostream* os) { *os << s.stem; }

class ShippedVolume : public ::testing::TestWithParam<Shipped> {};

TEST_P(ShippedVolume, LayoutChecksumAndRange) {
  const Shipped& s = GetParam();
  const VolumeHeader header = readVolumeHeader(volumePath(s.stem));
  EXPECT_EQ(header.format, "nhdr");
  EXPECT_EQ(header.encoding, "gzip");
  EXPECT_EQ(header.dims, s.dims);
  EXPECT_EQ(header.type, s.type);
  EXPECT_EQ(header.spacing, s.spacing);
  if (bytesPerVoxel(s.type) > 1) {
    EXPECT_EQ(header.endian, s.endian);
  }
  const std::string checksum = checksumInComments(header);
  ASSERT_EQ(checksum.size(), 64u) << "no sha256 in the comments of " << s.stem;

  const Volume volume = loadVolume(volumePath(s.stem));
  EXPECT_EQ(volume.dims(), s.dims);
  EXPECT_EQ(volume.type(), s.type);
  EXPECT_EQ(volume.spacing(), s.spacing);
  EXPECT_EQ(volume.bytes(), header.data_bytes);
  EXPECT_EQ(test::sha256Hex(fileOrderBytes(volume, header.endian)), checksum);
  EXPECT_EQ(volume.valueRange().first, s.min);
  EXPECT_EQ(volume.valueRange().second, s.max);
}

INSTANTIATE_TEST_SUITE_P(VolumeIo, ShippedVolume,
                         ::testing::Values(Shipped{"engine_256x256x128_uint8",
                                                   {256, 256, 128},
                                                   ScalarType::kUint8,
                                                   Endian::kLittle,
                                                   {1, 1, 1},
                                                   0,
                                                   255},
                                           Shipped{"frogtissue_500x470x136_uint8",
                                                   {500, 470, 136},
                                                   ScalarType::kUint8,
                                                   Endian::kLittle,
                                                   {1, 1, 1.5},
                                                   0,
                                                   29},
                                           Shipped{"headsq_64x64x93_int16",
                                                   {64, 64, 93},
                                                   ScalarType::kInt16,
                                                   Endian::kLittle,
                                                   {3.2, 3.2, 1.5},
                                                   0,
                                                   3926},
                                           Shipped{"hydrogen_orbital_64x64x64_float32",
                                                   {64, 64, 64},
                                                   ScalarType::kFloat32,
                                                   Endian::kLittle,
                                                   {1, 1, 1},
                                                   0,
                                                   1},
                                           Shipped{"cthead_256x256x113_uint16be",
                                                   {256, 256, 113},
                                                   ScalarType::kUint16,
                                                   Endian::kBig,
                                                   {1, 1, 2},
                                                   0,
                                                   3272},
                                           Shipped{"nucleon_41x41x41_uint8",
                                                   {41, 41, 41},
                                                   ScalarType::kUint8,
                                                   Endian::kLittle,
                                                   {1, 1, 1},
                                                   0,
                                                   249}),
                         [](const auto& info) { return info.param.stem; });

// The frog label map: 0 background, 1..15 tissues, 777 stray voxels with 16..29 (README).
TEST(ShippedVolumes, FrogTissueLabels) {
  const Volume volume = loadVolume(volumePath("frogtissue_500x470x136_uint8"));
  std::vector<std::size_t> counts(256, 0);
  for (std::size_t i = 0; i < volume.voxelCount(); ++i)
    ++counts[static_cast<std::size_t>(volume.value(i))];
  std::size_t stray = 0;
  for (int label = 16; label <= 29; ++label) stray += counts[label];
  EXPECT_EQ(stray, 777u);
  for (int label = 1; label <= 15; ++label) EXPECT_GT(counts[label], 0u) << "label " << label;
  EXPECT_GT(counts[0], volume.voxelCount() / 2);
}

// The header's sha256 also holds for the raw stream itself, decompressed independently.
TEST(ShippedVolumes, ChecksumOfTheIndependentlyDecompressedFile) {
  const std::string stem = "nucleon_41x41x41_uint8";
  const VolumeHeader header = readVolumeHeader(volumePath(stem));
  EXPECT_EQ(test::sha256Hex(test::gunzipFile(header.data_file)), checksumInComments(header));
}

}  // namespace
}  // namespace svr
