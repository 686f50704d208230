#pragma once
// The raycaster's inner loops as the renderer sees them: one tile job, and per instruction set
// the kernel for a channel count, transmittance and gradient source (raycast_kernel.h holds
// the loop; raycast_kernel_portable.cpp and raycast_kernel_avx2.cpp compile it).

#include "renderers/classification/classification.h"
#include "renderers/kernels/gradient_volume.h"
#include "renderers/kernels/occupancy_pyramid.h"
#include "renderers/render/renderer.h"
#include "renderers/raycast/sample_table.h"

namespace svr::raycast {

inline constexpr int kMaxChannels = 128;

struct TileJob {
  const ClassifiedVolume* volume;
  const GradientVolume* gradients;  // null: on-the-fly gradients
  const SampleTable* table;
  const OccupancyPyramid* occupancy;
  const RayGenerator* rays;
  const RenderRequest* request;
  LightIndependentImage* image;
  int x0, y0, x1, y1;
  // A brick's front transmittance over the block holding this tile (FrontTransmittance's
  // layout: planes of kBlock², pitch kBlock, from pixel front_x0, front_y0); null: none.
  const float* front = nullptr;
  int front_x0 = 0, front_y0 = 0;
};

using TileFn = void (*)(const TileJob&);

// What selects a kernel: channels, transmittance channels, gradient source, and whether to take
// the dynamic-k path even where a fixed width is compiled (tests compare the two).
struct KernelKey {
  int k = 3, t_channels = 1;
  bool precomputed_gradients = true;
  bool dynamic_width = false;
};

namespace portable {
TileFn pick(const KernelKey& key);
}
namespace avx2 {
bool compiled();
TileFn pick(const KernelKey& key);
}

}  // namespace svr::raycast
