// Bad input to the readers: every case is an svr::Error whose message names the file and the
// specific problem; nothing crashes, hangs or allocates what a header merely claims.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <random>
#include <string>

#include "renderers/volume/volume_io.h"
#include "base/error.h"
#include "volume_test_files.h"

namespace svr {
namespace {

using test::errorOf;
using test::TempDir;
using ::testing::AllOf;
using ::testing::HasSubstr;

const std::string kNrrdHead = "NRRD0004\ntype: uint8\ndimension: 3\n";

// The message of loading `path`, which must name the file.
std::string loadError(const std::string& path, const VolumeLoadOptions& options = {}) {
  const std::string message = errorOf([&] { loadVolume(path, options); });
  EXPECT_THAT(message, HasSubstr(path));
  return message;
}

// A detached NRRD header `name` with these extra lines, and an 8-byte data file.
std::string nhdr(const TempDir& dir, const std::string& name, const std::string& lines) {
  test::writeFile(dir.path("eight.raw"), std::vector<std::byte>(8));
  test::writeFile(dir.path(name), kNrrdHead + lines);
  return dir.path(name);
}

std::string mhd(const TempDir& dir, const std::string& name, const std::string& text) {
  test::writeFile(dir.path("eight.raw"), std::vector<std::byte>(8));
  test::writeFile(dir.path(name), text);
  return dir.path(name);
}

const std::string kMhdHead =
    "ObjectType = Image\nNDims = 3\nDimSize = 2 2 2\n"
    "ElementType = MET_UCHAR\n";

TEST(VolumeIoErrors, MissingFilesAndFolders) {
  const TempDir dir;
  EXPECT_EQ(errorOf([] { loadVolume("/nonexistent/x.nhdr"); }),
            "/nonexistent/x.nhdr: no such file");
  EXPECT_EQ(errorOf([] { readVolumeHeader("/nonexistent/x.mhd"); }),
            "/nonexistent/x.mhd: no such file");
  std::filesystem::create_directory(dir.path("folder.nrrd"));
  EXPECT_THAT(loadError(dir.path("folder.nrrd")), HasSubstr("is a folder"));
  test::writeFile(dir.path("v.xyz"), "hello");
  EXPECT_THAT(loadError(dir.path("v.xyz")),
              AllOf(HasSubstr("unknown volume format '.xyz'"), HasSubstr("--raw-dims")));
}

TEST(VolumeIoErrors, DataFileMissingOutsideOrSeveral) {
  const TempDir dir, other;
  EXPECT_THAT(loadError(nhdr(dir, "m.nhdr", "sizes: 2 2 2\nencoding: raw\ndata file: gone.raw\n")),
              HasSubstr("data file 'gone.raw' does not exist"));
  EXPECT_THAT(
      loadError(nhdr(dir, "d.nhdr", "sizes: 2 2 2\nencoding: raw\ndata file: ../x/eight.raw\n")),
      HasSubstr("data file '../x/eight.raw' has a '..' component"));
  test::writeFile(other.path("o.raw"), std::vector<std::byte>(8));
  EXPECT_THAT(
      loadError(nhdr(dir, "a.nhdr",
                     "sizes: 2 2 2\nencoding: raw\ndata file: " + other.path("o.raw") + "\n")),
      HasSubstr("is outside the header's folder"));
  EXPECT_THAT(loadError(nhdr(dir, "l.nhdr",
                             "sizes: 2 2 2\nencoding: raw\ndata file: LIST\n"
                             "eight.raw\n")),
              HasSubstr("names several files"));
  EXPECT_THAT(
      loadError(nhdr(dir, "f.nhdr", "sizes: 2 2 2\nencoding: raw\ndata file: e%d.raw 1 2 1\n")),
      HasSubstr("names several files"));
  EXPECT_THAT(loadError(mhd(dir, "m.mhd", kMhdHead + "ElementDataFile = nothere.raw\n")),
              HasSubstr("ElementDataFile 'nothere.raw' does not exist"));
  EXPECT_THAT(loadError(mhd(dir, "d.mhd", kMhdHead + "ElementDataFile = ../eight.raw\n")),
              HasSubstr("ElementDataFile '../eight.raw' has a '..' component"));
  EXPECT_THAT(loadError(mhd(dir, "s.mhd", kMhdHead + "ElementDataFile = s%03d.raw 1 5 1\n")),
              HasSubstr("names several files"));
}

TEST(VolumeIoErrors, HeaderAndDataSizeDisagree) {
  const TempDir dir;
  test::writeFile(dir.path("hundred.raw"), std::vector<std::byte>(100));
  const std::string big = dir.path("big.nhdr");
  test::writeFile(big, kNrrdHead + "sizes: 256 256 128\nencoding: raw\ndata file: hundred.raw\n");
  const std::string expected = "header says 256×256×128 uint8 = 8388608 bytes but the data file '" +
                               dir.path("hundred.raw") + "' holds 100 bytes";
  EXPECT_THAT(loadError(big), HasSubstr(expected));
  EXPECT_THAT(errorOf([&] { readVolumeHeader(big); }), HasSubstr(expected));
  EXPECT_THAT(
      loadError(nhdr(dir, "small.nhdr", "sizes: 2 2 2\nencoding: raw\ndata file: hundred.raw\n")),
      HasSubstr("2×2×2 uint8 = 8 bytes but the data file"));
  // Attached: the voxels after the header are 4 bytes short.
  test::writeFile(dir.path("att.nrrd"), kNrrdHead + "sizes: 2 2 2\nencoding: raw\n\n1234");
  EXPECT_THAT(loadError(dir.path("att.nrrd")),
              AllOf(HasSubstr("= 8 bytes but the data file"), HasSubstr("holds 4 bytes after")));
  EXPECT_THAT(loadError(mhd(dir, "s.mhd",
                            "NDims = 3\nDimSize = 4 4 4\nElementType = MET_UCHAR\n"
                            "ElementDataFile = eight.raw\n")),
              HasSubstr("header says 4×4×4 uint8 = 64 bytes but the data file"));
  VolumeLoadOptions raw;
  raw.raw = RawLayout{{10, 10, 2}, ScalarType::kUint8};
  EXPECT_THAT(loadError(dir.path("hundred.raw"), raw),
              HasSubstr("the raw layout says 10×10×2 uint8 = 200 bytes but the data file"));
  raw.raw->header_bytes = 1;
  raw.raw->dims = {10, 10, 1};
  EXPECT_THAT(loadError(dir.path("hundred.raw"), raw),
              HasSubstr("holds 99 bytes after the first 1"));
}

TEST(VolumeIoErrors, TruncatedCorruptOrLongCompressedStreams) {
  const TempDir dir;
  std::vector<std::byte> voxels(4096);
  for (std::size_t i = 0; i < voxels.size(); ++i) voxels[i] = std::byte(i * 7919 % 251);
  const std::vector<std::byte> gz = test::gzipCompress(voxels);
  const std::string head = kNrrdHead + "sizes: 16 16 16\nencoding: gzip\ndata file: d.gz\n";
  test::writeFile(dir.path("v.nhdr"), head);

  test::writeFile(dir.path("d.gz"), std::vector<std::byte>(gz.begin(), gz.begin() + gz.size() / 2));
  EXPECT_THAT(loadError(dir.path("v.nhdr")),
              AllOf(HasSubstr("header says 16×16×16 uint8 = 4096 bytes but the gzip stream in"),
                    HasSubstr("(truncated)")));
  // All voxels there, but the 8-byte trailer (CRC and length) cut off.
  test::writeFile(dir.path("d.gz"), std::vector<std::byte>(gz.begin(), gz.end() - 8));
  EXPECT_THAT(loadError(dir.path("v.nhdr")),
              HasSubstr("is truncated: it ends before its checksum"));
  // A flipped byte in the middle: bad deflate data or a failed checksum.
  std::vector<std::byte> flipped = gz;
  flipped[flipped.size() / 2] ^= std::byte{0x55};
  test::writeFile(dir.path("d.gz"), flipped);
  EXPECT_THAT(loadError(dir.path("v.nhdr")), HasSubstr("is corrupt"));
  test::writeFile(dir.path("d.gz"), "this is not gzip at all");
  EXPECT_THAT(loadError(dir.path("v.nhdr")), HasSubstr("is corrupt after 0 bytes"));
  // A stream that holds more than the header says.
  std::vector<std::byte> more = voxels;
  more.push_back(std::byte{1});
  test::writeFile(dir.path("d.gz"), test::gzipCompress(more));
  EXPECT_THAT(loadError(dir.path("v.nhdr")), HasSubstr("= 4096 bytes but the gzip stream in"));
  EXPECT_THAT(loadError(dir.path("v.nhdr")), HasSubstr("holds more"));

  // MetaImage zlib, cut short, with and without CompressedDataSize.
  const std::vector<std::byte> z = test::zlibCompress(voxels);
  test::writeFile(dir.path("d.zraw"), std::vector<std::byte>(z.begin(), z.begin() + 100));
  const std::string meta =
      "NDims = 3\nDimSize = 16 16 16\nElementType = MET_UCHAR\n"
      "CompressedData = True\n";
  test::writeFile(dir.path("z.mhd"), meta + "ElementDataFile = d.zraw\n");
  EXPECT_THAT(loadError(dir.path("z.mhd")),
              AllOf(HasSubstr("zlib stream"), HasSubstr("(truncated)")));
  test::writeFile(dir.path("c.mhd"),
                  meta + "CompressedDataSize = 5000\nElementDataFile = d.zraw\n");
  EXPECT_THAT(loadError(dir.path("c.mhd")),
              HasSubstr("CompressedDataSize = 5000 but the data file"));
  // Headerless raw .gz.
  VolumeLoadOptions raw;
  raw.raw = RawLayout{{16, 16, 16}, ScalarType::kUint8};
  test::writeFile(dir.path("r.raw.gz"), std::vector<std::byte>(gz.begin(), gz.begin() + 30));
  EXPECT_THAT(loadError(dir.path("r.raw.gz"), raw), HasSubstr("(truncated)"));
}

TEST(VolumeIoErrors, DimsZeroNegativeHugeOrOverflowing) {
  const TempDir dir;
  EXPECT_THAT(loadError(nhdr(dir, "z.nhdr", "sizes: 4 0 4\nencoding: raw\ndata file: eight.raw\n")),
              HasSubstr("dimension y is 0; every dimension must be ≥ 1"));
  EXPECT_THAT(
      loadError(nhdr(dir, "n.nhdr", "sizes: 4 4 -4\nencoding: raw\ndata file: eight.raw\n")),
      HasSubstr("dimension z is -4; every dimension must be ≥ 1"));
  EXPECT_THAT(
      loadError(nhdr(dir, "w.nhdr", "sizes: 4 four 4\nencoding: raw\ndata file: eight.raw\n")),
      HasSubstr("sizes: axis y is 'four', not an integer"));
  EXPECT_THAT(loadError(nhdr(dir, "h.nhdr",
                             "sizes: 3000000000 1 1\nencoding: raw\ndata file: eight.raw\n")),
              HasSubstr("dimension x is 3000000000, above the largest supported (2147483647)"));
  EXPECT_THAT(loadError(nhdr(dir, "o.nhdr",
                             "sizes: 2147483647 2147483647 2147483647\nencoding: raw\n"
                             "data file: eight.raw\n")),
              HasSubstr("2147483647×2147483647×2147483647 uint8 does not fit in 64 bits"));
  EXPECT_THAT(loadError(mhd(dir, "z.mhd",
                            "NDims = 3\nDimSize = 2 0 2\nElementType = MET_UCHAR\n"
                            "ElementDataFile = eight.raw\n")),
              HasSubstr("dimension y is 0"));
  EXPECT_THAT(loadError(mhd(dir, "o.mhd",
                            "NDims = 3\nDimSize = 2000000000 2000000000 2000000000\n"
                            "ElementType = MET_DOUBLE\nElementDataFile = eight.raw\n")),
              HasSubstr("does not fit in 64 bits"));
  VolumeLoadOptions raw;
  raw.raw = RawLayout{{2, -2, 2}, ScalarType::kUint8};
  EXPECT_THAT(loadError(dir.path("eight.raw"), raw), HasSubstr("dimension y is -2"));
}

TEST(VolumeIoErrors, UnsupportedTypesEncodingsAndShapes) {
  const TempDir dir;
  EXPECT_THAT(loadError(nhdr(dir, "t.nhdr",
                             "sizes: 2 2 2\nencoding: raw\ndata file: eight.raw\n"
                             "type: quaternion\n")),
              HasSubstr("type: unsupported voxel type 'quaternion'"));
  test::writeFile(dir.path("t64.nhdr"),
                  "NRRD0004\ntype: int64\ndimension: 3\nsizes: 1 1 1\n"
                  "endian: little\nencoding: raw\ndata file: eight.raw\n");
  EXPECT_THAT(loadError(dir.path("t64.nhdr")), HasSubstr("unsupported voxel type 'int64'"));
  EXPECT_THAT(loadError(nhdr(dir, "e.nhdr", "sizes: 2 2 2\nencoding: lz4\ndata file: eight.raw\n")),
              HasSubstr("encoding 'lz4' is not supported; svr reads raw or gzip"));
  EXPECT_THAT(
      loadError(nhdr(dir, "a.nhdr", "sizes: 2 2 2\nencoding: ascii\ndata file: eight.raw\n")),
      HasSubstr("encoding 'ascii' is not supported"));
  test::writeFile(dir.path("d4.nhdr"),
                  "NRRD0004\ntype: uint8\ndimension: 4\nsizes: 1 2 2 2\n"
                  "encoding: raw\ndata file: eight.raw\n");
  EXPECT_THAT(loadError(dir.path("d4.nhdr")),
              HasSubstr("dimension is 4; svr reads 3-D scalar volumes only"));
  // teem's own complaints come through with the file name.
  test::writeFile(dir.path("ne.nhdr"),
                  "NRRD0004\ntype: short\ndimension: 3\nsizes: 2 2 1\n"
                  "encoding: raw\ndata file: eight.raw\n");
  EXPECT_THAT(loadError(dir.path("ne.nhdr")),
              AllOf(HasSubstr("cannot read the NRRD header"), HasSubstr("endian")));
  test::writeFile(dir.path("junk.nrrd"), "hello world\n");
  EXPECT_THAT(loadError(dir.path("junk.nrrd")), HasSubstr("not a NRRD file"));
  test::writeFile(dir.path("empty.nhdr"), "");
  EXPECT_THAT(loadError(dir.path("empty.nhdr")), HasSubstr("empty file"));

  EXPECT_THAT(loadError(mhd(dir, "t.mhd",
                            "NDims = 3\nDimSize = 2 2 2\nElementType = MET_LONG\n"
                            "ElementDataFile = eight.raw\n")),
              HasSubstr("ElementType = 'MET_LONG' is not supported"));
  EXPECT_THAT(loadError(mhd(dir, "n2.mhd",
                            "ObjectType = Image\nNDims = 2\nDimSize = 2 4\n"
                            "ElementType = MET_UCHAR\nElementDataFile = eight.raw\n")),
              HasSubstr("NDims = 2; svr reads 3-D volumes only"));
  EXPECT_THAT(loadError(mhd(dir, "ch.mhd",
                            kMhdHead + "ElementNumberOfChannels = 3\n"
                                       "ElementDataFile = eight.raw\n")),
              HasSubstr("ElementNumberOfChannels = 3"));
  EXPECT_THAT(loadError(mhd(dir, "ob.mhd",
                            "ObjectType = Mesh\nNDims = 3\nDimSize = 2 2 2\n"
                            "ElementType = MET_UCHAR\nElementDataFile = eight.raw\n")),
              HasSubstr("ObjectType = 'Mesh'"));
  EXPECT_THAT(loadError(mhd(dir, "nf.mhd", kMhdHead)), HasSubstr("no ElementDataFile"));
  EXPECT_THAT(
      loadError(mhd(dir, "nt.mhd", "NDims = 3\nDimSize = 2 2 2\nElementDataFile = eight.raw\n")),
      HasSubstr("no ElementType"));
  EXPECT_THAT(
      loadError(mhd(dir, "bd.mhd", kMhdHead + "BinaryData = False\nElementDataFile = eight.raw\n")),
      HasSubstr("BinaryData = False"));
}

TEST(VolumeIoErrors, MalformedValuesOfKnownMetaImageKeys) {
  const TempDir dir;
  EXPECT_THAT(loadError(mhd(dir, "a.mhd", "NDims = three\n")),
              HasSubstr("NDims = 'three' is not an integer"));
  EXPECT_THAT(loadError(mhd(dir, "b.mhd",
                            "NDims = 3\nDimSize = 2 2\nElementType = MET_UCHAR\n"
                            "ElementDataFile = eight.raw\n")),
              HasSubstr("DimSize = '2 2' is not 3 integers"));
  EXPECT_THAT(loadError(mhd(dir, "b2.mhd", "DimSize = 2 x 2\n")),
              HasSubstr("DimSize = '2 x 2' is not an integer"));
  EXPECT_THAT(loadError(mhd(dir, "c.mhd", "BinaryDataByteOrderMSB = maybe\n")),
              HasSubstr("BinaryDataByteOrderMSB = 'maybe' is not True or False"));
  EXPECT_THAT(loadError(mhd(dir, "d.mhd", "CompressedData = yes please\n")),
              HasSubstr("CompressedData = 'yes please' is not True or False"));
  EXPECT_THAT(loadError(mhd(dir, "e.mhd", "HeaderSize = -7\n")), HasSubstr("HeaderSize = '-7'"));
  EXPECT_THAT(loadError(mhd(dir, "f.mhd", "ElementSpacing = 1 x 1\n")),
              HasSubstr("ElementSpacing = '1 x 1' is not 3 numbers"));
  EXPECT_THAT(loadError(mhd(dir, "f2.mhd",
                            kMhdHead + "ElementSpacing = 1 1\n"
                                       "ElementDataFile = eight.raw\n")),
              HasSubstr("ElementSpacing = '1 1' is not 3 numbers"));
  EXPECT_THAT(loadError(mhd(dir, "g.mhd", "this line has no equals sign\n")),
              HasSubstr("line 1 is 'this line has no equals sign', not 'Key = Value'"));
  EXPECT_THAT(loadError(mhd(dir, "h.mhd", "")), HasSubstr("empty file"));
  EXPECT_THAT(loadError(mhd(dir, "i.mhd", kMhdHead + "ElementDataFile =\n")),
              HasSubstr("ElementDataFile is empty"));
}

TEST(VolumeIoErrors, NanZeroOrNegativeSpacing) {
  const TempDir dir;
  const std::string lines = "sizes: 2 2 2\nencoding: raw\ndata file: eight.raw\n";
  EXPECT_THAT(loadError(nhdr(dir, "n.nhdr", lines + "spacings: 1 nan 1\n")),
              HasSubstr("spacings: axis y is 'nan'; spacing must be finite and > 0"));
  EXPECT_THAT(loadError(nhdr(dir, "z.nhdr", lines + "spacings: 1 1 0\n")),
              HasSubstr("spacings: axis z is '0'; spacing must be finite and > 0"));
  EXPECT_THAT(loadError(nhdr(dir, "m.nhdr", lines + "spacings: -1 1 1\n")),
              HasSubstr("spacings: axis x is '-1'"));
  EXPECT_THAT(loadError(nhdr(dir, "d.nhdr",
                             lines + "space dimension: 3\n"
                                     "space directions: (0,0,0) (0,1,0) (0,0,1)\n")),
              HasSubstr("space directions: axis x is '(0,0,0)'"));
  EXPECT_THAT(loadError(mhd(dir, "n.mhd",
                            kMhdHead + "ElementSpacing = 1 nan 1\n"
                                       "ElementDataFile = eight.raw\n")),
              HasSubstr("ElementSpacing = '1 nan 1': spacing must be finite and > 0"));
  EXPECT_THAT(loadError(mhd(dir, "z.mhd",
                            kMhdHead + "ElementSpacing = 1 1 0\n"
                                       "ElementDataFile = eight.raw\n")),
              HasSubstr("ElementSpacing = '1 1 0': spacing must be finite and > 0"));
  VolumeLoadOptions raw;
  raw.raw = RawLayout{{2, 2, 2}, ScalarType::kUint8};
  raw.raw->spacing = {1, std::nan(""), 1};
  EXPECT_THAT(loadError(dir.path("eight.raw"), raw), HasSubstr("raw spacing y is nan"));
  raw.raw->spacing = {0, 1, 1};
  EXPECT_THAT(loadError(dir.path("eight.raw"), raw), HasSubstr("raw spacing x is 0"));
}

TEST(VolumeIoErrors, NonFiniteFloatVoxels) {
  const TempDir dir;
  test::writeFile(dir.path("f.nhdr"),
                  "NRRD0004\ntype: float\ndimension: 3\nsizes: 2 1 1\n"
                  "endian: little\nencoding: raw\ndata file: f.raw\n");
  test::writeFile(dir.path("f.raw"),
                  test::encodeValues({1.0, std::nan("")}, ScalarType::kFloat32, Endian::kLittle));
  EXPECT_THAT(loadError(dir.path("f.nhdr")), HasSubstr("voxel (1, 0, 0) is nan"));
}

TEST(VolumeIoErrors, OverTheMemoryBudgetBeforeAllocating) {
  const TempDir dir;
  VolumeLoadOptions tiny;
  tiny.memory_budget = 7;
  EXPECT_THAT(
      loadError(nhdr(dir, "b.nhdr", "sizes: 2 2 2\nencoding: raw\ndata file: eight.raw\n"), tiny),
      HasSubstr("b.nhdr: 2×2×2 uint8 needs 8 B, over the memory budget of 7 B (set "
                "--memory-budget to raise it)"));
  // A header that claims 7.5 GiB over a few bytes of gzip: refused by the budget, not by an
  // allocation failure.
  test::writeFile(dir.path("small.gz"), test::gzipCompress(std::vector<std::byte>(8)));
  test::writeFile(dir.path("huge.nhdr"),
                  "NRRD0004\ntype: double\ndimension: 3\n"
                  "sizes: 1000 1000 1000\nendian: little\n"
                  "encoding: gzip\ndata file: small.gz\n");
  VolumeLoadOptions gib;
  gib.memory_budget = std::uint64_t{1} << 30;
  EXPECT_THAT(loadError(dir.path("huge.nhdr"), gib),
              HasSubstr("1000×1000×1000 float64 needs 7.5 GiB, over the memory budget of 1.0 GiB"));
  // The header alone is fine to read.
  EXPECT_EQ(readVolumeHeader(dir.path("huge.nhdr")).data_bytes, 8000000000u);
}

// Random and mutated headers: whatever happens, it is an svr::Error or a volume, never a crash.
TEST(VolumeIoErrors, RandomAndMutatedHeadersNeverCrash) {
  const TempDir dir;
  test::writeFile(dir.path("eight.raw"), std::vector<std::byte>(8));
  const std::string good_nhdr = kNrrdHead +
                                "sizes: 2 2 2\nspacings: 1 1 1\nencoding: raw\n"
                                "data file: eight.raw\n";
  const std::string good_mhd = kMhdHead + "ElementSpacing = 1 1 1\nElementDataFile = eight.raw\n";
  std::mt19937 random(12345);
  int errors = 0, loaded = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const bool nrrd = trial % 2 == 0;
    std::string text = nrrd ? good_nhdr : good_mhd;
    if (trial % 10 == 9) {
      for (char& c : text) c = static_cast<char>(random() % 256);
    } else {
      for (int m = 0; m < 1 + trial % 4; ++m)
        text[random() % text.size()] = "0-9 \n:=.%/#x\xff"[random() % 14];
    }
    const std::string path = dir.path(nrrd ? "r.nhdr" : "r.mhd");
    test::writeFile(path, text);
    try {
      loadVolume(path);
      ++loaded;
    } catch (const Error& e) {
      EXPECT_THAT(e.what(), HasSubstr(path));
      ++errors;
    }
  }
  EXPECT_EQ(errors + loaded, 300);
  EXPECT_GT(errors, 100);
}

}  // namespace
}  // namespace svr

