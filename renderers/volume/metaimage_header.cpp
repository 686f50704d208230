// MetaImage headers (.mhd with a separate data file, .mha with the voxels after the header):
// "Key = Value" lines ending with ElementDataFile. Own parser: the format is small, and ITK's
// MetaIO is not a Debian package of its own. MetaImage has many keys (Offset, TransformMatrix,
// AnatomicalOrientation, …) that do not change how voxels are read; unknown keys are ignored,
// but a malformed value of a key svr reads is an error naming the key and the value.

#include <fmt/format.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include "renderers/volume/volume_source.h"
#include "base/error.h"

namespace svr::detail {

namespace {


struct MetaKeys {
  std::optional<std::string> object_type, element_data_file;
  std::optional<std::int64_t> ndims, channels, header_size;
  std::optional<std::uint64_t> compressed_size;
  std::optional<std::vector<std::int64_t>> dim_size;
  std::optional<std::vector<double>> spacing, element_size;
  std::string dim_size_text, spacing_text, element_size_text;
  std::optional<ScalarType> type;
  std::optional<bool> msb, compressed, binary;
  std::vector<std::string> comments;
  std::uint64_t data_offset = 0;  // just after the ElementDataFile line
};

Error badValue(const std::string& path, const std::string& key, const std::string& value,
               const std::string& expected) {
  return Error(fmt::format("{}: {} = '{}' is not {}", path, key, value, expected));
}

std::int64_t parseInteger(const std::string& path, const std::string& key, const std::string& value,
                          const std::string& word) {
  char* end = nullptr;
  errno = 0;
  const long long v = std::strtoll(word.c_str(), &end, 10);
  if (word.empty() || *end != '\0' || errno == ERANGE)
    throw badValue(path, key, value, "an integer");
  return v;
}

std::vector<std::int64_t> parseIntegers(const std::string& path, const std::string& key,
                                        const std::string& value) {
  std::vector<std::int64_t> out;
  for (const std::string& word : splitWhitespace(value))
    out.push_back(parseInteger(path, key, value, word));
  return out;  // the count is checked against NDims once the whole header is read
}

std::vector<double> parseSpacing(const std::string& path, const std::string& key,
                                 const std::string& value) {
  std::vector<double> out;
  for (const std::string& word : splitWhitespace(value)) {
    char* end = nullptr;
    const double v = std::strtod(word.c_str(), &end);
    if (end == word.c_str() || *end != '\0') throw badValue(path, key, value, "3 numbers");
    if (!std::isfinite(v) || v <= 0)
      throw Error(fmt::format("{}: {} = '{}': spacing must be finite and > 0", path, key, value));
    out.push_back(v);
  }
  return out;  // the count is checked against NDims once the whole header is read
}

bool parseBool(const std::string& path, const std::string& key, const std::string& value) {
  const std::string v = toLower(value);
  if (v == "true" || v == "1") return true;
  if (v == "false" || v == "0") return false;
  throw badValue(path, key, value, "True or False");
}

ScalarType parseElementType(const std::string& path, const std::string& value) {
  static const std::pair<const char*, ScalarType> kTypes[] = {
      {"MET_UCHAR", ScalarType::kUint8},   {"MET_CHAR", ScalarType::kInt8},
      {"MET_USHORT", ScalarType::kUint16}, {"MET_SHORT", ScalarType::kInt16},
      {"MET_UINT", ScalarType::kUint32},   {"MET_INT", ScalarType::kInt32},
      {"MET_FLOAT", ScalarType::kFloat32}, {"MET_DOUBLE", ScalarType::kFloat64}};
  for (const auto& [name, type] : kTypes)
    if (value == name) return type;
  throw Error(
      fmt::format("{}: ElementType = '{}' is not supported; expected MET_UCHAR, "
                  "MET_CHAR, MET_USHORT, MET_SHORT, MET_UINT, MET_INT, MET_FLOAT or "
                  "MET_DOUBLE",
                  path, value));
}

MetaKeys parseKeys(const std::string& path, std::uint64_t budget) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(fmt::format("{}: cannot open the file", path));
  MetaKeys keys;
  std::string line;
  std::uint64_t consumed = 0;
  int line_number = 0;
  while (!keys.element_data_file && std::getline(in, line)) {
    ++line_number;
    consumed += line.size() + (in.eof() ? 0 : 1);
    checkHeaderWithinBudget(path, consumed, budget, "the ElementDataFile line that ends it");
    checkHeaderLineIsText(path, line, line_number);
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (trim(line).empty()) continue;
    const auto equals = line.find('=');
    if (equals == std::string::npos)
      throw Error(fmt::format("{}: line {} is '{}', not 'Key = Value'", path, line_number,
                              trim(line).substr(0, 60)));
    const std::string key = trim(line.substr(0, equals));
    const std::string value = trim(line.substr(equals + 1));
    const std::string k = toLower(key);
    if (k == "objecttype") {
      keys.object_type = value;
    } else if (k == "ndims") {
      keys.ndims = parseInteger(path, key, value, value);
    } else if (k == "dimsize") {
      keys.dim_size = parseIntegers(path, key, value);
      keys.dim_size_text = value;
    } else if (k == "elementtype") {
      keys.type = parseElementType(path, value);
    } else if (k == "elementspacing") {
      keys.spacing = parseSpacing(path, key, value);
      keys.spacing_text = value;
    } else if (k == "elementsize") {
      keys.element_size = parseSpacing(path, key, value);
      keys.element_size_text = value;
    } else if (k == "binarydatabyteordermsb" || k == "elementbyteordermsb") {
      keys.msb = parseBool(path, key, value);
    } else if (k == "compresseddata") {
      keys.compressed = parseBool(path, key, value);
    } else if (k == "binarydata") {
      keys.binary = parseBool(path, key, value);
    } else if (k == "compresseddatasize") {
      const std::int64_t size = parseInteger(path, key, value, value);
      if (size < 1) throw badValue(path, key, value, "a positive byte count");
      keys.compressed_size = static_cast<std::uint64_t>(size);
    } else if (k == "headersize") {
      keys.header_size = parseInteger(path, key, value, value);
      if (*keys.header_size < -1) throw badValue(path, key, value, "-1 or a byte count ≥ 0");
    } else if (k == "elementnumberofchannels") {
      keys.channels = parseInteger(path, key, value, value);
    } else if (k == "comment") {
      keys.comments.push_back(value);
    } else if (k == "elementdatafile") {
      keys.element_data_file = value;
    }
  }
  if (line_number == 0)
    throw Error(fmt::format("{}: empty file, expected a MetaImage header", path));
  keys.data_offset = consumed;
  return keys;
}

}  // namespace

