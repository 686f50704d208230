// NIfTI, DICOM and TIFF readers against files made by independent tools (nibabel, pydicom,
// Pillow + tiffcp: tests/data/formats/make_formats.py) and the same voxels as NRRD: identical
// voxels, spacing and world box. Every file holds voxel (i, j, k) = i + 10 j + 100 k − 50 in RAS
// order once read, however it stores it (flipped, permuted, rescaled).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "base/error.h"
#include "renderers/volume/volume_brick.h"
#include "renderers/volume/volume_io.h"

namespace svr {
namespace {

namespace fs = std::filesystem;

const std::string kDir = std::string(SVR_SOURCE_DIR) + "/tests/data/formats/";

void expectSameVolume(const Volume& got, const Volume& want) {
  ASSERT_EQ(got.dims(), want.dims());
  EXPECT_EQ(got.spacing(), want.spacing());
  EXPECT_EQ(got.extent(), want.extent());
  EXPECT_EQ(got.type(), want.type());
  for (std::size_t i = 0; i < want.voxelCount(); ++i)
    ASSERT_EQ(got.value(i), want.value(i)) << "voxel " << i;
}

// The grid's own formula, so that a reader that matched a wrong NRRD would still fail.
void expectTheGrid(const Volume& v, double scale, double offset) {
  ASSERT_EQ(v.dims(), (Dims{5, 4, 3}));
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 5; ++i)
        ASSERT_EQ(v.value(i, j, k), scale * (i + 10 * j + 100 * k - 50) + offset)
            << i << "," << j << "," << k;
}

TEST(FormatReaders, NiftiInRasOrderMatchesNrrd) {
  const Volume nifti = loadVolume(kDir + "ras.nii");
  expectSameVolume(nifti, loadVolume(kDir + "ras.nrrd"));
  expectTheGrid(nifti, 1, 0);
  EXPECT_EQ(readVolumeHeader(kDir + "ras.nii").format, "nifti-1");
}

TEST(FormatReaders, Nifti2StoredLpsAndGzippedIsTurnedToRas) {
  const Volume nifti = loadVolume(kDir + "lps.nii.gz");
  expectSameVolume(nifti, loadVolume(kDir + "ras.nrrd"));
  const VolumeHeader h = readVolumeHeader(kDir + "lps.nii.gz");
  EXPECT_EQ(h.format, "nifti-2");
  EXPECT_EQ(h.encoding, "gzip");
  EXPECT_NE(h.orientation.find("L, P, S"), std::string::npos) << h.orientation;
}

TEST(FormatReaders, NiftiPermutedAxesAndSclSlopeInter) {
  // Stored [k, i, j] with qform axes S, R, A, and values (v + 10) / 2.
  const Volume nifti = loadVolume(kDir + "ski_scaled.nii");
  expectSameVolume(nifti, loadVolume(kDir + "scaled.nrrd"));
  expectTheGrid(nifti, 2, -10);
}

TEST(FormatReaders, DicomSeriesSortedByPositionRescaledAndTurnedToRas) {
  const Volume dicom = loadVolume(kDir + "series");
  expectSameVolume(dicom, loadVolume(kDir + "series.nrrd"));
  // LPS rows and columns: RAS x and y run backwards through the stored grid.
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 5; ++i)
        ASSERT_EQ(dicom.value(i, j, k), (4 - i) + 10 * (3 - j) + 100 * k - 50);
  EXPECT_EQ(dicom.spacing(), glm::dvec3(0.5, 0.75, 2.5));
}

