#include "volume_test_files.h"

#include <gtest/gtest.h>
#include <openssl/evp.h>
#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <stdexcept>

#include "base/error.h"

namespace svr::test {

namespace fs = std::filesystem;

TempDir::TempDir() {
  static std::atomic<int> counter{0};
  const ::testing::TestInfo* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string name = info ? std::string(info->test_suite_name()) + "_" + info->name() : "t";
  std::replace(name.begin(), name.end(), '/', '_');
  dir_ = fs::temp_directory_path() /
         ("svr_test_" + std::to_string(::getpid()) + "_" + std::to_string(counter++) + "_" + name);
  fs::create_directories(dir_);
}

TempDir::~TempDir() {
  std::error_code ec;
  fs::remove_all(dir_, ec);
}

void writeFile(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  if (!out) throw std::runtime_error("cannot write " + path);
}

void writeFile(const std::string& path, const std::vector<std::byte>& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(bytes.data()),
            static_cast<std::streamsize>(bytes.size()));
  if (!out) throw std::runtime_error("cannot write " + path);
}

std::vector<std::byte> readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  return bytesOf(text);
}

std::vector<std::byte> bytesOf(const std::string& text) {
  std::vector<std::byte> bytes(text.size());
  std::memcpy(bytes.data(), text.data(), text.size());
  return bytes;
}

namespace {

std::vector<std::byte> deflateWith(const std::vector<std::byte>& bytes, int window_bits) {
  z_stream zs{};
  if (deflateInit2(&zs, 9, Z_DEFLATED, window_bits, 8, Z_DEFAULT_STRATEGY) != Z_OK)
    throw std::runtime_error("deflateInit2");
  std::vector<std::byte> out(deflateBound(&zs, bytes.size()) + 32);
  zs.next_in = reinterpret_cast<Bytef*>(const_cast<std::byte*>(bytes.data()));
  zs.avail_in = static_cast<uInt>(bytes.size());
  zs.next_out = reinterpret_cast<Bytef*>(out.data());
  zs.avail_out = static_cast<uInt>(out.size());
  const int code = deflate(&zs, Z_FINISH);
  deflateEnd(&zs);
  if (code != Z_STREAM_END) throw std::runtime_error("deflate");
  out.resize(zs.total_out);
  return out;
}

}  // namespace

std::vector<std::byte> gzipCompress(const std::vector<std::byte>& bytes) {
  return deflateWith(bytes, 15 + 16);
}

std::vector<std::byte> zlibCompress(const std::vector<std::byte>& bytes) {
  return deflateWith(bytes, 15);
}

std::vector<std::byte> gunzipFile(const std::string& path) {
  gzFile file = gzopen(path.c_str(), "rb");
  if (!file) throw std::runtime_error("cannot open " + path);
  std::vector<std::byte> out;
  std::vector<std::byte> chunk(1 << 20);
  int got = 0;
  while ((got = gzread(file, chunk.data(), static_cast<unsigned>(chunk.size()))) > 0)
    out.insert(out.end(), chunk.begin(), chunk.begin() + got);
  gzclose(file);
  return out;
}

std::string sha256Hex(const std::vector<std::byte>& bytes) {
  unsigned char digest[EVP_MAX_MD_SIZE];
  unsigned int length = 0;
  if (EVP_Digest(bytes.data(), bytes.size(), digest, &length, EVP_sha256(), nullptr) != 1)
    throw std::runtime_error("EVP_Digest");
  std::string hex;
  for (unsigned i = 0; i < length; ++i) {
    static constexpr char kDigits[] = "0123456789abcdef";
    hex += kDigits[digest[i] >> 4];
    hex += kDigits[digest[i] & 15];
  }
  return hex;
}

std::vector<double> knownValues(ScalarType type, std::size_t count) {
  std::vector<double> values(count);
  const auto spread = [&](double lo, double hi) {
    // Integer steps from lo to hi, both ends included.
    for (std::size_t i = 0; i < count; ++i)
      values[i] = i + 1 == count ? hi
                                 : lo + std::floor((hi - lo) * static_cast<double>(i) /
                                                   static_cast<double>(count - 1));
  };
  switch (type) {
    case ScalarType::kUint8:
      spread(0, 255);
      break;
    case ScalarType::kInt8:
      spread(-128, 127);
      break;
    case ScalarType::kUint16:
      spread(0, 65535);
      break;
    case ScalarType::kInt16:
      spread(-32768, 32767);
      break;
    case ScalarType::kUint32:
      spread(0, 4294967295.0);
      break;
    case ScalarType::kInt32:
      spread(-2147483648.0, 2147483647.0);
      break;
    case ScalarType::kFloat32:
      for (std::size_t i = 0; i < count; ++i)
        values[i] = static_cast<float>((static_cast<double>(i) - 30.0) * 1250.375);
      break;
    case ScalarType::kFloat64:
      for (std::size_t i = 0; i < count; ++i)
        values[i] = (static_cast<double>(i) - 30.0) * 123456.789012345678;
      break;
  }
  return values;
}

std::vector<std::byte> encodeValues(const std::vector<double>& values, ScalarType type,
                                    Endian endian) {
  const std::size_t width = bytesPerVoxel(type);
  std::vector<std::byte> bytes(values.size() * width);
  for (std::size_t i = 0; i < values.size(); ++i) {
    std::byte* p = bytes.data() + i * width;
    const auto put = [&](auto v) { std::memcpy(p, &v, sizeof v); };
    switch (type) {
      case ScalarType::kUint8:
        put(static_cast<std::uint8_t>(values[i]));
        break;
      case ScalarType::kInt8:
        put(static_cast<std::int8_t>(values[i]));
        break;
      case ScalarType::kUint16:
        put(static_cast<std::uint16_t>(values[i]));
        break;
      case ScalarType::kInt16:
        put(static_cast<std::int16_t>(values[i]));
        break;
      case ScalarType::kUint32:
        put(static_cast<std::uint32_t>(values[i]));
        break;
      case ScalarType::kInt32:
        put(static_cast<std::int32_t>(values[i]));
        break;
      case ScalarType::kFloat32:
        put(static_cast<float>(values[i]));
        break;
      case ScalarType::kFloat64:
        put(values[i]);
        break;
    }
    if (endian != nativeEndian()) std::reverse(p, p + width);
  }
  return bytes;
}

std::string nrrdTypeName(ScalarType type) {
  switch (type) {
    case ScalarType::kUint8:
      return "uchar";
    case ScalarType::kInt8:
      return "signed char";
    case ScalarType::kUint16:
      return "ushort";
    case ScalarType::kInt16:
      return "short";
    case ScalarType::kUint32:
      return "uint";
    case ScalarType::kInt32:
      return "int";
    case ScalarType::kFloat32:
      return "float";
    case ScalarType::kFloat64:
      return "double";
  }
  return "?";
}

std::string metaTypeName(ScalarType type) {
  switch (type) {
    case ScalarType::kUint8:
      return "MET_UCHAR";
    case ScalarType::kInt8:
      return "MET_CHAR";
    case ScalarType::kUint16:
      return "MET_USHORT";
    case ScalarType::kInt16:
      return "MET_SHORT";
    case ScalarType::kUint32:
      return "MET_UINT";
    case ScalarType::kInt32:
      return "MET_INT";
    case ScalarType::kFloat32:
      return "MET_FLOAT";
    case ScalarType::kFloat64:
      return "MET_DOUBLE";
  }
  return "?";
}

std::string errorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  ADD_FAILURE() << "no svr::Error thrown";
  return "";
}

}  // namespace svr::test
