#include "renderers/splat/splat_list.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <utility>

#include "renderers/classification/classified_sample.h"
#include "renderers/kernels/splat_projection.h"
#include "renderers/splat/splat_coverage.h"
#include "base/error.h"

namespace svr::splat {

namespace {

// The shade of every listed voxel, in list (voxel index) order: the mean of the Phong terms at
// the cell's 8 corners — the raycaster's Phong at the dual-grid nodes — not the shade at its
// centre (near a boundary those differ, and the centre alone is too bright). The list is cut into
// runs of whole z-slices. Under an orthographic camera every node has one Phong value per frame,
// and a run keeps the values of its two current node planes (slot z & 1, stamped with z), so a
// node shared by up to 8 voxels is shaded once per run; in index order the cell means are read
// nearly in sequence. A perspective camera's view direction differs per voxel, and each voxel
// shades its own corners.
void shadeVoxels(const SplatVoxels& sv, const ClassifiedVolume& cv, const RenderRequest& req,
                 const Projector& projector, bool any_specular, std::span<Splat> out) {
  const auto voxels = sv.voxels();
  const Dims& d = cv.dims;
  const bool ortho = projector.orthographic();
  const auto setupAt = [&](std::uint32_t index) {
    const glm::dvec3 view = projector.towardsEye(voxelWorld(cv, index));
    const glm::dvec3 light = req.light_direction ? *req.light_direction : view;
    PhongSetup setup(req.shading, light, glm::normalize(light + view));
    if (!any_specular) setup.specular = 0.f;
    return setup;
  };
  constexpr int kSlicesPerRun = 8;
  const int runs = (d[2] + kSlicesPerRun - 1) / kSlicesPerRun;
  const std::size_t plane = static_cast<std::size_t>(d[0] + 1) * (d[1] + 1);
  const std::size_t slice = static_cast<std::size_t>(d[0]) * d[1];
  const auto firstAtOrAfter = [&](int z) {
    return static_cast<std::size_t>(
        std::lower_bound(voxels.begin(), voxels.end(), slice * z,
                         [](const SplatVoxel& v, std::size_t i) { return v.index < i; }) -
        voxels.begin());
  };
#pragma omp parallel
  {
    std::vector<PhongTerms> node_terms(ortho ? 2 * plane : 0);
    std::vector<int> stamp(ortho ? 2 * plane : 0);
#pragma omp for schedule(dynamic)
    for (int run = 0; run < runs; ++run) {
      std::fill(stamp.begin(), stamp.end(), -1);
      PhongSetup setup = setupAt(0);
      const std::size_t end = firstAtOrAfter(std::min(d[2], (run + 1) * kSlicesPerRun));
      // The corners' terms, c = x + 2y + 4z; the previous voxel's, where it is this one's left
      // neighbour in the row, give this one's left face (an orthographic camera's terms are
      // the node's alone).
      PhongTerms terms[8];
      std::uint32_t previous = 0;
      int x = 0, y = 0, z = 0;
      const std::size_t first = firstAtOrAfter(run * kSlicesPerRun);
      for (std::size_t i = first; i < end; ++i) {
        const std::uint32_t index = voxels[i].index;
        const bool follows = ortho && i != first && index == previous + 1 && x + 1 < d[0];
        previous = index;
        if (follows) {
          ++x;
          for (int c = 0; c < 8; c += 2) terms[c] = terms[c + 1];
        } else {
          x = static_cast<int>(index % d[0]);
          y = static_cast<int>(index / d[0] % d[1]);
          z = static_cast<int>(index / slice);
        }
        if (!ortho) setup = setupAt(index);
        for (int c = follows ? 1 : 0; c < 8; c += follows ? 2 : 1) {
          const int nx = x + (c & 1), ny = y + ((c >> 1) & 1), nz = z + ((c >> 2) & 1);
          PhongTerms& t = terms[c];
          const std::size_t at = (nz & 1) * plane + static_cast<std::size_t>(ny) * (d[0] + 1) + nx;
          if (ortho && stamp[at] == nz) {
            t = node_terms[at];
          } else {
            float g[3];
            sv.gradientAtNode(nx, ny, nz, g);
            t = phong(setup, g);
            if (ortho) {
              node_terms[at] = t;
              stamp[at] = nz;
            }
          }
        }
        float shade = 0.f, highlight = 0.f;
        for (int c = 0; c < 8; ++c) {
          shade += terms[c].shade;
          highlight += terms[c].highlight;
        }
        out[i].shade = shade * 0.125f;
        out[i].highlight = highlight * 0.125f;
      }
    }
  }
}

}  // namespace

SplatList::SplatList(const ClassifiedVolume& cv, const RenderRequest& req,
                     const Projector& projector, SplatVoxels::Set set, SplatListMemory& memory)
    : cv_(cv),
      voxels_(SplatVoxels::of(cv, set)),
      k_(cv.k),
      kt_(cv.t_channels),
      splats_(memory.splats),
      footprints_(memory.footprints) {
  row_stride_ = (2 + k_ + kt_ + 3) / 4 * 4;
  if (row_stride_ > kMaxRowStride)
    throw Error(fmt::format("splat: {} + {} channels are more than the {} a splat's blend holds",
                            k_, kt_, kMaxSplatChannels));
  rows_ = blendRows(cv, voxels_->sigmaAlpha().data(), voxels_->sigmaT().data(), row_stride_);
  VoxelProjection& projected = memory.projection;
  projectInListOrder(*voxels_, cv, projector, req.width, req.height, projected);
  const auto voxels = voxels_->voxels();
  const bool any_specular = req.shading.specular > 0.0 &&
                            std::any_of(cv.specular.begin(), cv.specular.end(),
                                        [](float s) { return s > 0.f; });
  // Each voxel's splat in list order, written in sequence; then one gather into depth order,
  // one record a splat, where gathering each of its parts read four places at random.
  std::vector<Splat>& in_list_order = memory.in_list_order;
  in_list_order.resize(voxels.size());
  shadeVoxels(*voxels_, cv, req, projector, any_specular, in_list_order);
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < voxels.size(); ++i) {
    Splat& s = in_list_order[i];
    s.x = projected.position[i].x;
    s.y = projected.position[i].y;
    s.depth = projected.depth[i];
    s.entry = voxels[i].entry;
    s.frac = voxels[i].frac;
  }
  const std::size_t n = projected.order.size();
  const bool ortho = projector.orthographic();
  splats_.resize(n);
  footprints_.resize(ortho ? 1 : n);
  if (ortho) footprints_[0] = projected.footprints[0];
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t id = projected.order[i];
    splats_[i] = in_list_order[id];
    if (!ortho) footprints_[i] = projected.footprints[id];
  }
  orthographic_ = ortho;
  for (const Footprint& fp : footprints_) max_depth_sigma_ = std::max(max_depth_sigma_, fp.depth_sigma);
}

}  // namespace svr::splat