VolumeSource readMetaImageSource(const std::string& path, std::uint64_t budget) {
  const MetaKeys keys = parseKeys(path, budget);
  const auto require = [&](bool present, const char* key) {
    if (!present) throw Error(fmt::format("{}: no {}; a MetaImage volume needs it", path, key));
  };
  require(keys.element_data_file.has_value(), "ElementDataFile");
  if (keys.object_type && toLower(*keys.object_type) != "image")
    throw Error(fmt::format("{}: ObjectType = '{}'; svr reads ObjectType = Image", path,
                            *keys.object_type));
  require(keys.ndims.has_value(), "NDims");
  if (*keys.ndims != 3)
    throw Error(
        fmt::format("{}: NDims = {}; svr reads 3-D volumes only (NDims = 3)", path, *keys.ndims));
  require(keys.dim_size.has_value(), "DimSize");
  if (keys.dim_size->size() != 3) throw badValue(path, "DimSize", keys.dim_size_text, "3 integers");
  if (keys.spacing && keys.spacing->size() != 3)
    throw badValue(path, "ElementSpacing", keys.spacing_text, "3 numbers");
  if (keys.element_size && keys.element_size->size() != 3)
    throw badValue(path, "ElementSize", keys.element_size_text, "3 numbers");
  require(keys.type.has_value(), "ElementType");
  if (keys.channels && *keys.channels != 1)
    throw Error(
        fmt::format("{}: ElementNumberOfChannels = {}; svr reads scalar volumes only "
                    "(1 channel)",
                    path, *keys.channels));
  if (keys.binary && !*keys.binary)
    throw Error(fmt::format("{}: BinaryData = False (voxels as text) is not supported", path));

  VolumeSource source;
  VolumeHeader& h = source.header;
  h.path = path;
  const std::string extension = toLower(std::filesystem::path(path).extension().string());
  h.format = extension == ".mha" ? "mha" : "mhd";
  h.type = *keys.type;
  const std::vector<std::int64_t>& d = *keys.dim_size;
  h.data_bytes = volumeBytes({d[0], d[1], d[2]}, h.type, path);
  for (int a = 0; a < 3; ++a) h.dims[a] = static_cast<int>(d[a]);
  const std::vector<double> spacing =
      keys.spacing.value_or(keys.element_size.value_or(std::vector<double>{1, 1, 1}));
  h.spacing = {spacing[0], spacing[1], spacing[2]};
  h.endian = bytesPerVoxel(h.type) == 1 ? nativeEndian()
             : keys.msb.value_or(false) ? Endian::kBig
                                        : Endian::kLittle;
  h.encoding = keys.compressed.value_or(false) ? "zlib" : "raw";
  h.comments = keys.comments;

  const std::string& file = *keys.element_data_file;
  const std::vector<std::string> file_words = splitWhitespace(file);
  if (file_words.empty()) throw Error(fmt::format("{}: ElementDataFile is empty", path));
  if (toLower(file) == "local") {
    h.data_file = path;
    source.offset = keys.data_offset;
  } else {
    if (file.find('%') != std::string::npos || toLower(file_words[0]) == "list")
      throw Error(
          fmt::format("{}: ElementDataFile = '{}' names several files; svr reads one "
                      "data file per volume",
                      path, file));
    h.data_file = resolveDataFile(path, file, "ElementDataFile");
  }
  const std::int64_t header_size = keys.header_size.value_or(0);
  if (header_size == -1) {
    // -1: the voxels are the last data_bytes of the file, whatever precedes them.
    if (h.encoding != "raw")
      throw Error(
          fmt::format("{}: HeaderSize = -1 cannot be used with CompressedData = True", path));
    const std::uint64_t size = fileSize(h.data_file, path);
    source.offset = size >= h.data_bytes ? size - h.data_bytes : 0;
  } else {
    source.offset += static_cast<std::uint64_t>(header_size);
  }
  if (h.encoding == "zlib") {
    const std::uint64_t size = fileSize(h.data_file, path);
    const std::uint64_t held = size > source.offset ? size - source.offset : 0;
    if (keys.compressed_size && *keys.compressed_size > held)
      throw Error(
          fmt::format("{}: CompressedDataSize = {} but the data file '{}' holds {} "
                      "bytes",
                      path, *keys.compressed_size, h.data_file, held));
    source.compressed_bytes = keys.compressed_size.value_or(held);
  }
  return source;
}

}  // namespace svr::detail
