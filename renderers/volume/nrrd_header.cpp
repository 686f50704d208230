// NRRD headers (attached .nrrd and detached .nhdr), parsed by teem's nrrd library (design.md §7:
// "teem for NRRD") with skipData, so teem reads no voxels and allocates nothing: the voxels are
// read afterwards by readPayload (volume_source.cpp), once the memory budget has been checked,
// straight into the Volume's buffer. That also gives one exact error for every short, long,
// truncated or corrupt payload, where teem would print warnings to stderr or read into its own
// buffer that we would then have to copy (twice the memory at the peak).
//
// Before teem sees the file, a small pre-scan of the header's "field: value" lines checks what
// teem accepts or words poorly for our purposes: the magic (teem would also accept PNG, VTK
// and text files), sizes ≤ 0 or whose product overflows (teem says "size is zero!" for -4),
// NaN spacings (teem takes them as "unknown"), types and encodings svr does not read, and a
// "data file" with ".." or outside the header's folder (teem would open it).

#include <fmt/format.h>
#include <teem/nrrd.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "renderers/volume/volume_source.h"
#include "base/error.h"

namespace svr::detail {

namespace {

constexpr const char* kAxisNames[] = {"x", "y", "z"};
// teem 1.12 formats its error messages with vsprintf into a fixed buffer of about 1 KiB and
// quotes the offending header line in them, so a field line of ~1 KB that it cannot parse
// overflows the buffer and aborts the process (found by fuzz_nrrd's long campaign, issue 15;
// tests/data/bad/nrrd_long_field_line.nrrd). Field lines are refused beyond this length;
// comments and key:=value lines, which teem stores without quoting them, may be of any length.
constexpr std::size_t kMaxFieldLine = 512;

struct NrrdDeleter {
  void operator()(Nrrd* nrrd) const { nrrdNuke(nrrd); }
};
struct NrrdIoDeleter {
  void operator()(NrrdIoState* nio) const { nrrdIoStateNix(nio); }
};

std::int64_t parseSize(const std::string& path, const std::string& word, int axis) {
  char* end = nullptr;
  errno = 0;
  const long long value = std::strtoll(word.c_str(), &end, 10);
  if (end == word.c_str() || *end != '\0' || errno == ERANGE)
    throw Error(fmt::format("{}: sizes: axis {} is '{}', not an integer", path,
                            axis < 3 ? kAxisNames[axis] : std::to_string(axis), word));
  return value;
}

void checkSpacing(const std::string& path, const std::string& key, int axis, double value,
                  const std::string& text) {
  if (!std::isfinite(value) || value <= 0)
    throw Error(fmt::format("{}: {}: axis {} is '{}'; spacing must be finite and > 0", path, key,
                            kAxisNames[axis], text));
}

// Checks the header's "field: value" lines that svr words itself (see the top of the file).
void preScan(const std::string& path, std::uint64_t budget) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(fmt::format("{}: cannot open the file", path));
  std::string line;
  if (!std::getline(in, line))
    throw Error(fmt::format("{}: empty file, expected a NRRD header", path));
  if (line.rfind("NRRD000", 0) != 0 || line.size() < 8)
    throw Error(
        fmt::format("{}: not a NRRD file: it starts with '{}' instead of NRRD0001…"
                    "NRRD0005",
                    path, trim(line.substr(0, 16))));
  std::optional<ScalarType> type;
  std::vector<std::int64_t> sizes;
  std::uint64_t header_bytes = line.size();
  int line_number = 1;
  while (std::getline(in, line)) {
    header_bytes += line.size() + 1;
    ++line_number;
    checkHeaderWithinBudget(path, header_bytes, budget, "the empty line that ends it");
    checkHeaderLineIsText(path, line, line_number);
    // A key:=value line has its ":=" before any ": ". teem reads "space: …:=…" as the field
    // "space" and quotes it when it fails, so such a line is a field line here too.
    const auto colon = line.find(": ");
    const bool comment = !line.empty() && line[0] == '#';
    const bool key_value = line.find(":=") < colon;
    if (line.size() > kMaxFieldLine && !comment && !key_value)
      throw Error(fmt::format("{}: line {} is a field line of {} bytes; field lines (all but "
                              "comments and key:=value lines) may be at most {} bytes, since "
                              "teem's error messages overflow on longer ones",
                              path, line_number, line.size(), kMaxFieldLine));
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) break;                                   // the end of an attached header
    if (comment || key_value || colon == std::string::npos) continue;
    const std::string key = toLower(trim(line.substr(0, colon)));
    const std::string value = trim(line.substr(colon + 2));
    if (key == "type") {
      try {
        type = parseScalarType(value);
      } catch (const Error& e) {
        throw Error(fmt::format("{}: type: {}", path, e.what()));
      }
    } else if (key == "encoding") {
      const std::string encoding = toLower(value);
      if (encoding != "raw" && encoding != "gzip" && encoding != "gz")
        throw Error(
            fmt::format("{}: encoding '{}' is not supported; svr reads raw or gzip", path, value));
    } else if (key == "dimension") {
      if (value != "3")
        throw Error(
            fmt::format("{}: dimension is {}; svr reads 3-D scalar volumes only "
                        "(dimension 3)",
                        path, value));
    } else if (key == "sizes") {
      const std::vector<std::string> words = splitWhitespace(value);
      for (std::size_t a = 0; a < words.size(); ++a)
        sizes.push_back(parseSize(path, words[a], static_cast<int>(a)));
    } else if (key == "spacings") {
      const std::vector<std::string> words = splitWhitespace(value);
      for (std::size_t a = 0; a < words.size() && a < 3; ++a) {
        char* end = nullptr;
        const double spacing = std::strtod(words[a].c_str(), &end);
        if (end == words[a].c_str() || *end != '\0')
          throw Error(fmt::format("{}: spacings: axis {} is '{}', not a number", path,
                                  kAxisNames[a], words[a]));
        checkSpacing(path, "spacings", static_cast<int>(a), spacing, words[a]);
      }
    } else if (key == "data file" || key == "datafile") {
      const std::vector<std::string> words = splitWhitespace(value);
      if (words.size() != 1 || words[0] == "LIST")
        throw Error(
            fmt::format("{}: data file '{}' names several files; svr reads one data "
                        "file per volume",
                        path, value));
      resolveDataFile(path, value, "data file");
    }
  }
  if (sizes.size() == 3)
    volumeBytes({sizes[0], sizes[1], sizes[2]}, type.value_or(ScalarType::kUint8), path);
}