namespace svr::splat {

void bandsOf(const SplatCoverage& coverage, int rows, Bands& bands) {
  bands.rows = rows;
  bands.count = (coverage.height() + rows - 1) / rows;
  const auto splats = coverage.list().splats();
  // The band range of each splat, from the rows its box reaches (an empty box none): computed
  // once, for both passes.
  std::vector<std::int32_t>&first_band = bands.first, &last_band = bands.last;
  first_band.resize(splats.size());
  last_band.resize(splats.size());
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < splats.size(); ++i) {
    const SplatCoverage::Box box = coverage.box(i);
    const bool empty = box.xa > box.xb || box.ya > box.yb;
    first_band[i] = empty ? 0 : box.ya / rows;
    last_band[i] = empty ? -1 : box.yb / rows;
  }
  const auto range = [&](std::size_t i, int& b0, int& b1) {
    b0 = first_band[i];
    b1 = last_band[i];
  };
  // Counting sort by band, in splat order, so each band's list stays front to back: over fixed
  // chunks of splats, each counting its own, the offsets band by band and within a band chunk
  // by chunk.
  const FixedChunks chunks(splats.size());
  const std::size_t nb = static_cast<std::size_t>(bands.count);
  std::vector<std::size_t> offset(chunks.count * nb, 0);
#pragma omp parallel for schedule(static)
  for (std::size_t c = 0; c < chunks.count; ++c)
    for (std::size_t i = chunks.begin(c); i < chunks.end(c); ++i) {
      int b0, b1;
      range(i, b0, b1);
      for (int b = b0; b <= b1; ++b) ++offset[c * nb + b];
    }
  bands.offsets.assign(nb + 1, 0);
  std::size_t sum = 0;
  for (std::size_t b = 0; b < nb; ++b) {
    bands.offsets[b] = sum;
    for (std::size_t c = 0; c < chunks.count; ++c) {
      const std::size_t count = offset[c * nb + b];
      offset[c * nb + b] = sum;
      sum += count;
    }
  }
  bands.offsets[nb] = sum;
  bands.splats.resize(sum);
#pragma omp parallel for schedule(static)
  for (std::size_t c = 0; c < chunks.count; ++c)
    for (std::size_t i = chunks.begin(c); i < chunks.end(c); ++i) {
      int b0, b1;
      range(i, b0, b1);
      for (int b = b0; b <= b1; ++b)
        bands.splats[offset[c * nb + b]++] = static_cast<std::uint32_t>(i);
    }
}

}  // namespace svr::splat
