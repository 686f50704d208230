#include "renderers/volume/memory_budget.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "base/error.h"
#include "volume_test_files.h"

namespace svr {
namespace {

using test::errorOf;
using ::testing::HasSubstr;

TEST(VolumeMemoryBudget, DefaultIsWhatTheMachineHasFree) {
  const std::uint64_t budget = defaultMemoryBudget();
  EXPECT_GT(budget, std::uint64_t{16} << 20);  // any machine that builds this has 16 MiB free
}

TEST(VolumeMemoryBudget, CheckNamesTheVolumeTheNeedAndTheBudget) {
  EXPECT_NO_THROW(checkMemoryBudget(100, 100, "x"));
  EXPECT_EQ(errorOf([] {
              checkMemoryBudget(std::uint64_t{512} << 20, std::uint64_t{100} << 20,
                                "big.nhdr: 512×512×512 float32");
            }),
            "big.nhdr: 512×512×512 float32 needs 512.0 MiB, over the memory budget of 100.0 MiB "
            "(set --memory-budget to raise it)");
}

TEST(VolumeMemoryBudget, VolumeBytesCheckEveryDimensionAndOverflow) {
  EXPECT_EQ(volumeBytes({256, 256, 128}, ScalarType::kUint8, "f"), 8388608u);
  // 4·(2³¹ − 1)² = 2⁶⁴ − 2³⁴ + 4 still fits; twice that does not.
  EXPECT_EQ(volumeBytes({2147483647, 2147483647, 1}, ScalarType::kFloat32, "f"),
            4ull * 2147483647ull * 2147483647ull);
  EXPECT_EQ(errorOf([] {
              volumeBytes({4, 0, 4}, ScalarType::kUint8, "f.nhdr");
            }),
            "f.nhdr: dimension y is 0; every dimension must be ≥ 1");
  EXPECT_EQ(errorOf([] {
              volumeBytes({4, 4, -1}, ScalarType::kUint8, "f.nhdr");
            }),
            "f.nhdr: dimension z is -1; every dimension must be ≥ 1");
  EXPECT_EQ(errorOf([] {
              volumeBytes({1ll << 31, 1, 1}, ScalarType::kUint8, "f.nhdr");
            }),
            "f.nhdr: dimension x is 2147483648, above the largest supported (2147483647)");
  EXPECT_EQ(errorOf([] {
              volumeBytes({2147483647, 2147483647, 1}, ScalarType::kFloat64, "f.nhdr");
            }),
            "f.nhdr: 2147483647×2147483647×1 float64 does not fit in 64 bits of bytes");
}

TEST(VolumeMemoryBudget, FormatBytes) {
  EXPECT_EQ(formatBytes(0), "0 B");
  EXPECT_EQ(formatBytes(1023), "1023 B");
  EXPECT_EQ(formatBytes(1024), "1.0 KiB");
  EXPECT_EQ(formatBytes(68921), "67.3 KiB");
  EXPECT_EQ(formatBytes(std::uint64_t{512} << 20), "512.0 MiB");
  EXPECT_EQ(formatBytes(std::uint64_t{3} << 30), "3.0 GiB");
  EXPECT_EQ(formatBytes(~std::uint64_t{0}), "16.0 EiB");
}

TEST(VolumeMemoryBudget, ParseByteSize) {
  EXPECT_EQ(parseByteSize("1073741824", "--memory-budget"), 1073741824u);
  EXPECT_EQ(parseByteSize("512M", "--memory-budget"), std::uint64_t{512} << 20);
  EXPECT_EQ(parseByteSize("2G", "--memory-budget"), std::uint64_t{2} << 30);
  EXPECT_EQ(parseByteSize("2g", "--memory-budget"), std::uint64_t{2} << 30);
  EXPECT_EQ(parseByteSize("1.5GiB", "--memory-budget"), std::uint64_t{3} << 29);
  EXPECT_EQ(parseByteSize("64KB", "--memory-budget"), 65536u);
  EXPECT_EQ(parseByteSize("1T", "--memory-budget"), std::uint64_t{1} << 40);
  EXPECT_EQ(parseByteSize("100B", "--memory-budget"), 100u);
  for (const char* bad : {"", "G", "-1G", "0", "2X", "2GG", "nan", "2 G", "1e30"})
    EXPECT_THAT(errorOf([&] { parseByteSize(bad, "--memory-budget"); }),
                HasSubstr(std::string("--memory-budget: '") + bad + "'"))
        << bad;
}

}  // namespace
}  // namespace svr
