// DICOM series through GDCM: a folder holding the single-frame files of one series (CT, MR, …).
// Slices are sorted by their position along the slice normal (ImagePositionPatient ·
// (row × column cosines)), not by file name or InstanceNumber. The series must be one grid:
// one SeriesInstanceUID, one size, pixel spacing and orientation, slices evenly spaced (a gap
// is a missing slice) along the normal (a sideways drift is gantry tilt). Values are the
// modality's (RescaleSlope × stored + RescaleIntercept, per file: float32 when any file
// rescales). The grid is turned from DICOM's patient frame (LPS) to RAS (axis_map.h).
#include <fmt/format.h>
#include <gdcmImage.h>
#include <gdcmPhotometricInterpretation.h>
#include <gdcmReader.h>
#include <gdcmStringFilter.h>
#include <gdcmTrace.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cstring>
#include <cmath>
#include <filesystem>
#include <memory>
#include <mutex>
#include <sstream>

#include "renderers/volume/dicom_structure.h"
#include "renderers/volume/memory_budget.h"
#include "renderers/volume/volume_source.h"
#include "base/error.h"

namespace svr::detail {

namespace fs = std::filesystem;

namespace {

const gdcm::Tag kPixelData(0x7fe0, 0x0010), kSeriesUid(0x0020, 0x000e),
    kPosition(0x0020, 0x0032), kOrientation(0x0020, 0x0037), kRows(0x0028, 0x0010),
    kColumns(0x0028, 0x0011), kPixelSpacing(0x0028, 0x0030), kSlope(0x0028, 0x1053),
    kIntercept(0x0028, 0x1052), kFrames(0x0028, 0x0008), kSamples(0x0028, 0x0002),
    kThickness(0x0018, 0x0050), kBitsAllocated(0x0028, 0x0100), kBitsStored(0x0028, 0x0101),
    kHighBit(0x0028, 0x0102), kPixelRepresentation(0x0028, 0x0103),
    kPhotometric(0x0028, 0x0004);

// One file's header, up to its pixels.
struct SliceHeader {
  std::string file, series;
  glm::dvec3 position{0.0}, row{0.0}, column{0.0};
  double pixel_spacing[2]{1.0, 1.0};  // between rows (y), between columns (x)
  int rows = 0, columns = 0;
  ScalarType stored = ScalarType::kUint8;
  gdcm::PixelFormat format;  // as the header states it: what GDCM decodes to
  std::string photometric, syntax;
  double slope = 1.0, intercept = 0.0, thickness = 0.0;
  double along = 0.0;  // position · normal
};

std::vector<double> numbers(const gdcm::StringFilter& filter, const gdcm::File& file,
                            const gdcm::Tag& tag) {
  std::vector<double> out;
  if (!file.GetDataSet().FindDataElement(tag)) return out;
  std::string text = filter.ToString(tag);
  std::replace(text.begin(), text.end(), '\\', ' ');
  std::istringstream in(text);
  for (double v; in >> v;) out.push_back(v);
  return out;
}

std::vector<double> required(const gdcm::StringFilter& filter, const gdcm::File& file,
                             const gdcm::Tag& tag, std::size_t count, const char* name,
                             const std::string& path) {
  std::vector<double> v = numbers(filter, file, tag);
  if (v.size() != count ||
      !std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); }))
    throw Error(fmt::format("{}: {} ({:04x},{:04x}) holds {} finite numbers; expected {}", path,
                            name, tag.GetGroup(), tag.GetElement(), v.size(), count));
  return v;
}

// One whole number in [lo, hi] (Rows, Columns and the pixel format's are US; a fuzzed VR may
// hold anything).
int wholeNumber(const gdcm::StringFilter& filter, const gdcm::File& file, const gdcm::Tag& tag,
                const char* name, int lo, int hi, const std::string& path) {
  const double value = required(filter, file, tag, 1, name, path)[0];
  if (!(value >= lo && value <= hi && value == std::floor(value)))
    throw Error(fmt::format("{}: {} is {}; expected a whole number in {} … {}", path, name, value,
                            lo, hi));
  return static_cast<int>(value);
}