// teem reports errors through biff, a process-wide message store keyed by library; calls that
// may add to it are serialised so one thread's messages never end up in another's error.
std::mutex& teemMutex() {
  static std::mutex mutex;
  return mutex;
}

// The innermost biff message ("_nrrdReadNrrdParse_type: couldn't parse type …"): the cause.
std::string takeBiffMessage() {
  char* const text = biffGetDone(NRRD);
  std::string all = text ? text : "";
  std::free(text);
  while (!all.empty() && (all.back() == '\n' || all.back() == ' ')) all.pop_back();
  std::string last = all.substr(all.find_last_of('\n') + 1);
  const std::string prefix = "[nrrd] ";
  if (last.rfind(prefix, 0) == 0) last.erase(0, prefix.size());
  return last.empty() ? "unknown teem error" : last;
}

ScalarType scalarTypeOf(const std::string& path, int teem_type) {
  switch (teem_type) {
    case nrrdTypeChar:
      return ScalarType::kInt8;
    case nrrdTypeUChar:
      return ScalarType::kUint8;
    case nrrdTypeShort:
      return ScalarType::kInt16;
    case nrrdTypeUShort:
      return ScalarType::kUint16;
    case nrrdTypeInt:
      return ScalarType::kInt32;
    case nrrdTypeUInt:
      return ScalarType::kUint32;
    case nrrdTypeFloat:
      return ScalarType::kFloat32;
    case nrrdTypeDouble:
      return ScalarType::kFloat64;
    default:
      throw Error(
          fmt::format("{}: type '{}' is not supported; expected uint8, int8, uint16, "
                      "int16, uint32, int32, float32 or float64",
                      path, airEnumStr(nrrdType, teem_type)));
  }
}

}  // namespace