namespace svr {
namespace {

// The NRRD format sets no limit on a header's length: megabytes of comments and key/value
// metadata load, within the memory budget; beyond it, and for binary bytes, a clear error.
TEST(VolumeIoErrors, HeadersOfAnyLengthWithinTheBudgetLoad) {
  const TempDir dir;
  std::string metadata;
  for (int i = 0; metadata.size() < (std::size_t{3} << 20); ++i)
    metadata += fmt::format("# comment line {} of a long provenance record\nkey{}:=value {}\n",
                            i, i, i);
  const std::string lines =
      "sizes: 2 2 2\nencoding: raw\n" + metadata + "data file: eight.raw\n";
  const std::string path = nhdr(dir, "long.nhdr", lines);
  const Volume v = loadVolume(path);
  EXPECT_EQ(v.dims(), (Dims{2, 2, 2}));
  // The same as an attached header: the payload follows the empty line.
  std::string attached = kNrrdHead + "sizes: 2 2 2\nencoding: raw\n" + metadata + "\n";
  attached.append(8, '\x07');
  test::writeFile(dir.path("long.nrrd"), attached);
  EXPECT_EQ(loadVolume(dir.path("long.nrrd")).value(1, 1, 1), 7.0);

  VolumeLoadOptions small;
  small.memory_budget = std::uint64_t{1} << 20;
  EXPECT_THAT(loadError(path, small),
              AllOf(HasSubstr("the header runs past 1.0 MiB without the empty line that ends it"),
                    HasSubstr("memory budget")));
}

TEST(VolumeIoErrors, BinaryBytesInAHeaderAreRefused) {
  const TempDir dir;
  const std::string path =
      nhdr(dir, "binary.nhdr", "sizes: 2 2 2\nencoding: raw\n# \x01\x02 junk\ndata file: eight.raw\n");
  EXPECT_THAT(loadError(path),
              HasSubstr("line 6 of the header holds binary data (byte 0x01 at column 3)"));
  const std::string mha = mhd(dir, "binary.mhd", kMhdHead + std::string("Comment = a\0b\n", 14) +
                                                     "ElementDataFile = eight.raw\n");
  EXPECT_THAT(loadError(mha), HasSubstr("holds binary data (byte 0x00"));
}

}  // namespace
}  // namespace svr