// The pixel format from the header's own attributes, checked here: GDCM's ImageReader derives it
// through ImageHelper, which asserts on inconsistent attributes (a RescaleSlope of 0, a VR or
// VM it did not expect: fuzz findings), so svr decodes without it (DicomStack::slice).
void readPixelFormat(const gdcm::StringFilter& filter, const gdcm::File& file, SliceHeader& s) {
  const auto value = [&](const gdcm::Tag& tag, const char* name) {
    return wholeNumber(filter, file, tag, name, 0, 65535, s.file);
  };
  const int allocated = value(kBitsAllocated, "BitsAllocated");
  const int stored = value(kBitsStored, "BitsStored"), high = value(kHighBit, "HighBit");
  const int is_signed = value(kPixelRepresentation, "PixelRepresentation");
  if (!(allocated == 8 || allocated == 16 || allocated == 32) || stored < 1 ||
      stored > allocated || high != stored - 1 || (is_signed != 0 && is_signed != 1))
    throw Error(fmt::format("{}: BitsAllocated {}, BitsStored {}, HighBit {}, "
                            "PixelRepresentation {}; svr reads 8-, 16- or 32-bit integers with "
                            "HighBit = BitsStored − 1",
                            s.file, allocated, stored, high, is_signed));
  static const ScalarType kTypes[2][3] = {
      {ScalarType::kUint8, ScalarType::kUint16, ScalarType::kUint32},
      {ScalarType::kInt8, ScalarType::kInt16, ScalarType::kInt32}};
  s.stored = kTypes[is_signed][allocated == 8 ? 0 : allocated == 16 ? 1 : 2];
  s.format = gdcm::PixelFormat(1, static_cast<unsigned short>(allocated),
                               static_cast<unsigned short>(stored),
                               static_cast<unsigned short>(high),
                               static_cast<unsigned short>(is_signed));
  if (file.GetDataSet().FindDataElement(kPhotometric))
    s.photometric = withoutPadding(filter.ToString(kPhotometric));
  if (s.photometric != "MONOCHROME1" && s.photometric != "MONOCHROME2")
    throw Error(fmt::format("{}: PhotometricInterpretation is '{}'; svr reads grey-value series "
                            "(MONOCHROME1 or MONOCHROME2)",
                            s.file, s.photometric));
}

SliceHeader readSliceHeader(const std::string& path) {
  checkDicomStructure(path);
  gdcm::Reader reader;
  reader.SetFileName(path.c_str());
  if (!reader.ReadUpToTag(kPixelData))
    throw Error(fmt::format("{}: not a DICOM file GDCM can read", path));
  const gdcm::File& file = reader.GetFile();
  gdcm::StringFilter filter;
  filter.SetFile(file);
  SliceHeader s;
  s.file = path;
  s.series = file.GetDataSet().FindDataElement(kSeriesUid) ? filter.ToString(kSeriesUid) : "";
  const std::vector<double> frames = numbers(filter, file, kFrames);
  if (!frames.empty() && frames[0] > 1)
    throw Error(fmt::format("{}: holds {} frames; svr reads series of single-frame files", path,
                            frames[0]));
  const std::vector<double> samples = numbers(filter, file, kSamples);
  if (!samples.empty() && samples[0] != 1)
    throw Error(fmt::format("{}: has {} samples per pixel; svr reads grey-value series", path,
                            samples[0]));
  const auto p = required(filter, file, kPosition, 3, "ImagePositionPatient", path);
  const auto o = required(filter, file, kOrientation, 6, "ImageOrientationPatient", path);
  const auto ps = required(filter, file, kPixelSpacing, 2, "PixelSpacing", path);
  s.rows = wholeNumber(filter, file, kRows, "Rows", 1, 65535, path);
  s.columns = wholeNumber(filter, file, kColumns, "Columns", 1, 65535, path);
  readPixelFormat(filter, file, s);
  s.syntax = file.GetHeader().GetDataSetTransferSyntax().GetString();
  s.position = {p[0], p[1], p[2]};
  s.row = {o[0], o[1], o[2]};
  s.column = {o[3], o[4], o[5]};
  s.pixel_spacing[0] = ps[0];
  s.pixel_spacing[1] = ps[1];
  if (!(ps[0] > 0 && ps[1] > 0))
    throw Error(fmt::format("{}: PixelSpacing is {}\\{}; both must be > 0", path, ps[0], ps[1]));
  if (const auto v = numbers(filter, file, kSlope); !v.empty()) s.slope = v[0];
  if (const auto v = numbers(filter, file, kIntercept); !v.empty()) s.intercept = v[0];
  if (const auto v = numbers(filter, file, kThickness); !v.empty()) s.thickness = v[0];
  if (!std::isfinite(s.slope) || !std::isfinite(s.intercept) || s.slope == 0.0)
    throw Error(fmt::format("{}: RescaleSlope {} and RescaleIntercept {} must be finite, the "
                            "slope not 0",
                            path, s.slope, s.intercept));
  return s;
}

