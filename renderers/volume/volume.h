#pragma once
// A regular grid of scalars (design.md §7): x fastest, then y, then z; world position of voxel
// (i, j, k) = ((i, j, k) − (dims − 1)/2) ⊙ spacing, so the volume is centred at the origin.
// Voxels keep their original type and values, so a transfer function's domain is in data units.
// Label maps are volumes too; the scene says when values are labels.

#include <array>
#include <cstddef>
#include <cstdint>
#include <glm/vec3.hpp>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "renderers/volume/brick_box.h"

namespace svr {

enum class ScalarType { kUint8, kInt8, kUint16, kInt16, kUint32, kInt32, kFloat32, kFloat64 };
std::string toString(ScalarType type);
// "uint8", "int16", "float32", … (also NRRD's and MetaImage's spellings); throws svr::Error.
ScalarType parseScalarType(const std::string& text);
std::size_t bytesPerVoxel(ScalarType type);

enum class Endian { kLittle, kBig };
std::string toString(Endian endian);
Endian nativeEndian();

// Loops over fewer voxels than this run on one thread: a parallel region costs a fork and a
// join, and on a machine busy with other work (a build beside the renderer) a join can wait a
// whole scheduler slice for a descheduled thread — more than the few milliseconds the loop
// takes alone.
inline constexpr std::int64_t kParallelVoxels = std::int64_t{1} << 22;

class Volume {
 public:
  Volume() = default;
  // data: dims product × bytesPerVoxel(type) bytes in native byte order. Throws svr::Error
  // (naming `source`) for non-positive dims, a size mismatch, a spacing that is not finite and
  // positive, or a non-finite float voxel.
  Volume(Dims dims, glm::dvec3 spacing, ScalarType type, std::vector<std::byte> data,
         std::string source);
  // A float32 volume from values (procedural volumes, tests).
  static Volume fromValues(Dims dims, glm::dvec3 spacing, const std::vector<float>& values,
                           std::string source);

  const Dims& dims() const { return dims_; }
  const glm::dvec3& spacing() const { return spacing_; }
  ScalarType type() const { return type_; }
  const std::string& source() const { return source_; }
  std::size_t voxelCount() const {
    return static_cast<std::size_t>(dims_[0]) * dims_[1] * dims_[2];
  }
  std::size_t bytes() const { return data_->size(); }
  const std::vector<std::byte>& data() const { return *data_; }

  // Value of one voxel in data units.
  double value(int x, int y, int z) const { return value(index(x, y, z)); }
  double value(std::size_t linear_index) const;
  std::size_t index(int x, int y, int z) const {
    return (static_cast<std::size_t>(z) * dims_[1] + y) * dims_[0] + x;
  }
  // Smallest and largest voxel value (of the whole volume, for a brick that knows it).
  std::pair<double, double> valueRange() const {
    return brick_ && brick_->whole_range ? *brick_->whole_range : range_;
  }
  // World-space size of the sampled box: spacing ⊙ (dims − 1), of the whole grid for a brick.
  glm::dvec3 extent() const;

  // A distributed render's brick: this volume holds brick.stored of a larger grid (the voxels'
  // own range, before the whole volume's is known, is localRange()).
  const std::optional<VolumeBrick>& brick() const { return brick_; }
  void setBrick(VolumeBrick brick) { brick_ = std::move(brick); }
  std::pair<double, double> localRange() const { return range_; }
  glm::dvec3 worldPosition(double x, double y, double z) const;

  // Every voxel as float, x fastest (what the renderers sample).
  std::vector<float> toFloat() const;

 private:
  Dims dims_{0, 0, 0};
  glm::dvec3 spacing_{1.0};
  ScalarType type_ = ScalarType::kFloat32;
  // Shared, never changed after construction: copies of a volume (a scene copied per render,
  // the Python module's renders of one scene) share its voxels instead of copying them.
  std::shared_ptr<const std::vector<std::byte>> data_ =
      std::make_shared<const std::vector<std::byte>>();
  std::string source_;
  std::pair<double, double> range_{0.0, 0.0};
  std::optional<VolumeBrick> brick_;
};

}  // namespace svr
