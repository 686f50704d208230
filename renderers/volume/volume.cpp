#include "renderers/volume/volume.h"

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <cctype>
#include <cmath>
#include <cstring>

#include "base/error.h"

namespace svr {

std::string toString(ScalarType type) {
  switch (type) {
    case ScalarType::kUint8: return "uint8";
    case ScalarType::kInt8: return "int8";
    case ScalarType::kUint16: return "uint16";
    case ScalarType::kInt16: return "int16";
    case ScalarType::kUint32: return "uint32";
    case ScalarType::kInt32: return "int32";
    case ScalarType::kFloat32: return "float32";
    case ScalarType::kFloat64: return "float64";
  }
  return "?";
}

ScalarType parseScalarType(const std::string& text) {
  std::string t;
  for (char c : text) t += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  // Our names, NRRD's spellings and MetaImage's MET_ names.
  static const std::pair<const char*, ScalarType> names[] = {
      {"uint8", ScalarType::kUint8},     {"uchar", ScalarType::kUint8},
      {"unsigned char", ScalarType::kUint8}, {"uint8_t", ScalarType::kUint8},
      {"met_uchar", ScalarType::kUint8}, {"int8", ScalarType::kInt8},
      {"signed char", ScalarType::kInt8}, {"int8_t", ScalarType::kInt8},
      {"met_char", ScalarType::kInt8},   {"uint16", ScalarType::kUint16},
      {"ushort", ScalarType::kUint16},   {"unsigned short", ScalarType::kUint16},
      {"unsigned short int", ScalarType::kUint16}, {"uint16_t", ScalarType::kUint16},
      {"met_ushort", ScalarType::kUint16}, {"int16", ScalarType::kInt16},
      {"short", ScalarType::kInt16},     {"short int", ScalarType::kInt16},
      {"signed short", ScalarType::kInt16}, {"signed short int", ScalarType::kInt16},
      {"int16_t", ScalarType::kInt16},   {"met_short", ScalarType::kInt16},
      {"uint32", ScalarType::kUint32},   {"uint", ScalarType::kUint32},
      {"unsigned int", ScalarType::kUint32}, {"uint32_t", ScalarType::kUint32},
      {"met_uint", ScalarType::kUint32}, {"int32", ScalarType::kInt32},
      {"int", ScalarType::kInt32},       {"signed int", ScalarType::kInt32},
      {"int32_t", ScalarType::kInt32},   {"met_int", ScalarType::kInt32},
      {"float32", ScalarType::kFloat32}, {"float", ScalarType::kFloat32},
      {"met_float", ScalarType::kFloat32}, {"float64", ScalarType::kFloat64},
      {"double", ScalarType::kFloat64},  {"met_double", ScalarType::kFloat64}};
  for (const auto& [name, type] : names)
    if (t == name) return type;
  throw Error(fmt::format("unsupported voxel type '{}'; expected uint8, int8, uint16, int16, "
                          "uint32, int32, float32 or float64", text));
}

std::size_t bytesPerVoxel(ScalarType type) {
  switch (type) {
    case ScalarType::kUint8:
    case ScalarType::kInt8: return 1;
    case ScalarType::kUint16:
    case ScalarType::kInt16: return 2;
    case ScalarType::kUint32:
    case ScalarType::kInt32:
    case ScalarType::kFloat32: return 4;
    case ScalarType::kFloat64: return 8;
  }
  return 1;
}

std::string toString(Endian endian) { return endian == Endian::kLittle ? "little" : "big"; }

Endian nativeEndian() {
  return std::endian::native == std::endian::little ? Endian::kLittle : Endian::kBig;
}

namespace {

template <typename T>
T load(const std::byte* p) {
  T v;
  std::memcpy(&v, p, sizeof(T));
  return v;
}

double valueAt(ScalarType type, const std::byte* p) {
  switch (type) {
    case ScalarType::kUint8: return load<std::uint8_t>(p);
    case ScalarType::kInt8: return load<std::int8_t>(p);
    case ScalarType::kUint16: return load<std::uint16_t>(p);
    case ScalarType::kInt16: return load<std::int16_t>(p);
    case ScalarType::kUint32: return load<std::uint32_t>(p);
    case ScalarType::kInt32: return load<std::int32_t>(p);
    case ScalarType::kFloat32: return load<float>(p);
    case ScalarType::kFloat64: return load<double>(p);
  }
  return 0.0;
}

}  // namespace

Volume::Volume(Dims dims, glm::dvec3 spacing, ScalarType type, std::vector<std::byte> data,
               std::string source)
    : dims_(dims),
      spacing_(spacing),
      type_(type),
      data_(std::make_shared<const std::vector<std::byte>>(std::move(data))),
      source_(std::move(source)) {
  for (int a = 0; a < 3; ++a)
    if (dims_[a] < 1)
      throw Error(fmt::format("{}: dimension {} is {}; every dimension must be ≥ 1", source_, a,
                              dims_[a]));
  for (int a = 0; a < 3; ++a)
    if (!std::isfinite(spacing_[a]) || spacing_[a] <= 0)
      throw Error(fmt::format("{}: spacing {} is {}; it must be finite and > 0", source_, a,
                              spacing_[a]));
  const std::size_t expect = voxelCount() * bytesPerVoxel(type_);
  if (data_->size() != expect)
    throw Error(fmt::format("{}: {} bytes of voxels, but {}×{}×{} {} needs {}", source_,
                            data_->size(), dims_[0], dims_[1], dims_[2], toString(type_), expect));
  const std::size_t n = voxelCount(), step = bytesPerVoxel(type_);
  const std::byte* bytes = data_->data();
  double lo = INFINITY, hi = -INFINITY;
  for (std::size_t i = 0; i < n; ++i) {
    const double v = valueAt(type_, bytes + i * step);
    if (!std::isfinite(v))
      throw Error(fmt::format("{}: voxel ({}, {}, {}) is {}; voxels must be finite", source_,
                              i % dims_[0], (i / dims_[0]) % dims_[1], i / (std::size_t(dims_[0]) * dims_[1]), v));
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  range_ = {lo, hi};
}

Volume Volume::fromValues(Dims dims, glm::dvec3 spacing, const std::vector<float>& values,
                          std::string source) {
  std::vector<std::byte> bytes(values.size() * sizeof(float));
  std::memcpy(bytes.data(), values.data(), bytes.size());
  return Volume(dims, spacing, ScalarType::kFloat32, std::move(bytes), std::move(source));
}

double Volume::value(std::size_t i) const {
  return valueAt(type_, data_->data() + i * bytesPerVoxel(type_));
}

glm::dvec3 Volume::extent() const {
  const Dims& d = brick_ ? brick_->whole : dims_;
  return spacing_ * glm::dvec3(d[0] - 1, d[1] - 1, d[2] - 1);
}

glm::dvec3 Volume::worldPosition(double x, double y, double z) const {
  const Dims& d = brick_ ? brick_->whole : dims_;
  const glm::dvec3 origin = brick_ ? glm::dvec3(brick_->stored.lo[0], brick_->stored.lo[1],
                                                brick_->stored.lo[2])
                                   : glm::dvec3(0.0);
  return (glm::dvec3(x, y, z) + origin - 0.5 * glm::dvec3(d[0] - 1, d[1] - 1, d[2] - 1)) *
         spacing_;
}

std::vector<float> Volume::toFloat() const {
  std::vector<float> out(voxelCount());
  const std::size_t step = bytesPerVoxel(type_);
  const std::byte* bytes = data_->data();
  const std::int64_t n = static_cast<std::int64_t>(out.size());
#pragma omp parallel for schedule(static) if (n >= kParallelVoxels)
  for (std::int64_t i = 0; i < n; ++i)
    out[i] = static_cast<float>(valueAt(type_, bytes + i * step));
  return out;
}

}  // namespace svr
