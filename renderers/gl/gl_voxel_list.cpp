#include "renderers/gl/gl_voxel_list.h"

#include <algorithm>
#include <utility>

namespace svr::gl {

GlVoxelList::GlVoxelList(const ClassifiedVolume& cv,
                         std::shared_ptr<const splat::SplatVoxels> splat)
    : splat_voxels(std::move(splat)) {
  const std::size_t E = cv.entries;
  const int k = cv.k, kt = cv.t_channels;
  tables.assign(E * (2 + kt + k) + k, 0.f);
  std::ranges::copy(splat_voxels->sigmaAlpha(), tables.begin());
  std::ranges::copy(splat_voxels->sigmaT(), tables.begin() + E);
  std::ranges::copy(cv.reflectance, tables.begin() + E * (1 + kt));
  std::ranges::copy(cv.specular, tables.begin() + E * (1 + kt + k));
  std::ranges::copy(cv.white, tables.begin() + E * (2 + kt + k));

  const Dims& d = cv.dims;
  const auto list = splat_voxels->voxels();
  voxels.resize(list.size());
#pragma omp parallel for schedule(static)
  for (std::size_t v = 0; v < list.size(); ++v) {
    const std::uint32_t index = list[v].index;
    const int x = static_cast<int>(index % d[0]), y = static_cast<int>(index / d[0] % d[1]),
              z = static_cast<int>(index / d[0] / d[1]);
    voxels[v] = {static_cast<float>((x - 0.5 * (d[0] - 1)) * cv.spacing.x),
                 static_cast<float>((y - 0.5 * (d[1] - 1)) * cv.spacing.y),
                 static_cast<float>((z - 0.5 * (d[2] - 1)) * cv.spacing.z),
                 list[v].frac,
                 x,
                 y,
                 z,
                 list[v].entry};
  }
}

std::shared_ptr<const GlVoxelList> GlVoxelList::of(const ClassifiedVolume& cv) {
  // Outside the cache's build below: the cache holds its lock while building.
  auto splat_voxels = splat::SplatVoxels::of(cv);
  return cv.derived->get<GlVoxelList>("gl.voxels", [&] {
    return std::make_shared<const GlVoxelList>(cv, std::move(splat_voxels));
  });
}

}  // namespace svr::gl