bool near(const glm::dvec3& a, const glm::dvec3& b, double tolerance) {
  return std::abs(a.x - b.x) <= tolerance && std::abs(a.y - b.y) <= tolerance &&
         std::abs(a.z - b.z) <= tolerance;
}

// Every slice against the first; then the positions' spacing. Returns the slice spacing.
double checkSeries(const std::string& folder, const std::vector<SliceHeader>& s,
                   const glm::dvec3& normal) {
  const SliceHeader& a = s.front();
  for (const SliceHeader& b : s) {
    const std::string name = fs::path(b.file).filename().string();
    const std::string first = fs::path(a.file).filename().string();
    if (b.series != a.series)
      throw Error(fmt::format("{}: mixes series: '{}' is of series {} and '{}' of {}; give a "
                              "folder holding one series",
                              folder, first, a.series, name, b.series));
    if (b.rows != a.rows || b.columns != a.columns)
      throw Error(fmt::format("{}: '{}' is {} × {} pixels but '{}' is {} × {}", folder, name,
                              b.columns, b.rows, first, a.columns, a.rows));
    if (b.stored != a.stored)
      throw Error(fmt::format("{}: '{}' has {} pixels but '{}' {}", folder, name,
                              toString(b.stored), first, toString(a.stored)));
    if (!near(b.row, a.row, 1e-4) || !near(b.column, a.column, 1e-4))
      throw Error(fmt::format("{}: '{}' has another ImageOrientationPatient than '{}'", folder,
                              name, first));
    if (std::abs(b.pixel_spacing[0] - a.pixel_spacing[0]) > 1e-4 * a.pixel_spacing[0] ||
        std::abs(b.pixel_spacing[1] - a.pixel_spacing[1]) > 1e-4 * a.pixel_spacing[1])
      throw Error(fmt::format("{}: '{}' has another PixelSpacing than '{}'", folder, name, first));
  }
  if (s.size() == 1) return a.thickness > 0 ? a.thickness : 1.0;
  // The smallest gap is the series' step: a gap that is a multiple of it is missing slices.
  double step = INFINITY;
  for (std::size_t i = 1; i < s.size(); ++i) step = std::min(step, s[i].along - s[i - 1].along);
  for (std::size_t i = 1; i < s.size(); ++i) {
    const double gap = s[i].along - s[i - 1].along;
    const std::string before = fs::path(s[i - 1].file).filename().string();
    const std::string name = fs::path(s[i].file).filename().string();
    if (gap < 1e-6)
      throw Error(fmt::format("{}: '{}' and '{}' lie at the same position ({} along the normal)",
                              folder, before, name, s[i].along));
    if (std::abs(gap - step) > 0.01 * step) {
      const long missing = std::lround(gap / step) - 1;
      throw Error(fmt::format("{}: {} mm between '{}' and '{}' where the closest slices are {} "
                              "mm apart: {}; svr needs a whole, evenly spaced series",
                              folder, gap, before, name, step,
                              missing >= 1 && std::abs(gap - (missing + 1) * step) <= 0.01 * step
                                  ? fmt::format("{} slice{} missing", missing,
                                                missing == 1 ? " is" : "s are")
                                  : std::string("the spacing is uneven")));
    }
    // Each position must lie on the line through the first along the normal: else the slices
    // drift sideways (gantry tilt), and the grid is not rectangular.
    const glm::dvec3 offset = s[i].position - s[0].position;
    const glm::dvec3 sideways = offset - glm::dot(offset, normal) * normal;
    if (glm::length(sideways) > 0.01 * step * static_cast<double>(i))
      throw Error(fmt::format("{}: '{}' is {} mm off the slice normal from the first slice: a "
                              "tilted gantry, whose slices svr cannot stack",
                              folder, name, glm::length(sideways)));
  }
  return step;
}

