// The readers on small files the tests write themselves: every voxel type in both byte orders,
// in every format and encoding, checked voxel by voxel.
#include "renderers/volume/volume_io.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <ostream>
#include <string>
#include <vector>

#include "volume_test_files.h"

namespace svr {
namespace {

using test::TempDir;

enum class Container {
  kNrrdRaw,
  kNrrdGzip,
  kNhdrRaw,
  kNhdrGzip,
  kMhdRaw,
  kMhdZlib,
  kMhaRaw,
  kMhaZlib,
  kRaw,
  kRawGz
};

std::string toString(Container c) {
  switch (c) {
    case Container::kNrrdRaw:
      return "NrrdRaw";
    case Container::kNrrdGzip:
      return "NrrdGzip";
    case Container::kNhdrRaw:
      return "NhdrRaw";
    case Container::kNhdrGzip:
      return "NhdrGzip";
    case Container::kMhdRaw:
      return "MhdRaw";
    case Container::kMhdZlib:
      return "MhdZlib";
    case Container::kMhaRaw:
      return "MhaRaw";
    case Container::kMhaZlib:
      return "MhaZlib";
    case Container::kRaw:
      return "Raw";
    case Container::kRawGz:
      return "RawGz";
  }
  return "?";
}

constexpr Dims kDims{3, 4, 5};
const glm::dvec3 kSpacing{0.5, 1.25, 2.0};

struct Written {
  std::string path;
  VolumeLoadOptions options;
  std::string format, encoding;
};

// Writes `voxels` (already in the file's byte order) as `container`.
Written writeVolume(const TempDir& dir, Container c, ScalarType type, Endian endian,
                    const std::vector<std::byte>& voxels) {
  Written w;
  const std::string nrrd_head = fmt::format(
      "NRRD0004\n# written by the svr tests\ntype: {}\ndimension: 3\nsizes: 3 4 5\n"
      "spacings: 0.5 1.25 2\nendian: {}\n",
      test::nrrdTypeName(type), svr::toString(endian));
  const std::string meta_head = fmt::format(
      "ObjectType = Image\nNDims = 3\nDimSize = 3 4 5\nElementType = {}\n"
      "ElementSpacing = 0.5 1.25 2\nBinaryData = True\nBinaryDataByteOrderMSB = {}\n",
      test::metaTypeName(type), endian == Endian::kBig ? "True" : "False");
  const auto concat = [](const std::string& text, const std::vector<std::byte>& data) {
    std::vector<std::byte> out = test::bytesOf(text);
    out.insert(out.end(), data.begin(), data.end());
    return out;
  };
  switch (c) {
    case Container::kNrrdRaw:
    case Container::kNrrdGzip: {
      const bool gz = c == Container::kNrrdGzip;
      w.path = dir.path("v.nrrd");
      test::writeFile(w.path, concat(nrrd_head + (gz ? "encoding: gzip\n\n" : "encoding: raw\n\n"),
                                     gz ? test::gzipCompress(voxels) : voxels));
      w.format = "nrrd";
      w.encoding = gz ? "gzip" : "raw";
      break;
    }
    case Container::kNhdrRaw:
    case Container::kNhdrGzip: {
      const bool gz = c == Container::kNhdrGzip;
      w.path = dir.path("v.nhdr");
      const std::string data = gz ? "v.raw.gz" : "v.raw";
      test::writeFile(w.path, nrrd_head + (gz ? "encoding: gzip\n" : "encoding: raw\n") +
                                  "data file: " + data + "\n");
      test::writeFile(dir.path(data), gz ? test::gzipCompress(voxels) : voxels);
      w.format = "nhdr";
      w.encoding = gz ? "gzip" : "raw";
      break;
    }
    case Container::kMhdRaw:
    case Container::kMhdZlib: {
      const bool z = c == Container::kMhdZlib;
      w.path = dir.path("v.mhd");
      const std::vector<std::byte> data = z ? test::zlibCompress(voxels) : voxels;
      test::writeFile(w.path, meta_head +
                                  (z ? fmt::format("CompressedData = True\n"
                                                   "CompressedDataSize = {}\n",
                                                   data.size())
                                     : "CompressedData = False\n") +
                                  "ElementDataFile = " + (z ? "v.zraw" : "v.raw") + "\n");
      test::writeFile(dir.path(z ? "v.zraw" : "v.raw"), data);
      w.format = "mhd";
      w.encoding = z ? "zlib" : "raw";
      break;
    }
    case Container::kMhaRaw:
    case Container::kMhaZlib: {
      const bool z = c == Container::kMhaZlib;
      w.path = dir.path("v.mha");
      // No CompressedDataSize here: the stream runs to the end of the file.
      test::writeFile(w.path, concat(meta_head + (z ? "CompressedData = True\n" : "") +
                                         "ElementDataFile = LOCAL\n",
                                     z ? test::zlibCompress(voxels) : voxels));
      w.format = "mha";
      w.encoding = z ? "zlib" : "raw";
      break;
    }
    case Container::kRaw:
    case Container::kRawGz: {
      const bool gz = c == Container::kRawGz;
      w.path = dir.path(gz ? "v.bin.gz" : "v.bin");
      test::writeFile(w.path, gz ? test::gzipCompress(voxels) : voxels);
      w.options.raw = RawLayout{kDims, type, endian, kSpacing, 0, false};
      w.format = "raw";
      w.encoding = gz ? "gzip" : "raw";
      break;
    }
  }
  return w;
}

struct Case {
  Container container;
  ScalarType type;
  Endian endian;
};

std::string nameOf(const Case& c) {
  return toString(c.container) + "_" + svr::toString(c.type) + "_" + svr::toString(c.endian);
}

// Readable test names in ctest and gtest output.
void PrintTo(const Case& c, std::ostream* os) { *os << nameOf(c); }

std::vector<Case> everyCase() {
  std::vector<Case> cases;
  for (const Container c :
       {Container::kNrrdRaw, Container::kNrrdGzip, Container::kNhdrRaw, Container::kNhdrGzip,
        Container::kMhdRaw, Container::kMhdZlib, Container::kMhaRaw, Container::kMhaZlib,
        Container::kRaw, Container::kRawGz})
    for (const ScalarType t :
         {ScalarType::kUint8, ScalarType::kInt8, ScalarType::kUint16, ScalarType::kInt16,
          ScalarType::kUint32, ScalarType::kInt32, ScalarType::kFloat32, ScalarType::kFloat64})
      for (const Endian e : {Endian::kLittle, Endian::kBig}) cases.push_back({c, t, e});
  return cases;
}

class ReadEveryTypeAndEndianness : public ::testing::TestWithParam<Case> {};

TEST_P(ReadEveryTypeAndEndianness, DimsSpacingTypeValuesAndRange) {
  const auto [container, type, endian] = GetParam();
  const TempDir dir;
  const std::vector<double> values = test::knownValues(type, 60);
  const Written w =
      writeVolume(dir, container, type, endian, test::encodeValues(values, type, endian));

  const VolumeHeader header = readVolumeHeader(w.path, w.options);
  EXPECT_EQ(header.path, w.path);
  EXPECT_EQ(header.format, w.format);
  EXPECT_EQ(header.encoding, w.encoding);
  EXPECT_EQ(header.dims, kDims);
  EXPECT_EQ(header.type, type);
  EXPECT_EQ(header.spacing, kSpacing);
  EXPECT_EQ(header.data_bytes, 60 * bytesPerVoxel(type));
  if (bytesPerVoxel(type) > 1) {
    EXPECT_EQ(header.endian, endian);
  }

  const Volume volume = loadVolume(w.path, w.options);
  EXPECT_EQ(volume.dims(), kDims);
  EXPECT_EQ(volume.spacing(), kSpacing);
  EXPECT_EQ(volume.type(), type);
  EXPECT_EQ(volume.source(), w.path);
  ASSERT_EQ(volume.voxelCount(), values.size());
  for (std::size_t i = 0; i < values.size(); ++i)
    ASSERT_EQ(volume.value(i), values[i]) << "voxel " << i;
  EXPECT_EQ(volume.value(2, 3, 4), values.back());
  EXPECT_EQ(volume.value(1, 0, 0), values[1]);
  EXPECT_EQ(volume.value(0, 1, 0), values[3]);
  EXPECT_EQ(volume.value(0, 0, 1), values[12]);
  const auto [lo, hi] = std::minmax_element(values.begin(), values.end());
  EXPECT_EQ(volume.valueRange().first, *lo);
  EXPECT_EQ(volume.valueRange().second, *hi);

  // A coarse lattice (work estimates): the first, last and evenly spread voxels of each axis,
  // read with seeks or out of the stream, with the spacing that keeps the grid's extent.
  VolumeLoadOptions coarse = w.options;
  coarse.lattice = Dims{2, 2, 3};
  const Volume lattice = loadVolume(w.path, coarse);
  ASSERT_EQ(lattice.dims(), (Dims{2, 2, 3}));
  for (int a = 0; a < 3; ++a)
    EXPECT_DOUBLE_EQ(lattice.extent()[a], volume.extent()[a]) << "axis " << a;
  const int xs[] = {0, 2}, ys[] = {0, 3}, zs[] = {0, 2, 4};  // of 3 × 4 × 5
  for (int z = 0; z < 3; ++z)
    for (int y = 0; y < 2; ++y)
      for (int x = 0; x < 2; ++x)
        ASSERT_EQ(lattice.value(x, y, z), volume.value(xs[x], ys[y], zs[z]))
            << "lattice voxel " << x << ", " << y << ", " << z;
  const Volume same = latticeOf(volume, {2, 2, 3});
  ASSERT_EQ(same.data().size(), lattice.data().size());
  EXPECT_TRUE(std::equal(same.data().begin(), same.data().end(), lattice.data().begin()));
}

INSTANTIATE_TEST_SUITE_P(VolumeIo, ReadEveryTypeAndEndianness, ::testing::ValuesIn(everyCase()),
                         [](const auto& info) { return nameOf(info.param); });

// uint16 values 0, 1, …, 59 as big-endian bytes, for the layout tests below.
std::vector<std::byte> rampBigEndian() {
  std::vector<double> v(60);
  for (std::size_t i = 0; i < v.size(); ++i) v[i] = static_cast<double>(i);
  return test::encodeValues(v, ScalarType::kUint16, Endian::kBig);
}

void expectRamp(const Volume& volume) {
  ASSERT_EQ(volume.voxelCount(), 60u);
  for (std::size_t i = 0; i < 60; ++i) ASSERT_EQ(volume.value(i), static_cast<double>(i));
}

TEST(VolumeIo, NrrdSpaceDirectionsGiveSpacingAsTheirLengths) {
  const TempDir dir;
  test::writeFile(dir.path("d.nhdr"),
                  "NRRD0005\ntype: uint16\ndimension: 3\nsizes: 3 4 5\n"
                  "space: right-anterior-superior\n"
                  "space directions: (0,0,1.5) (0,3,4) (-2,0,0)\n"
                  "space origin: (10,20,30)\nendian: big\nencoding: raw\ndata file: d.raw\n");
  test::writeFile(dir.path("d.raw"), rampBigEndian());
  const Volume volume = loadVolume(dir.path("d.nhdr"));
  EXPECT_EQ(volume.spacing(), glm::dvec3(1.5, 5.0, 2.0));
  expectRamp(volume);
}

TEST(VolumeIo, NrrdTypeSpellingsAndDefaultSpacing) {
  const TempDir dir;
  for (const std::string spelling : {"uint16", "unsigned short int", "uint16_t", "ushort"}) {
    test::writeFile(dir.path("t.nhdr"), "NRRD0004\ntype: " + spelling +
                                            "\ndimension: 3\nsizes: 3 4 5\nendian: big\n"
                                            "encoding: raw\ndata file: t.raw\n");
    test::writeFile(dir.path("t.raw"), rampBigEndian());
    const Volume volume = loadVolume(dir.path("t.nhdr"));
    EXPECT_EQ(volume.type(), ScalarType::kUint16) << spelling;
    EXPECT_EQ(volume.spacing(), glm::dvec3(1.0)) << spelling;
    expectRamp(volume);
  }
}

TEST(VolumeIo, NrrdSkipsLinesAndBytesBeforeTheVoxels) {
  const TempDir dir;
  const std::string head = "NRRD0004\ntype: uint16\ndimension: 3\nsizes: 3 4 5\nendian: big\n";
  std::vector<std::byte> junk = test::bytesOf("line one\nline two\n0123456789");
  std::vector<std::byte> data = junk;
  const std::vector<std::byte> ramp = rampBigEndian();
  data.insert(data.end(), ramp.begin(), ramp.end());
  test::writeFile(dir.path("s.raw"), data);
  test::writeFile(dir.path("lines.nhdr"),
                  head + "encoding: raw\nline skip: 2\nbyte skip: 10\ndata file: s.raw\n");
  expectRamp(loadVolume(dir.path("lines.nhdr")));
  test::writeFile(dir.path("end.nhdr"), head + "encoding: raw\nbyte skip: -1\ndata file: s.raw\n");
  expectRamp(loadVolume(dir.path("end.nhdr")));
  // For gzip, the byte skip counts decompressed bytes.
  test::writeFile(dir.path("s.raw.gz"),
                  test::gzipCompress(std::vector<std::byte>(data.begin() + 18, data.end())));
  test::writeFile(dir.path("gz.nhdr"),
                  head + "encoding: gzip\nbyte skip: 10\ndata file: s.raw.gz\n");
  expectRamp(loadVolume(dir.path("gz.nhdr")));
}

TEST(VolumeIo, NrrdHeaderKeepsCommentsAndNamesTheDataFile) {
  const TempDir dir;
  test::writeFile(dir.path("c.nhdr"),
                  "NRRD0004\n# first comment\n#second\ntype: uint8\ndimension: 3\n"
                  "sizes: 2 2 2\nencoding: raw\nname:=value\ndata file: ./c.raw\n");
  test::writeFile(dir.path("c.raw"), std::vector<std::byte>(8, std::byte{7}));
  const VolumeHeader header = readVolumeHeader(dir.path("c.nhdr"));
  EXPECT_EQ(header.comments, (std::vector<std::string>{"first comment", "second"}));
  EXPECT_EQ(std::filesystem::path(header.data_file).lexically_normal(),
            std::filesystem::path(dir.path("c.raw")).lexically_normal());
  EXPECT_EQ(header.endian, nativeEndian());  // one byte per voxel: no byte order
  EXPECT_EQ(loadVolume(dir.path("c.nhdr")).valueRange(), std::make_pair(7.0, 7.0));
}

TEST(VolumeIo, NrrdAbsoluteDataFileInsideTheFolderIsAllowed) {
  const TempDir dir;
  test::writeFile(dir.path("a.nhdr"),
                  "NRRD0004\ntype: uint16\ndimension: 3\nsizes: 3 4 5\n"
                  "endian: big\nencoding: raw\ndata file: " +
                      dir.path("a.raw") + "\n");
  test::writeFile(dir.path("a.raw"), rampBigEndian());
  expectRamp(loadVolume(dir.path("a.nhdr")));
}

TEST(VolumeIo, ConcatenatedGzipMembersReadAsOneStream) {
  const TempDir dir;
  const std::vector<std::byte> ramp = rampBigEndian();
  std::vector<std::byte> gz =
      test::gzipCompress(std::vector<std::byte>(ramp.begin(), ramp.begin() + 50));
  const std::vector<std::byte> tail =
      test::gzipCompress(std::vector<std::byte>(ramp.begin() + 50, ramp.end()));
  gz.insert(gz.end(), tail.begin(), tail.end());
  test::writeFile(dir.path("m.raw.gz"), gz);
  test::writeFile(dir.path("m.nhdr"),
                  "NRRD0004\ntype: uint16\ndimension: 3\nsizes: 3 4 5\n"
                  "endian: big\nencoding: gzip\ndata file: m.raw.gz\n");
  expectRamp(loadVolume(dir.path("m.nhdr")));
}

TEST(VolumeIo, MetaImageVariants) {
  const TempDir dir;
  const std::vector<std::byte> ramp = rampBigEndian();
  std::vector<std::byte> with_header = test::bytesOf("HEADERHEADER");
  with_header.insert(with_header.end(), ramp.begin(), ramp.end());
  test::writeFile(dir.path("h.raw"), with_header);
  // ElementSize stands in for ElementSpacing; ElementByteOrderMSB for BinaryDataByteOrderMSB;
  // unknown keys are ignored; CRLF line ends are fine.
  test::writeFile(dir.path("h.mhd"),
                  "ObjectType = Image\r\nNDims = 3\r\nOffset = 1 2 3\r\n"
                  "TransformMatrix = 1 0 0 0 1 0 0 0 1\r\nAnatomicalOrientation = RAI\r\n"
                  "DimSize = 3 4 5\r\nElementSize = 0.25 0.5 4\r\nElementType = MET_USHORT\r\n"
                  "ElementByteOrderMSB = True\r\nHeaderSize = 12\r\nElementNumberOfChannels = 1\r\n"
                  "Comment = a test volume\r\nElementDataFile = h.raw\r\n");
  const VolumeHeader header = readVolumeHeader(dir.path("h.mhd"));
  EXPECT_EQ(header.spacing, glm::dvec3(0.25, 0.5, 4));
  EXPECT_EQ(header.endian, Endian::kBig);
  EXPECT_EQ(header.comments, std::vector<std::string>{"a test volume"});
  expectRamp(loadVolume(dir.path("h.mhd")));
  // HeaderSize = -1: the voxels are the last bytes of the file.
  test::writeFile(dir.path("e.mhd"),
                  "NDims = 3\nDimSize = 3 4 5\nElementType = MET_USHORT\n"
                  "BinaryDataByteOrderMSB = True\nHeaderSize = -1\n"
                  "ElementDataFile = h.raw\n");
  expectRamp(loadVolume(dir.path("e.mhd")));
}

TEST(VolumeIo, RawHeaderBytesAreSkipped) {
  const TempDir dir;
  const std::vector<std::byte> ramp = rampBigEndian();
  std::vector<std::byte> data(100 + ramp.size(), std::byte{0xAB});
  std::copy(ramp.begin(), ramp.end(), data.begin() + 100);
  VolumeLoadOptions options;
  options.raw = RawLayout{kDims, ScalarType::kUint16, Endian::kBig, glm::dvec3(1), 100, false};
  test::writeFile(dir.path("r.img"), data);
  expectRamp(loadVolume(dir.path("r.img"), options));
  // gzip by flag, whatever the name; the skip counts decompressed bytes.
  test::writeFile(dir.path("r.dat"), test::gzipCompress(data));
  options.raw->gzip = true;
  const VolumeHeader header = readVolumeHeader(dir.path("r.dat"), options);
  EXPECT_EQ(header.encoding, "gzip");
  expectRamp(loadVolume(dir.path("r.dat"), options));
}

TEST(VolumeIo, VolumesAreCentredAtTheOrigin) {
  const TempDir dir;
  const Written w = writeVolume(dir, Container::kRaw, ScalarType::kUint8, Endian::kLittle,
                                std::vector<std::byte>(60));
  const Volume volume = loadVolume(w.path, w.options);
  EXPECT_EQ(volume.worldPosition(0, 0, 0), -0.5 * volume.extent());
  EXPECT_EQ(volume.worldPosition(2, 3, 4), 0.5 * volume.extent());
  EXPECT_EQ(volume.extent(), glm::dvec3(1.0, 3.75, 8.0));
}

}  // namespace
}  // namespace svr
