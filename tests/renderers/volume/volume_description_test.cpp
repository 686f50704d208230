#include "renderers/volume/volume_description.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <sstream>

#include "renderers/volume/procedural_volume.h"
#include "renderers/volume/volume_io.h"

namespace svr {
namespace {

using ::testing::HasSubstr;

TEST(VolumeDescription, NamesDimsTypeRangeSpacingMemoryAndHistogram) {
  const std::string path = std::string(SVR_TEST_DATA_DIR) + "/volumes/nucleon_41x41x41_uint8.nhdr";
  const std::string text = describeVolume(readVolumeHeader(path), loadVolume(path));
  EXPECT_THAT(text, HasSubstr(path + "\n"));
  EXPECT_THAT(text, HasSubstr("dims        41 × 41 × 41  (68921 voxels)"));
  EXPECT_THAT(text, HasSubstr("type        uint8, one byte per voxel"));
  EXPECT_THAT(text, HasSubstr("encoding    gzip"));
  EXPECT_THAT(text, HasSubstr("spacing     1 × 1 × 1"));
  EXPECT_THAT(text, HasSubstr("extent      40 × 40 × 40 world units, from (-20, -20, -20) to "
                              "(20, 20, 20)"));
  EXPECT_THAT(text, HasSubstr("range       0 … 249"));
  EXPECT_THAT(text, HasSubstr("memory      67.3 KiB as stored, 269.2 KiB as float32"));
  EXPECT_THAT(text, HasSubstr("histogram   16 bins over [0, 249]"));
  EXPECT_THAT(text, HasSubstr("Nucleon: two-body distribution"));  // a header comment
  // 16 bars whose counts add up to every voxel; the fullest bin has the longest bar.
  std::istringstream lines(text);
  std::string line;
  std::uint64_t total = 0;
  int bars = 0;
  std::size_t longest = 0;
  while (std::getline(lines, line)) {
    if (line.rfind("    [", 0) != 0) continue;
    ++bars;
    total += std::stoull(line.substr(line.find_last_of(' ') + 1));
    longest =
        std::max(longest, static_cast<std::size_t>(std::count(line.begin(), line.end(), '#')));
  }
  EXPECT_EQ(bars, 16);
  EXPECT_EQ(total, 68921u);
  EXPECT_EQ(longest, 40u);
}

TEST(VolumeDescription, MultiByteTypesGiveTheirByteOrderAndConstantVolumesOneBin) {
  VolumeHeader header;
  header.path = "box";
  header.format = "raw";
  header.encoding = "raw";
  header.data_file = "box";
  header.endian = Endian::kBig;
  const Volume volume = boxVolume({4, 4, 4}, glm::dvec3(2), glm::dvec3(10));  // all ones
  const std::string text = describeVolume(header, volume);
  EXPECT_THAT(text, HasSubstr("type        float32, big-endian in the file"));
  EXPECT_THAT(text, HasSubstr("range       1 … 1"));
  EXPECT_THAT(text, HasSubstr("histogram   1 bins over [1, 1]"));
  EXPECT_THAT(text, HasSubstr("memory      256 B as stored, 256 B as float32"));
}

}  // namespace
}  // namespace svr