// A slice's pixels: GDCM parses the file and decodes its PixelData in the file's transfer
// syntax (any GDCM has a codec for) into the pixel format the header states.
std::vector<std::byte> decodePixels(const SliceHeader& s) {
  gdcm::Reader reader;
  reader.SetFileName(s.file.c_str());
  if (!reader.Read()) throw Error(fmt::format("{}: GDCM cannot read it", s.file));
  const gdcm::DataSet& data = reader.GetFile().GetDataSet();
  if (!data.FindDataElement(kPixelData))
    throw Error(fmt::format("{}: has no PixelData (7fe0,0010)", s.file));
  const gdcm::DataElement& element = data.GetDataElement(kPixelData);
  std::vector<std::byte> pixels(static_cast<std::size_t>(s.rows) * s.columns *
                                bytesPerVoxel(s.stored));
  const gdcm::ByteValue* native = element.GetByteValue();
  if (native && native->GetLength() < pixels.size())
    throw Error(fmt::format("{}: PixelData holds {} bytes; {} × {} {} needs {}", s.file,
                            native->GetLength(), s.columns, s.rows, toString(s.stored),
                            pixels.size()));
  gdcm::Image image;
  image.SetNumberOfDimensions(2);
  image.SetDimension(0, static_cast<unsigned>(s.columns));
  image.SetDimension(1, static_cast<unsigned>(s.rows));
  image.SetPixelFormat(s.format);
  image.SetPhotometricInterpretation(
      gdcm::PhotometricInterpretation::GetPIType(s.photometric.c_str()));
  image.SetTransferSyntax(reader.GetFile().GetHeader().GetDataSetTransferSyntax());
  image.SetDataElement(element);
  if (image.GetBufferLength() != pixels.size() ||
      !image.GetBuffer(reinterpret_cast<char*>(pixels.data())))
    throw Error(fmt::format("{}: GDCM cannot decode {} × {} {} pixels from its PixelData ({})",
                            s.file, s.columns, s.rows, toString(s.stored), s.syntax));
  return pixels;
}

// The sorted files' pixels, decoded by GDCM (any transfer syntax it supports), rescaled when
// any file rescales.
class DicomStack final : public SliceStack {
 public:
  DicomStack(std::vector<SliceHeader> slices, bool rescale)
      : slices_(std::move(slices)), rescale_(rescale) {}
  // The series' files share one stored type (checkSeries).
  ScalarType type() const override {
    return rescale_ ? ScalarType::kFloat32 : slices_.front().stored;
  }
  std::vector<std::byte> slice(int z) const override {
    const SliceHeader& s = slices_[static_cast<std::size_t>(z)];
    const std::size_t n = static_cast<std::size_t>(s.rows) * s.columns;
    std::vector<std::byte> pixels = decodePixels(s);
    if (!rescale_) return pixels;
    const Volume stored({s.columns, s.rows, 1}, glm::dvec3(1.0), s.stored, std::move(pixels),
                        s.file);
    std::vector<std::byte> out(n * sizeof(float));
    for (std::size_t i = 0; i < n; ++i) {
      const float v = static_cast<float>(s.slope * stored.value(i) + s.intercept);
      std::memcpy(out.data() + i * sizeof(float), &v, sizeof v);
    }
    return out;
  }

