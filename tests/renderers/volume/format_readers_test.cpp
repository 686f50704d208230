// NIfTI, DICOM and TIFF readers against files made by independent tools (nibabel, pydicom,
// Pillow + tiffcp: tests/data/formats/make_formats.py) and the same voxels as NRRD: identical
// voxels, spacing and world box. Every file holds voxel (i, j, k) = i + 10 j + 100 k − 50 in RAS
// order once read, however it stores it (flipped, permuted, rescaled).
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "base/error.h"
#include "renderers/volume/volume_brick.h"
#include "renderers/volume/volume_io.h"

namespace svr {
namespace {

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

TEST(FormatReaders, TiffMultiPageAndNumberedFolderMatchNrrd) {
  const Volume nrrd = loadVolume(kDir + "stack.nrrd");
  expectSameVolume(loadVolume(kDir + "stack.tif"), nrrd);
  expectSameVolume(loadVolume(kDir + "numbered"), nrrd);
  expectTheGrid(nrrd, 1, 50);
  EXPECT_EQ(readVolumeHeader(kDir + "stack.tif").encoding, "LZW");
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