VolumeSource readNrrdSource(const std::string& path, std::uint64_t budget) {
  preScan(path, budget);

  const std::lock_guard<std::mutex> lock(teemMutex());
  const std::unique_ptr<Nrrd, NrrdDeleter> nrrd(nrrdNew());
  const std::unique_ptr<NrrdIoState, NrrdIoDeleter> nio(nrrdIoStateNew());
  nio->skipData = AIR_TRUE;
  // Keeps the data file open at the first voxel, after any line and byte skips, so its offset
  // can be read with ftell.
  nio->keepNrrdDataFileOpen = AIR_TRUE;
  if (nrrdLoad(nrrd.get(), path.c_str(), nio.get()) != 0)
    throw Error(fmt::format("{}: cannot read the NRRD header: {}", path, takeBiffMessage()));
  std::int64_t offset = 0;
  if (nio->dataFile) {
    offset = ftello(nio->dataFile);
    std::fclose(nio->dataFile);
    nio->dataFile = nullptr;
  }

  VolumeSource source;
  VolumeHeader& h = source.header;
  h.path = path;
  if (nrrd->dim != 3)
    throw Error(
        fmt::format("{}: dimension is {}; svr reads 3-D scalar volumes only", path, nrrd->dim));
  h.type = scalarTypeOf(path, nrrd->type);
  HeaderDims dims{};
  for (int a = 0; a < 3; ++a) {
    if (nrrd->axis[a].size > static_cast<std::size_t>(std::numeric_limits<std::int64_t>::max()))
      throw Error(fmt::format("{}: sizes: axis {} is {}, too large", path, kAxisNames[a],
                              nrrd->axis[a].size));
    dims[a] = static_cast<std::int64_t>(nrrd->axis[a].size);
  }
  h.data_bytes = volumeBytes(dims, h.type, path);
  for (int a = 0; a < 3; ++a) h.dims[a] = static_cast<int>(dims[a]);

  // Spacing: the length of each axis's space direction, else its spacing, else 1.
  for (int a = 0; a < 3; ++a) {
    const NrrdAxisInfo& axis = nrrd->axis[a];
    if (nrrd->spaceDim > 0) {
      const double norm = nrrdSpaceVecNorm(nrrd->spaceDim, axis.spaceDirection);
      std::string text = "(";
      for (unsigned i = 0; i < nrrd->spaceDim; ++i)
        text += fmt::format("{}{}", i ? "," : "", axis.spaceDirection[i]);
      checkSpacing(path, "space directions", a, norm, text + ")");
      h.spacing[a] = norm;
    } else if (std::isfinite(axis.spacing)) {
      checkSpacing(path, "spacings", a, axis.spacing, fmt::format("{}", axis.spacing));
      h.spacing[a] = axis.spacing;
    } else {
      h.spacing[a] = 1.0;
    }
  }

  if (nio->encoding == nrrdEncodingRaw) {
    h.encoding = "raw";
  } else if (nio->encoding == nrrdEncodingGzip) {
    h.encoding = "gzip";
  } else {
    throw Error(fmt::format("{}: encoding '{}' is not supported; svr reads raw or gzip", path,
                            nio->encoding->name));
  }
  if (bytesPerVoxel(h.type) == 1 || nio->endian == airEndianUnknown)
    h.endian = nativeEndian();
  else
    h.endian = nio->endian == airEndianBig ? Endian::kBig : Endian::kLittle;

  const bool detached = nio->dataFNArr->len > 0 || nio->dataFNFormat != nullptr;
  if (detached && (nio->dataFNArr->len != 1 || nio->dataFNFormat != nullptr))
    throw Error(fmt::format("{}: several data files; svr reads one data file per volume", path));
  h.format = detached ? "nhdr" : "nrrd";
  h.data_file = detached ? resolveDataFile(path, nio->dataFN[0], "data file") : path;

  if (offset < 0) throw Error(fmt::format("{}: cannot find where the voxels start", path));
  source.offset = static_cast<std::uint64_t>(offset);
  if (h.encoding == "gzip") {
    // teem skips "byte skip" bytes of a compressed payload after decompressing it.
    if (nio->byteSkip < 0)
      throw Error(fmt::format("{}: byte skip: {} (from the end) cannot be used with gzip", path,
                              nio->byteSkip));
    source.skip_decompressed = static_cast<std::uint64_t>(nio->byteSkip);
  }
  for (unsigned i = 0; i < nrrd->cmtArr->len; ++i) h.comments.emplace_back(nrrd->cmt[i]);
  return source;
}

}  // namespace svr::detail