TEST(FormatReaders, DicomSeriesThatAreNotOneGridAreRefused) {
  const auto message = [](const std::string& folder) {
    try {
      loadVolume(kDir + folder);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message("mixed").find("mixes series"), std::string::npos) << message("mixed");
  EXPECT_NE(message("gap").find("2 slices are missing"), std::string::npos) << message("gap");
  EXPECT_NE(message("tilt").find("tilted gantry"), std::string::npos) << message("tilt");
}

// The same series written by pydicom in the other framings: implicit VR with nested sequences
// (items of defined and undefined length, delimiters), explicit VR big endian, and RLE pixels
// (encapsulated: fragments, then a delimiter). GDCM decodes them; svr's walk must pass them.
TEST(FormatReaders, DicomSeriesInEveryFramingMatchNrrd) {
  const Volume want = loadVolume(kDir + "series.nrrd");
  for (const char* folder : {"series_implicit", "series_big_endian", "series_rle"}) {
    SCOPED_TRACE(folder);
    expectSameVolume(loadVolume(kDir + folder), want);
  }
}

// A good slice with `length` bytes at the offset where `marker` is first found (plus `skip`)
// replaced by `bytes`, alone in a folder: the error loading it.
std::string dicomError(const std::string& slice, const std::string& marker, std::size_t skip,
                       const std::string& bytes, std::size_t length) {
  std::ifstream in(kDir + slice, std::ios::binary);
  std::string file((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::size_t at = file.find(marker);
  if (at == std::string::npos) return "marker not found";
  file.replace(at + skip, length, bytes);
  const fs::path dir = fs::temp_directory_path() / "svr_dicom_framing";
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream(dir / "IM0000.dcm", std::ios::binary) << file;
  try {
    loadVolume(dir.string());
  } catch (const Error& e) {
    return e.what();
  }
  return "no error";
}

// Faults in a file's framing are refused before GDCM reads it (GDCM would allocate what a
// length says, or assert), naming the element and the byte.
TEST(FormatReaders, DicomFramingFaultsAreRefusedBeforeGdcm) {
  const auto has = [](const std::string& message, const std::string& part) {
    return message.find(part) != std::string::npos;
  };
  // The bytes of tags and lengths, as ""s literals: they hold NULs.
  using namespace std::string_literals;
  const std::string item = "\xfe\xff\x00\xe0"s, pixel_data = "\xe0\x7f\x10\x00"s;
  // An item of the implicit file's sequence whose length runs past the file.
  const std::string past = dicomError("series_implicit/IM0000.dcm", item, 4,
                                      "\x00\x00\x00\x40"s, 4);
  EXPECT_TRUE(has(past, "element (fffe,e000) has length 1073741824, past its container's end"))
      << past;
  // Explicit VR: an unknown VR, PixelSpacing's DS made US (GDCM asserts on that), and native
  // pixel data given an undefined length.
  const std::string vr = dicomError("series/IM0001.dcm", pixel_data, 4, "ZZ", 2);
  EXPECT_TRUE(has(vr, "element (7fe0,0010) has VR 5a 5a, not one of PS3.5's")) << vr;
  const std::string spacing = dicomError("series/IM0001.dcm", "\x28\x00\x30\x00"s + "DS", 4, "US", 2);
  EXPECT_TRUE(has(spacing, "element (0028,0030) has VR US where DICOM's data dictionary says DS"))
      << spacing;
  const std::string undefined = dicomError("series/IM0001.dcm", pixel_data, 8,
                                           "\xff\xff\xff\xff"s, 4);
  EXPECT_TRUE(has(undefined, "where the encapsulated pixel data expects an item")) << undefined;
  // Big endian read as such: the pixel data's length (big endian 40) made 40 × 2^24.
  const std::string big = dicomError("series_big_endian/IM0000.dcm", "\x7f\xe0\x00\x10"s + "OW", 8,
                                     "\x28\x00\x00\x28"s, 4);
  EXPECT_TRUE(has(big, "element (7fe0,0010) OW has length 671088680, past its container's end"))
      << big;
  // A sequence delimiter given a length; the file cut inside its last element.
  const std::string delimiter = dicomError("series_rle/IM0000.dcm", "\xfe\xff\xdd\xe0"s, 4,
                                           "\x01\x00\x00\x00"s, 4);
  EXPECT_TRUE(has(delimiter, "delimiter (fffe,e0dd) has length 1")) << delimiter;
  const std::string cut = dicomError("series/IM0001.dcm", pixel_data, 20, "", 1000);
  EXPECT_TRUE(has(cut, "(7fe0,0010) OW has length 40, past its container's end")) << cut;
}

TEST(FormatReaders, TiffMultiPageAndNumberedFolderMatchNrrd) {
  const Volume nrrd = loadVolume(kDir + "stack.nrrd");
  expectSameVolume(loadVolume(kDir + "stack.tif"), nrrd);
  expectSameVolume(loadVolume(kDir + "numbered"), nrrd);
  expectTheGrid(nrrd, 1, 50);
  EXPECT_EQ(readVolumeHeader(kDir + "stack.tif").encoding, "LZW");
}

// Tiles are read as strips are; a tile's buffer (16 × 16 uint16 = 512 bytes, larger than the
// 5 × 4 page) must fit the memory budget like the volume (120 bytes) does.
TEST(FormatReaders, TiledTiffMatchesAndItsTilesCountInTheBudget) {
  expectSameVolume(loadVolume(kDir + "stack_tiled.tif"), loadVolume(kDir + "stack.nrrd"));
  VolumeLoadOptions tight;
  tight.memory_budget = 200;
  try {
    loadVolume(kDir + "stack_tiled.tif", tight);
    ADD_FAILURE() << "a tile over the budget was read";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("a tile of 16 × 16 uint16 needs"), std::string::npos)
        << e.what();
  }
}

TEST(FormatReaders, TiffSpacingComesFromTheCaller) {
  VolumeLoadOptions options;
  options.spacing = glm::dvec3(0.5, 0.25, 2.0);
  EXPECT_EQ(loadVolume(kDir + "stack.tif", options).spacing(), *options.spacing);
  EXPECT_THROW(loadVolume(kDir + "ras.nii", options), Error);  // NIfTI states its own
}

TEST(FormatReaders, FloatTiffPage) {
  const Volume v = loadVolume(kDir + "float.tif");
  ASSERT_EQ(v.dims(), (Dims{5, 4, 1}));
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 5; ++i) ASSERT_EQ(v.value(i, j, 0), (i + 10 * j - 50) / 8.0);
}

// A distributed render's brick and a work estimate's lattice read through the reorientation:
// the same voxels as cutting them from the whole volume.
TEST(FormatReaders, BricksAndLatticesOfReorientedFilesMatchTheWhole) {
  for (const std::string file : {"lps.nii.gz", "ski_scaled.nii", "series", "stack.tif"}) {
    SCOPED_TRACE(file);
    const Volume whole = loadVolume(kDir + file);
    VolumeLoadOptions options;
    const VoxelBox box{{1, 0, 1}, {4, 3, 3}};
    options.brick = [&](const Dims& dims) {
      EXPECT_EQ(dims, whole.dims());
      VolumeBrick brick;
      brick.whole = dims;
      brick.own = brick.stored = box;
      return brick;
    };
    const Volume brick = loadVolume(kDir + file, options);
    ASSERT_EQ(brick.dims(), box.size());
    for (int z = 0; z < 2; ++z)
      for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 3; ++x)
          ASSERT_EQ(brick.value(x, y, z), whole.value(x + 1, y, z + 1));
    VolumeLoadOptions coarse;
    coarse.lattice = Dims{3, 2, 2};
    const Volume lattice = loadVolume(kDir + file, coarse);
    const LatticeIndices at = latticeIndices(whole.dims(), *coarse.lattice);
    ASSERT_EQ(lattice.dims(), (Dims{3, 2, 2}));
    for (int z = 0; z < 2; ++z)
      for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 3; ++x)
          ASSERT_EQ(lattice.value(x, y, z), whole.value(at[0][x], at[1][y], at[2][z]));
  }
}

}  // namespace
}  // namespace svr
