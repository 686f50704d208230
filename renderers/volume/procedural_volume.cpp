#include "renderers/volume/procedural_volume.h"

#include <fmt/format.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>

#include "renderers/volume/memory_budget.h"
#include "base/error.h"

namespace svr {

namespace {

constexpr double kPi = std::numbers::pi;

// Samples f at every voxel centre, x fastest. The centre is Volume::worldPosition's
// (index − (dims − 1)/2) ⊙ spacing; a test checks the two agree.
template <typename F>
Volume sample(Dims dims, glm::dvec3 spacing, const std::string& name, F f) {
  const std::uint64_t bytes =
      volumeBytes({dims[0], dims[1], dims[2]}, ScalarType::kFloat32, name);  // dims ≥ 1
  const glm::dvec3 centre = 0.5 * glm::dvec3(dims[0] - 1, dims[1] - 1, dims[2] - 1);
  // Straight into the Volume's bytes: a float vector copied over would double the peak memory.
  std::vector<std::byte> data(bytes);
  std::size_t at = 0;
  for (int z = 0; z < dims[2]; ++z)
    for (int y = 0; y < dims[1]; ++y)
      for (int x = 0; x < dims[0]; ++x, at += sizeof(float)) {
        const auto value = static_cast<float>(f((glm::dvec3(x, y, z) - centre) * spacing));
        std::memcpy(data.data() + at, &value, sizeof(float));
      }
  return Volume(dims, spacing, ScalarType::kFloat32, std::move(data), name);
}

}  // namespace

double marschnerLobb(glm::dvec3 p) {
  const double r = std::hypot(p.x, p.y);
  const double rho_r = std::cos(2 * kPi * kMarschnerLobbFM * std::cos(kPi * r / 2));
  return (1 - std::sin(kPi * p.z / 2) + kMarschnerLobbAlpha * (1 + rho_r)) /
         (2 * (1 + kMarschnerLobbAlpha));
}

glm::dvec3 marschnerLobbGradient(glm::dvec3 p) {
  const double scale = 1 / (2 * (1 + kMarschnerLobbAlpha));
  const double r = std::hypot(p.x, p.y);
  // dρr/dr = π² fM sin(2π fM cos(πr/2)) sin(πr/2); ∂r/∂x = x/r. sin(πr/2)/r → π/2 as r → 0,
  // which keeps the gradient finite (and zero) on the axis.
  const double sin_over_r = r > 1e-12 ? std::sin(kPi * r / 2) / r : kPi / 2;
  const double radial = kPi * kPi * kMarschnerLobbFM *
                        std::sin(2 * kPi * kMarschnerLobbFM * std::cos(kPi * r / 2)) * sin_over_r;
  return scale * glm::dvec3(kMarschnerLobbAlpha * radial * p.x, kMarschnerLobbAlpha * radial * p.y,
                            -(kPi / 2) * std::cos(kPi * p.z / 2));
}

Volume marschnerLobbVolume(int n) {
  if (n < 2)
    throw Error(fmt::format("Marschner-Lobb volume: n is {}; it needs n ≥ 2 samples per axis", n));
  const double h = 2.0 / (n - 1);
  return sample({n, n, n}, glm::dvec3(h), fmt::format("marschner-lobb {}³", n), marschnerLobb);
}

Volume slabVolume(Dims dims, glm::dvec3 spacing, double thickness) {
  return sample(dims, spacing, fmt::format("slab thickness {}", thickness),
                [&](glm::dvec3 p) { return std::abs(p.z) <= thickness / 2 ? 1.0 : 0.0; });
}

double slabChordLength(double thickness, glm::dvec3 direction) {
  if (direction.z == 0) return std::numeric_limits<double>::infinity();
  return thickness *
         std::sqrt(direction.x * direction.x + direction.y * direction.y +
                   direction.z * direction.z) /
         std::abs(direction.z);
}

Volume boxVolume(Dims dims, glm::dvec3 spacing, glm::dvec3 half_size) {
  return sample(dims, spacing, "box", [&](glm::dvec3 p) {
    return std::abs(p.x) <= half_size.x && std::abs(p.y) <= half_size.y &&
                   std::abs(p.z) <= half_size.z
               ? 1.0
               : 0.0;
  });
}

double boxChordLength(glm::dvec3 half_size, glm::dvec3 origin, glm::dvec3 direction) {
  // Slab method: intersect the parameter intervals of the three axis slabs.
  double t0 = -std::numeric_limits<double>::infinity();
  double t1 = std::numeric_limits<double>::infinity();
  for (int a = 0; a < 3; ++a) {
    if (direction[a] == 0) {
      if (std::abs(origin[a]) > half_size[a]) return 0;
      continue;
    }
    double ta = (-half_size[a] - origin[a]) / direction[a];
    double tb = (half_size[a] - origin[a]) / direction[a];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  if (t1 <= t0) return 0;
  const double length =
      std::sqrt(direction.x * direction.x + direction.y * direction.y + direction.z * direction.z);
  return (t1 - t0) * length;
}

Volume sphereVolume(Dims dims, glm::dvec3 spacing, double radius) {
  return sample(dims, spacing, fmt::format("sphere radius {}", radius), [&](glm::dvec3 p) {
    return p.x * p.x + p.y * p.y + p.z * p.z <= radius * radius ? 1.0 : 0.0;
  });
}

double sphereChordLength(double radius, double b) {
  const double b2 = b * b, r2 = radius * radius;
  return b2 < r2 ? 2 * std::sqrt(r2 - b2) : 0.0;
}

int nestedShellIndex(const std::vector<double>& radii, double r) {
  for (std::size_t i = 0; i < radii.size(); ++i)
    if (r <= radii[i]) return static_cast<int>(i) + 1;
  return 0;
}

Volume nestedShellsVolume(Dims dims, glm::dvec3 spacing, const std::vector<double>& radii) {
  if (radii.empty()) throw Error("nested shells: no radii");
  for (std::size_t i = 0; i < radii.size(); ++i)
    if (!std::isfinite(radii[i]) || radii[i] <= (i ? radii[i - 1] : 0.0))
      throw Error(
          fmt::format("nested shells: radius {} is {}; radii must be finite, > 0 and "
                      "strictly increasing",
                      i, radii[i]));
  return sample(dims, spacing, fmt::format("{} nested shells", radii.size()), [&](glm::dvec3 p) {
    return static_cast<double>(
        nestedShellIndex(radii, std::sqrt(p.x * p.x + p.y * p.y + p.z * p.z)));
  });
}

double shellChordLength(double inner, double outer, double b) {
  return sphereChordLength(outer, b) - sphereChordLength(inner, b);
}

double nestedShellsLineIntegral(const std::vector<double>& radii, double b) {
  double sum = 0;
  for (std::size_t i = 0; i < radii.size(); ++i)
    sum += static_cast<double>(i + 1) * shellChordLength(i ? radii[i - 1] : 0.0, radii[i], b);
  return sum;
}

int phantomLabel(glm::dvec3 p) {
  const auto in_ball = [&](glm::dvec3 c, double r) {
    const glm::dvec3 d = p - c;
    return d.x * d.x + d.y * d.y + d.z * d.z <= r * r;
  };
  if (in_ball({0, 12, 10}, 4)) return 4;
  if (in_ball({12, 0, 0}, 8)) return 3;
  if (std::abs(p.x + 12) <= 6 && std::abs(p.y) <= 6 && std::abs(p.z) <= 14) return 2;
  if (in_ball({0, 0, 0}, 28)) return 1;
  return 0;
}

Volume phantomVolume() {
  return sample({kPhantomSize, kPhantomSize, kPhantomSize}, glm::dvec3(1.0), "phantom 64³",
                [](glm::dvec3 p) { return static_cast<double>(phantomLabel(p)); });
}

}  // namespace svr
