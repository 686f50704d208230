#include "renderers/volume/volume_description.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>

#include "renderers/volume/memory_budget.h"

namespace svr {

namespace {

constexpr int kBins = 16;
constexpr int kBarWidth = 40;

// Shortest round-trip form: "1", "3.2", "0.015625".
std::string number(double v) { return fmt::format("{}", v); }

std::string triple(const glm::dvec3& v) {
  return fmt::format("{} × {} × {}", number(v.x), number(v.y), number(v.z));
}

// 16 equal bins over [lo, hi]; bar lengths grow with log(1 + count) so sparse tails (bone in a
// CT, small labels) stay visible beside a background bin holding most voxels.
std::string histogram(const Volume& volume) {
  const auto [lo, hi] = volume.valueRange();
  std::array<std::uint64_t, kBins> counts{};
  const double width = (hi - lo) / kBins;
  const std::size_t n = volume.voxelCount();
  for (std::size_t i = 0; i < n; ++i) {
    const double v = volume.value(i);
    const int bin = width > 0 ? std::min(kBins - 1, static_cast<int>((v - lo) / width)) : 0;
    ++counts[static_cast<std::size_t>(bin)];
  }
  const std::uint64_t most = *std::max_element(counts.begin(), counts.end());
  const double log_most = std::log1p(static_cast<double>(most));
  const int bins = width > 0 ? kBins : 1;
  std::string out =
      fmt::format("  histogram   {} bins over [{}, {}], bar length ∝ log(1 + count)\n", bins,
                  number(lo), number(hi));
  for (int b = 0; b < bins; ++b) {
    const double from = lo + b * width, to = b + 1 == bins ? hi : lo + (b + 1) * width;
    const int bar =
        counts[b] == 0
            ? 0
            : std::max(1, static_cast<int>(std::lround(
                              kBarWidth * std::log1p(static_cast<double>(counts[b])) / log_most)));
    out += fmt::format("    [{:>10.6g}, {:>10.6g}{}  {:<{}} {:>11}\n", from, to,
                       b + 1 == bins ? ']' : ')', std::string(static_cast<std::size_t>(bar), '#'),
                       kBarWidth, counts[b]);
  }
  return out;
}

}  // namespace

std::string describeVolume(const VolumeHeader& header, const Volume& volume) {
  const Dims& d = volume.dims();
  const std::size_t width = bytesPerVoxel(volume.type());
  const auto [lo, hi] = volume.valueRange();
  std::string out = fmt::format("{}\n", header.path);
  const std::string where = std::filesystem::is_directory(header.path)
                                ? "voxels in the folder's files"
                            : header.data_file == header.path
                                ? "voxels in the same file"
                                : fmt::format("voxels in {}", header.data_file);
  out += fmt::format("  format      {}, {}\n", header.format, where);
  out += fmt::format("  dims        {} × {} × {}  ({} voxels)\n", d[0], d[1], d[2],
                     volume.voxelCount());
  out += fmt::format("  type        {}, {}\n", toString(volume.type()),
                     width == 1 ? "one byte per voxel (no byte order)"
                                : fmt::format("{}-endian in the file", toString(header.endian)));
  out += fmt::format("  encoding    {}\n", header.encoding);
  if (!header.values.empty()) out += fmt::format("  values      {}\n", header.values);
  if (!header.orientation.empty()) out += fmt::format("  orientation {}\n", header.orientation);
  out += fmt::format("  spacing     {}\n", triple(volume.spacing()));
  const glm::dvec3 half = 0.5 * volume.extent();
  out += fmt::format("  extent      {} world units, from ({}, {}, {}) to ({}, {}, {})\n",
                     triple(volume.extent()), number(-half.x), number(-half.y), number(-half.z),
                     number(half.x), number(half.y), number(half.z));
  out += fmt::format("  range       {} … {}\n", number(lo), number(hi));
  out += fmt::format("  memory      {} as stored, {} as float32 for rendering\n",
                     formatBytes(volume.bytes()), formatBytes(volume.voxelCount() * 4));
  out += histogram(volume);
  if (!header.comments.empty()) {
    out += "  comments\n";
    for (const std::string& c : header.comments) out += fmt::format("    {}\n", c);
  }
  return out;
}

}  // namespace svr