 private:
  std::vector<SliceHeader> slices_;
  bool rescale_;
};

// svr says what is wrong with a file itself; GDCM's warnings and errors on stderr (in its
// tolerant parse: "Desperate attempt", duplicate elements, unknown UIDs) would only be noise.
void silenceGdcm() {
  static std::once_flag once;
  std::call_once(once, [] {
    gdcm::Trace::DebugOff();
    gdcm::Trace::WarningOff();
    gdcm::Trace::ErrorOff();
  });
}

}  // namespace

VolumeSource readDicomSource(const std::string& folder, std::uint64_t budget) {
  silenceGdcm();
  std::vector<SliceHeader> slices;
  for (const fs::directory_entry& entry : fs::directory_iterator(folder)) {
    const std::string name = entry.path().filename().string();
    if (!entry.is_regular_file() || name.starts_with(".") || name == "DICOMDIR") continue;
    slices.push_back(readSliceHeader(entry.path().string()));
  }
  if (slices.empty())
    throw Error(fmt::format("{}: is a folder holding no files (a folder is read as a DICOM "
                            "series or a stack of numbered TIFFs)",
                            folder));
  const SliceHeader& first = slices.front();
  const glm::dvec3 normal = glm::normalize(glm::cross(first.row, first.column));
  if (!std::isfinite(normal.x))
    throw Error(fmt::format("{}: ImageOrientationPatient's row and column are parallel",
                            first.file));
  for (SliceHeader& s : slices) s.along = glm::dot(s.position, normal);
  std::sort(slices.begin(), slices.end(),
            [](const SliceHeader& a, const SliceHeader& b) { return a.along < b.along; });
  const double step = checkSeries(folder, slices, normal);

  VolumeSource source;
  VolumeHeader& h = source.header;
  h.path = h.data_file = folder;
  h.format = "dicom";
  h.dims = {first.columns, first.rows, static_cast<int>(slices.size())};
  h.spacing = {slices[0].pixel_spacing[1], slices[0].pixel_spacing[0], step};
  // GDCM decodes a whole slice at a time.
  checkMemoryBudget(static_cast<std::uint64_t>(first.rows) *
                        static_cast<std::uint64_t>(first.columns) * bytesPerVoxel(first.stored),
                    budget,
                    fmt::format("{}: a slice of {} × {} {}", first.file, first.columns,
                                first.rows, toString(first.stored)));
  const ScalarType stored = first.stored;
  h.encoding = first.syntax;
  const bool rescale = std::any_of(slices.begin(), slices.end(), [](const SliceHeader& s) {
    return s.slope != 1.0 || s.intercept != 0.0;
  });
  if (rescale)
    h.values = fmt::format("stored {} × RescaleSlope + RescaleIntercept ({} + {} in the first "
                           "slice), as float32",
                           toString(stored), slices[0].slope, slices[0].intercept);
  // LPS to RAS: x and y negate.
  const auto ras = [](const glm::dvec3& v) { return glm::dvec3(-v.x, -v.y, v.z); };
  const OrientedAxes oriented =
      axesToRas({ras(first.row), ras(first.column), ras(normal)}, folder + ": the orientation");
  source.axes = oriented.map;
  h.orientation = fmt::format("{} slices sorted along the normal; file axes i, j, k point {}, "
                              "{}, {}; turned to RAS",
                              slices.size(), oriented.file_axes[0], oriented.file_axes[1],
                              oriented.file_axes[2]);
  if (oriented.oblique_degrees > 0.01)
    h.orientation += fmt::format(" (oblique by {:.2f}°: nearest axes kept, not resampled)",
                                 oriented.oblique_degrees);
  auto stack = std::make_shared<DicomStack>(std::move(slices), rescale);
  h.type = stack->type();
  h.endian = nativeEndian();
  h.data_bytes = volumeBytes({h.dims[0], h.dims[1], h.dims[2]}, h.type, folder);
  source.slices = std::move(stack);
  return source;
}

}  // namespace svr::detail
